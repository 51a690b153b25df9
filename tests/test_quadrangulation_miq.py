"""MIQ (§5.2.2 step 3): seamless to 1e-9 across every seam edge (a rotation by k·π/2 and an
integer translation), singular vertices on integer points, a regular grid with integer periods
on a torus, no flipped triangle on the shared meshes at about 3,000 quads, bad input."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, io
from meshsmith.quadrangulation import cross_field, merge_singularities, miq
from meshsmith.quadrangulation import pipeline

TURNS = [np.array(m, dtype=float) for m in ([[1, 0], [0, 1]], [[0, -1], [1, 0]], [[-1, 0], [0, -1]], [[0, 1], [-1, 0]])]


def corner(F, UV, f, v):
    return UV[f, list(F[f]).index(v)]


def seam_transitions(V, F, result, field):
    """Per seam edge: (k, t) with uv_g = R^k uv_f + t at both ends, asserting seamlessness to 1e-9."""
    edge_index = {tuple(e): k for k, e in enumerate(field.edges)}
    transitions = []
    for i, j in result.cut.cut.seam_edges:
        f, g = field.edge_faces[edge_index[(i, j)]]
        a_i, a_j = corner(F, result.UV, f, i), corner(F, result.UV, f, j)
        b_i, b_j = corner(F, result.UV, g, i), corner(F, result.UV, g, j)
        k = int(np.argmin([np.abs(R @ (a_j - a_i) - (b_j - b_i)).max() for R in TURNS]))
        t = b_i - TURNS[k] @ a_i
        assert np.abs(TURNS[k] @ a_j + t - b_j).max() < 1e-9
        assert np.abs(t - np.round(t)).max() < 1e-9
        transitions.append((k, np.round(t)))
    return transitions


def check_singular_vertices_on_integers(F, result):
    singular = set(result.cut.singularities.vertices)
    for f in range(len(F)):
        for k in range(3):
            if F[f, k] in singular:
                assert np.abs(result.UV[f, k] - np.round(result.UV[f, k])).max() < 1e-9


def test_torus_gives_a_regular_grid_with_integer_periods():
    V, F = datasets.torus(n_major=48, n_minor=16)
    # the analytic field along the parallels (the principal directions estimated on this coarse,
    # chirally triangulated torus are twisted by ~1.2°, which MIQ turns into a one-unit helical
    # shift over the 39 units of the long loop)
    centroids = V[F].mean(1)
    parallel = np.stack([-centroids[:, 1], centroids[:, 0], np.zeros(len(F))], axis=1)
    field = cross_field(V, F, constraints=(np.arange(len(F)), parallel))
    result = miq(V, F, field, target_quads=600, conformal_scale=0)   # a uniform grid (see below for 1)
    UV, before, after = result
    assert UV.shape == (len(F), 3, 2) and UV.dtype == np.float64
    assert len(result.cut.singularities.vertices) == 0
    assert before == 0 and after == 0
    transitions = seam_transitions(V, F, result, field)
    assert all(k == 0 for k, _ in transitions)  # no rotation on a torus
    periods = {tuple(t) for _, t in transitions if np.any(t)}
    # a grid: the periods (the seam arcs may be diagonal loops) span the lattice a·Z × b·Z of
    # one period along the parallels and one along the meridians
    P = np.array(sorted(periods))
    a, b = np.abs(P[:, 0][P[:, 0] != 0]).min(), np.abs(P[:, 1][P[:, 1] != 0]).min()
    assert np.all(P[:, 0] % a == 0) and np.all(P[:, 1] % b == 0)
    determinants = {abs(round(np.linalg.det(np.stack([p, q])))) for p in P for q in P} - {0}
    assert min(determinants) == a * b
    assert a > 10 and b > 5  # about 600 quads: 39 × 14 here
    # regular: every triangle's u and v gradients follow the parallels and meridians (the field)
    P = V[F]
    e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    du = np.stack([UV[:, 1] - UV[:, 0], UV[:, 2] - UV[:, 0]], axis=1)  # (m, 2, 2)
    areas = np.linalg.norm(np.cross(e1, e2), axis=1)
    jacobian = np.abs(np.linalg.det(du)) / areas
    assert jacobian.std() / jacobian.mean() < 0.35  # the torus' inner and outer rings differ in area


def test_conformal_scale_on_a_torus_is_the_analytic_conformal_factor():
    # On a torus of revolution (radii R, r) the metric is ρ² dφ² + r² dθ², ρ = R + r cos θ the
    # distance from the axis: a conformal map along the parallels has |∇u| ∝ 1/ρ, so its area
    # element per surface area goes as 1/ρ², and the log scale spans log(ρ_max / ρ_min). The
    # parallels turn against parallel transport (their geodesic curvature), which the conformal
    # factor of conformal_scale=1 absorbs; the uniform scale cannot (measured: (jacobian·ρ²)'s
    # std / mean 0.017 against 0.24, mean |μ| 0.031 against 0.124, log-scale range 0.70 for 0.71).
    V, F = datasets.torus(n_major=48, n_minor=16)
    centroids = V[F].mean(1)
    parallel = np.stack([-centroids[:, 1], centroids[:, 0], np.zeros(len(F))], axis=1)
    field = cross_field(V, F, constraints=(np.arange(len(F)), parallel))
    rho = np.linalg.norm(centroids[:, :2], axis=1)
    P = V[F]
    areas = np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=1)
    measures = {}
    for scale in (0.0, 1.0):
        result = miq(V, F, field, target_quads=600, conformal_scale=scale)
        assert result.flipped_after == 0
        UV = result.UV
        jacobian = np.abs(np.linalg.det(np.stack([UV[:, 1] - UV[:, 0], UV[:, 2] - UV[:, 0]], axis=1))) / areas
        conformal = jacobian * rho ** 2
        measures[scale] = (conformal.std() / conformal.mean(), pipeline._map_distortion(V, F, UV), result)
    assert measures[1.0][0] < 0.05 < 0.2 < measures[0.0][0]
    assert measures[1.0][1] < 0.05 < 0.1 < measures[0.0][1]
    conformal_result, uniform_result = measures[1.0][2], measures[0.0][2]
    assert uniform_result.log_scale_min == uniform_result.log_scale_max == 0
    spread = conformal_result.log_scale_max - conformal_result.log_scale_min
    assert abs(spread - np.log(rho.max() / rho.min())) < 0.1 * spread


def test_conformal_scale_is_checked():
    V, F = datasets.torus(n_major=24, n_minor=8)
    field = cross_field(V, F)
    for bad in (-0.1, 1.5, float("nan")):
        with pytest.raises(meshsmith.InputError, match="conformal_scale"):
            miq(V, F, field, conformal_scale=bad)
    with pytest.raises(meshsmith.InputError, match="conformal_scale"):
        miq(V, F, field, conformal_scale="1")


def test_sphere_is_seamless_with_singularities_on_integer_points():
    V, F = datasets.icosphere(3)
    field = cross_field(V, F)
    result = miq(V, F, field, target_quads=200)
    assert len(result.cut.singularities.vertices) == 8
    transitions = seam_transitions(V, F, result, field)
    assert any(k != 0 for k, _ in transitions)  # the sphere's seams rotate the grid
    check_singular_vertices_on_integers(F, result)
    assert result.flipped_after == 0
    assert result.integer_variables > 0 and result.rounding_residual <= 0.5


def test_spot_has_no_flipped_triangle_at_3000_quads(data_dir):
    V, F = io.read_mesh(data_dir / "spot.obj")
    field = cross_field(V, F)
    result = miq(V, F, field, target_quads=3000)
    assert result.flipped_before > 0 and result.flipped_after == 0  # the repair removes the rounding's flips
    seam_transitions(V, F, result, field)
    check_singular_vertices_on_integers(F, result)


@pytest.mark.parametrize("name", ["spot.obj", "kitten.off"])
def test_target_quads_calibrates_the_grid_to_the_count(data_dir, name):
    # The map's (u, v) area in unit squares is the quad count of a flip-free integer-grid map. With
    # √(area / quads) as the grid unit the map covered 6–11% fewer squares than asked (its gradients
    # are shorter than the field's where the field curls); calibrated on the continuous map, the
    # rounded map is within a few percent (measured here at 3,000: spot 3,021 squares, 2,743
    # uncalibrated; kitten 3,036 and 2,829). The field without its crease term (crease_weight=0),
    # as measured: following spot's folds the default field curls less and the correction is 1.8%.
    V, F = io.read_mesh(data_dir / name)
    field = cross_field(V, F, crease_weight=0)
    uncalibrated_length = np.sqrt(0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1).sum() / 3000)
    # the uniform scale, as measured (the conformal scale absorbs much of the curl: then the
    # correction is smaller, and test_conformal_scale_keeps_the_count_calibrated checks the count)
    calibrated = miq(V, F, field, target_quads=3000, conformal_scale=0)
    fixed = miq(V, F, field, target_edge_length=uncalibrated_length, conformal_scale=0)
    assert fixed.target_edge_length == uncalibrated_length
    assert calibrated.target_edge_length < 0.98 * uncalibrated_length
    for result, low, high in ((calibrated, 0.97, 1.03), (fixed, 0.8, 0.96)):
        uv = result.UV
        area = 0.5 * ((uv[:, 1, 0] - uv[:, 0, 0]) * (uv[:, 2, 1] - uv[:, 0, 1])
                      - (uv[:, 1, 1] - uv[:, 0, 1]) * (uv[:, 2, 0] - uv[:, 0, 0])).sum()
        assert low * 3000 < area < high * 3000


@pytest.mark.parametrize("name", ["spot.obj", "kitten.off"])
def test_conformal_scale_keeps_the_count_calibrated(data_dir, name):
    # the scale e^φ is normalized to a mean square of 1 and the grid calibrated after it: the
    # rounded map covers the count asked for within 3%
    V, F = io.read_mesh(data_dir / name)
    result = miq(V, F, cross_field(V, F), target_quads=3000)
    assert result.log_scale_min < -0.2 and result.log_scale_max > 0.2   # the scale does vary
    uv = result.UV
    area = 0.5 * ((uv[:, 1, 0] - uv[:, 0, 0]) * (uv[:, 2, 1] - uv[:, 0, 1])
                  - (uv[:, 1, 1] - uv[:, 0, 1]) * (uv[:, 2, 0] - uv[:, 0, 0])).sum()
    assert 0.97 * 3000 < area < 1.03 * 3000


def merged_field(V, F, quads, factor):
    """The curvature-aligned field with its singularity pairs closer than factor quad edges
    cancelled or moved apart (what quadrangulate does before MIQ)."""
    field = cross_field(V, F)
    length = np.sqrt(0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1).sum() / quads)
    return merge_singularities(V, F, field, factor * length)


def test_pmp_bunny_has_no_flip_once_close_singularities_are_merged(data_dir):
    # Without the merge the repair left 7 of 27 flips, all at valence-5 cones 0.2–0.3 quad edges
    # from another cone, which the rounding puts on the same or the next integer point.
    V, F = io.read_mesh(data_dir / "pmp-bunny.off")
    field = merged_field(V, F, 3000, 1.0)
    result = miq(V, F, field, target_quads=3000, conformal_scale=0)   # measured with the uniform scale
    assert result.flipped_before > 0 and result.flipped_after == 0
    assert len(result.cut.singularities.vertices) <= 60  # 67 before the merge
    seam_transitions(V, F, result, field)
    check_singular_vertices_on_integers(F, result)


def test_rocker_arm_has_no_flip_once_close_singularities_are_merged(data_dir):
    # Without the merge the stiffening leaves flips (±1 pairs on one edge, two −1 cones rounded
    # to one point), which the re-rounding may or may not remove: measured here at 3,000 quads
    # (the grid calibrated to the count, the repair solved locally; 2026-12-03) with OpenBLAS's
    # Haswell, SkylakeX and Sandybridge kernels, 14–15 flips → 3–4 by stiffening, → 3, 4 or 0
    # after re-rounding. Such dipoles are what the merge cancels.
    V, F = io.read_mesh(data_dir / "rocker-arm.obj")
    field = cross_field(V, F)
    unmerged = miq(V, F, field, target_quads=3000, conformal_scale=0)   # measured with the uniform scale
    stiffened_only = miq(V, F, field, target_quads=3000, reround=False, conformal_scale=0)
    assert 0 < stiffened_only.flipped_after <= 6 and stiffened_only.rerounded_integers == 0
    assert unmerged.flipped_after <= stiffened_only.flipped_after  # a move is kept only when it has fewer
    seam_transitions(V, F, unmerged, field)
    check_singular_vertices_on_integers(F, unmerged)
    field = merged_field(V, F, 3000, 1.5)
    result = miq(V, F, field, target_quads=3000, conformal_scale=0)
    assert result.flipped_after == 0
    seam_transitions(V, F, result, field)
    check_singular_vertices_on_integers(F, result)


def test_rerounding_removes_the_flips_the_stiffening_leaves(data_dir):
    # kitten's unmerged field at 3,000 quads (2026-12-03, OpenBLAS's Haswell, SkylakeX and
    # Sandybridge kernels): 8–9 flips after the rounding, 6–7 after the stiffening, 0–1 after
    # 3–4 re-rounding moves (a ±1 pair on one edge rounded onto one integer point). The field
    # without its crease term (crease_weight=0) and the uniform scale (conformal_scale=0), the ones
    # measured: the defaults' maps differ (the installed wheel's build: 2 flips left after one move).
    V, F = io.read_mesh(data_dir / "kitten.off")
    field = cross_field(V, F, crease_weight=0)
    rerounded = miq(V, F, field, target_quads=3000, conformal_scale=0)
    stiffened_only = miq(V, F, field, target_quads=3000, reround=False, conformal_scale=0)
    assert stiffened_only.flipped_after >= 3 and stiffened_only.rerounded_integers == 0
    assert rerounded.rerounded_integers > 0 and rerounded.flipped_after <= 1
    seam_transitions(V, F, rerounded, field)
    check_singular_vertices_on_integers(F, rerounded)


def test_feature_releases_run_only_where_releasing_helps(data_dir):
    """Where flips are left with the feature iso-lines held, MIQ first solves the map with every
    feature edge released (MiqResult.flipped_unconstrained) and runs its release re-solves only
    when that has fewer flips (2026-12-04: kitten at sharp_angle=40, 3,000 quads, 5 flips released
    against more held: one release round, 2 flips left; the installed wheel's build rounds this map
    otherwise: 1 released against more held, 4 left after the rounds, so the rounds' result is not
    asserted against it); with no flip left after the first solve (spot at 40) it is not solved
    (−1) and no feature is released."""
    V, F = io.read_mesh(data_dir / "kitten.off")
    held = miq(V, F, cross_field(V, F, sharp_angle=40), target_quads=3000, sharp_angle=40)
    assert held.flipped_unconstrained >= 0 and held.release_rounds > 0 and held.released_feature_edges > 0
    V, F = io.read_mesh(data_dir / "spot.obj")
    clean = miq(V, F, cross_field(V, F, sharp_angle=40), target_quads=3000, sharp_angle=40)
    assert clean.flipped_after == 0 and clean.flipped_unconstrained == -1
    assert clean.release_rounds == 0 and clean.released_feature_edges == 0 and clean.feature_edges > 0
    plain = miq(V, F, cross_field(V, F), target_quads=3000)
    assert plain.flipped_unconstrained == -1 and plain.feature_edges == 0


def test_genus_four_is_seamless(data_dir):
    V, F = io.read_mesh(data_dir / "fertility.off")
    field = cross_field(V, F)
    result = miq(V, F, field, target_quads=2000)
    seam_transitions(V, F, result, field)
    check_singular_vertices_on_integers(F, result)


def test_field_given_as_angles_or_directions_gives_the_same_map():
    V, F = datasets.torus(n_major=24, n_minor=10)
    field = cross_field(V, F)
    a = miq(V, F, field, target_edge_length=0.2)
    b = miq(V, F, field.directions, target_edge_length=0.2)
    assert np.allclose(a.UV, b.UV, atol=1e-9)
    assert a.target_edge_length == 0.2


def test_bad_input_raises_input_error():
    V, F = datasets.icosphere(1)
    theta = np.zeros(len(F))
    theta[0] = np.nan
    with pytest.raises(meshsmith.InputError, match="finite|NaN"):
        miq(V, F, theta)
    with pytest.raises(meshsmith.InputError, match="not both"):
        miq(V, F, np.zeros(len(F)), target_edge_length=1.0, target_quads=10)
    with pytest.raises(meshsmith.InputError, match="target_edge_length"):
        miq(V, F, np.zeros(len(F)), target_edge_length=-1.0)
    with pytest.raises(meshsmith.InputError, match="faces"):
        miq(V, F, np.zeros(3))


def test_progress_can_cancel():
    V, F = datasets.torus(n_major=24, n_minor=10)
    field = cross_field(V, F)
    with pytest.raises(meshsmith.Cancelled):
        miq(V, F, field, progress=lambda fraction, stage: False)


def feature_edges_on_iso_lines(V, F, field, UV, sharp_angle):
    """The edges whose dihedral angle exceeds sharp_angle (k, 2), and per edge whether some side
    has it on an integer iso-line of UV: both ends' same coordinate equal and an integer to 1e-6."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    sharp = field.edge_faces[:, 1] >= 0
    sharp &= np.einsum("ij,ij->i", n[field.edge_faces[:, 0]], n[field.edge_faces[:, 1]]) < np.cos(np.radians(sharp_angle))
    on_line = []
    for (i, j), faces in zip(field.edges[sharp], field.edge_faces[sharp]):
        held = False
        for f in faces:
            a, b = corner(F, UV, f, i), corner(F, UV, f, j)
            held |= bool(np.any((np.abs(a - b) < 1e-6) & (np.abs(a - np.round(a)) < 1e-6)))
        on_line.append(held)
    return field.edges[sharp], np.array(on_line)


