"""Volumetric repair (§2.4.2): meshsmith.repair.volumetric_repair."""
from __future__ import annotations

import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, repair, topology
from meshsmith.geometry import SurfaceDistance, volume
from meshsmith.io import read_mesh


def assert_watertight(V, F):
    """Closed, edge- and vertex-manifold, consistently oriented, outward, no self-intersection."""
    directed = np.stack([F, np.roll(F, -1, axis=1)], axis=2).reshape(-1, 2)
    assert len(np.unique(directed, axis=0)) == len(directed), "a directed edge twice: not oriented/manifold"
    reverse = {tuple(e) for e in directed.tolist()}
    assert all((b, a) in reverse for a, b in directed.tolist()), "an edge with one face: not closed"
    assert topology.is_manifold(F)
    assert len(topology.non_manifold_vertices(F)) == 0
    assert topology.is_oriented(F)
    assert volume(V, F) > 0, "inward orientation"
    assert len(repair.self_intersections(V, F)) == 0


def two_cubes():
    """Two overlapping closed cubes in one face list: their surfaces cross each other."""
    VA, FA = datasets.cube(4, 1.0)
    VB, FB = datasets.cube(4, 1.0)
    VB = VB + np.array([0.5, 0.3, 0.2])
    return np.vstack([VA, VB]), np.vstack([FA, FB + len(VA)])


def test_overlapping_cubes_become_their_union():
    V, F = two_cubes()
    assert len(repair.self_intersections(V, F)) > 0
    epsilon = 0.05
    V2, F2, report = repair.volumetric_repair(V, F, epsilon=epsilon)
    assert_watertight(V2, F2)
    diagonal = report.cell_size * np.sqrt(3)
    assert diagonal == pytest.approx(epsilon)
    # Output to input: every output vertex near the input surface.
    d = SurfaceDistance(V, F).distances(V2)
    assert d.max() <= epsilon + diagonal
    # The union's volume: 1 + 1 - 0.5 * 0.7 * 0.8.
    union = 2 - 0.5 * 0.7 * 0.8
    assert volume(V2, F2) == pytest.approx(union, rel=0.02)
    # Sharp corners survive: each corner of the union (a cube corner outside the other cube) has
    # an output vertex on it (all but one or two exactly; the others within half a cell: a
    # vertex moved back towards its grid corner by the untangling).
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    union_corners = [c for c in corners if not np.all((c > np.array([0, -0.2, -0.3])) & (c < [1, 0.8, 0.7]))]
    union_corners += [c + [0.5, 0.3, 0.2] for c in corners if not np.all(np.abs(c + [0.5, 0.3, 0.2]) < 0.5)]
    nearest = np.array([np.linalg.norm(V2 - c, axis=1).min() for c in union_corners])
    assert len(union_corners) == 14
    assert np.sum(nearest < 1e-9) >= 12
    assert nearest.max() < 0.5 * report.cell_size
    assert report.sharp_vertices > 0


def sphere_with_gap_and_hole(gap):
    V, F = datasets.icosphere(4)
    centroid = V[F].mean(axis=1)
    # A hole: the faces of a polar cap removed (radius about 0.17).
    F = F[centroid[:, 2] < 0.985]
    centroid = V[F].mean(axis=1)
    # A gap: the upper half (by face) moved up by `gap`, as its own vertex copy.
    upper = centroid[:, 2] > 0
    Vu = V + np.array([0, 0, gap])
    return np.vstack([V, Vu]), np.vstack([F[~upper], F[upper] + len(V)])


def test_gap_and_hole_below_rho_are_closed():
    gap, rho, epsilon = 0.04, 0.25, 0.04
    V, F = sphere_with_gap_and_hole(gap)
    assert len(topology.boundary_loops(F)) >= 3
    V2, F2, report = repair.volumetric_repair(V, F, epsilon=epsilon, rho=rho)
    assert_watertight(V2, F2)
    bound = epsilon + report.cell_size * np.sqrt(3)
    # Input to output: every input vertex near the output surface.
    assert SurfaceDistance(V2, F2).distances(V).max() <= bound
    # Output to input, away from the closed hole and gap: near the input surface.
    d = SurfaceDistance(V, F).distances(V2)
    away = (V2[:, 2] < 0.85) & (np.abs(V2[:, 2] - gap / 2) > gap + rho)
    assert d[away].max() <= bound
    assert report.closing_cells > 0 and report.unconstrained_vertices > 0
    # The solid: about the sphere stretched by the gap.
    assert volume(V2, F2) == pytest.approx(4 / 3 * np.pi + np.pi * gap, rel=0.04)
    # Without closing, the flood fill leaks through the gap: only a thin shell around the surface.
    V0, F0, _ = repair.volumetric_repair(V, F, epsilon=epsilon)
    assert_watertight(V0, F0)
    assert volume(V0, F0) < 0.25 * volume(V2, F2)


