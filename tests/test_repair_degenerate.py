"""meshsmith.repair.remove_needles_and_caps (§2.4): a needle and a cap planted in a flat grid are
removed, the topology (Euler characteristic, boundary loops, components) and the flat shape kept,
positions not moved; clean's needles_and_caps option with its counts."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, geometry, repair, topology


def grid_with_needle_and_cap():
    """A flat 8×8 grid with a vertex moved next to a neighbour (the two faces on their edge become
    needles) and, far from it, a vertex moved next to the opposite edge of one of its faces (a cap
    of about 174°); every face keeps its upward normal."""
    V, F = datasets.grid(8, 8)
    V = V.copy()
    rim = set(topology.boundary_loops(F)[0].tolist())
    centre = V.mean(axis=0)
    inner = [f for f in range(len(F)) if not rim & set(F[f].tolist())]
    near = min(inner, key=lambda f: np.linalg.norm(V[F[f]].mean(axis=0) - centre + 0.2))
    far = min(inner, key=lambda f: np.linalg.norm(V[F[f]].mean(axis=0) - centre - 0.2))
    u, v = F[near, :2]
    V[v] = V[u] + 1e-3 * (V[v] - V[u])
    a, b, c = F[far]
    middle = (V[a] + V[b]) / 2
    V[c] = middle + 0.05 * (V[c] - middle)
    assert (geometry.face_normals(V, F)[:, 2] > 0).all()
    return V, F


def test_needle_and_cap_removed_topology_kept():
    V, F = grid_with_needle_and_cap()
    out = repair.remove_needles_and_caps(V, F)
    assert out.collapses >= 1 and out.flips >= 1 and out.remaining_needles == 0 and out.remaining_caps == 0
    np.testing.assert_array_equal(out.V, V[out.vertex_map])                  # nothing moved
    assert topology.euler_characteristic(out.F) == topology.euler_characteristic(F)
    assert len(topology.boundary_loops(out.F)) == 1 and topology.is_manifold(out.F) and topology.is_oriented(out.F)
    assert geometry.surface_area(out.V, out.F) == pytest.approx(1.0, rel=1e-12)  # still the unit square
    normals = geometry.face_normals(out.V, out.F)
    assert (normals[:, 2] > 0.999).all()                                     # no face turned over
    assert len(out.F) == len(F) - 2 * out.collapses
    V_ok, F_ok = datasets.icosphere(3)
    untouched = repair.remove_needles_and_caps(V_ok, F_ok)
    assert untouched.collapses == untouched.flips == 0
    np.testing.assert_array_equal(untouched.F, F_ok)


def test_clean_option_counts():
    V, F = grid_with_needle_and_cap()
    V2, F2, report = repair.clean(V, F, needles_and_caps=True)
    assert report.needle_collapses >= 1 and report.needle_faces == 2 * report.needle_collapses
    assert len(V2) == len(V) - report.needle_collapses and len(F2) == len(F) - report.needle_faces
    np.testing.assert_array_equal(V2, np.asarray(V)[report.vertex_map])
    assert repair.clean(V, F).report.needle_collapses == 0                     # off by default


def test_bad_options():
    V, F = datasets.icosphere(1)
    for option in ({"needle_ratio": 1.0}, {"cap_angle": 90.0}, {"cap_angle": 180.0}, {"max_passes": -1}):
        with pytest.raises(meshsmith.InputError):
            repair.remove_needles_and_caps(V, F, **option)