def test_fandisk_features_lie_on_integer_iso_lines(data_dir):
    # MIQ's feature handling: with sharp_angle the coordinate across each feature edge is held
    # constant and integer on both sides, feature lines / cones less than a quad edge apart are
    # rounded onto distinct iso-lines, flips left after the stiffening are re-rounded (integers
    # near them moved by ±1), and feature edges next to flips that still remain are released.
    # Measured here at 3,000 quads (the grid calibrated to the count; 2026-12-03, the same on
    # OpenBLAS's Haswell, SkylakeX and Sandybridge kernels): of fandisk's 710 edges above 40°,
    # 681 held, 9 flips → 0 after one re-rounding and 8 release rounds (23 released); without
    # the re-rounding 685 held (19 released) after 3 release rounds, 7 flips → 0. The field
    # without its crease term (crease_weight=0), the one measured (with it, 2026-12-04, the
    # re-rounding holds as many; without the re-rounding 94.4% of the feature length stays on lines).
    V, F = io.read_mesh(data_dir / "fandisk.obj")
    field = cross_field(V, F, sharp_angle=40, crease_weight=0)
    length = None
    for reround in (True, False):
        result = miq(V, F, field, target_quads=3000, sharp_angle=40, reround=reround)
        assert result.flipped_after == 0
        edges, on_line = feature_edges_on_iso_lines(V, F, field, result.UV, 40)
        assert result.separations > 0 and result.separation_conflicts == 0
        assert result.feature_edges + result.released_feature_edges <= len(edges)
        assert on_line.sum() >= result.feature_edges
        length = np.linalg.norm(V[edges[:, 1]] - V[edges[:, 0]], axis=1)
        if reround:
            assert result.rerounded_integers > 0
            assert result.feature_edges >= 0.95 * len(edges)
            assert length[on_line].sum() >= 0.95 * length.sum()
        else:
            assert result.rerounded_integers == 0
            assert result.released_feature_edges < 0.05 * len(edges) and result.release_rounds > 0
            assert length[on_line].sum() >= 0.95 * length.sum()
    unconstrained = miq(V, F, field, target_quads=3000)
    assert unconstrained.feature_edges == 0 and unconstrained.separations == 0