def test_smoothing_off_and_untangling_count():
    V, F = two_cubes()
    V2, F2, report = repair.volumetric_repair(V, F, epsilon=0.08, smoothing=0)
    assert_watertight(V2, F2)
    assert report.untangled_vertices >= 0 and report.manifold_cells >= 0
    assert report.inside_cells >= report.occupied_cells * 0.5


def test_bad_input():
    V, F = datasets.cube(2)
    with pytest.raises(meshsmith.InputError, match="epsilon"):
        repair.volumetric_repair(V, F, epsilon=0)
    with pytest.raises(meshsmith.InputError, match="epsilon"):
        repair.volumetric_repair(V, F, epsilon=float("nan"))
    with pytest.raises(meshsmith.InputError, match="rho"):
        repair.volumetric_repair(V, F, epsilon=0.1, rho=-1)
    with pytest.raises(meshsmith.InputError, match=r"grid would have \d\.\d+e\+\d+ cells \(\d+ x \d+ x \d+"):
        repair.volumetric_repair(V, F, epsilon=1e-4)
    with pytest.raises(meshsmith.InputError, match="max_cells"):
        repair.volumetric_repair(V, F, epsilon=0.05, max_cells=1000)
    with pytest.raises(meshsmith.InputError):
        repair.volumetric_repair(V, F[:, :2], epsilon=0.1)


def test_progress_and_cancel():
    V, F = datasets.cube(2)
    stages = []
    repair.volumetric_repair(V, F, epsilon=0.1, progress=lambda f, s: stages.append(s) or True)
    assert "rasterize" in stages
    with pytest.raises(meshsmith.Cancelled):
        repair.volumetric_repair(V, F, epsilon=0.1, progress=lambda f, s: False)


def feature_samples(V, F, angle_degrees=40.0, per_edge=5):
    """Points along the input's feature edges (dihedral angle above angle_degrees)."""
    N = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    sides = np.stack([F, np.roll(F, -1, axis=1)], axis=2).reshape(-1, 2)
    face = np.repeat(np.arange(len(F)), 3)
    key = np.sort(sides, axis=1)
    order = np.lexsort(key.T[::-1])
    key, face = key[order], face[order]
    same = np.all(key[1:] == key[:-1], axis=1)
    a, b = face[:-1][same], face[1:][same]
    sharp = np.einsum("ij,ij->i", N[a], N[b]) < np.cos(np.radians(angle_degrees))
    edges = key[:-1][same][sharp]
    t = (np.arange(per_edge) + 0.5) / per_edge
    return (V[edges[:, 0], None] * (1 - t[:, None]) + V[edges[:, 1], None] * t[:, None]).reshape(-1, 3)


def test_fandisk_sharp_edges_survive(data_dir):
    V, F = read_mesh(data_dir / "fandisk.obj")
    extent = float(np.ptp(V, axis=0).max())
    epsilon = extent / 80
    V2, F2, report = repair.volumetric_repair(V, F, epsilon=epsilon)
    assert_watertight(V2, F2)
    samples = feature_samples(V, F)
    assert len(samples) > 100
    feature = SurfaceDistance(V2, F2).distances(samples)
    overall = SurfaceDistance(V, F).distances(V2)
    h = report.cell_size
    print(f"fandisk: epsilon {epsilon:.4g}, cell {h:.4g}, grid {report.shape}, {len(F2)} faces; "
          f"feature-edge Hausdorff {feature.max():.4g} ({feature.max() / h:.3f} cells), "
          f"mean {feature.mean():.4g}; output->input {overall.max():.4g} ({overall.max() / h:.3f} cells), "
          f"sharp vertices {report.sharp_vertices}, untangled {report.untangled_vertices}")
    assert overall.max() <= epsilon + h * np.sqrt(3)
    # Features kept to a fraction of a cell (a voxel surface would round them by up to a cell).
    assert feature.max() <= epsilon
    assert np.median(feature) < 0.1 * h


@pytest.mark.parametrize("name", ["armadillo.obj", "bunny.off", "camelhead.off", "cubes_complex_edge.obj",
                                  "cubes_complex_vertex.obj", "hand_lowres.obj", "plane_holes.obj",
                                  "stanford-bunny.obj", "torus.obj"])
def test_shared_meshes_come_out_watertight(data_dir, name):
    """Open, holed, non-manifold and closed shared meshes: always closed, manifold, oriented, embedded."""
    V, F = read_mesh(data_dir / name)
    epsilon = float(np.ptp(V, axis=0).max()) / 30
    V2, F2, report = repair.volumetric_repair(V, F, epsilon=epsilon, rho=epsilon)
    assert_watertight(V2, F2)
    assert SurfaceDistance(V, F).distances(V2).max() <= epsilon + rho_bound(epsilon)


def rho_bound(rho):
    """How far a closed hole's patch may lie from the input: up to the closing radius, plus a cell."""
    return rho + rho / np.sqrt(3)
