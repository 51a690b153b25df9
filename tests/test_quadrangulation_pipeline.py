"""quadrangulate (§5.2.2): cross field → MIQ → quad extraction, end to end, and its command line."""
import numpy as np
import pytest

import meshsmith
from meshsmith import cli, datasets, io, repair, topology
from meshsmith.quadrangulation import cross_field, quad_quality, quadrangulate
from test_quadrangulation_miq import feature_edges_on_iso_lines


def triangles(Q):
    return np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]])


def assert_valid(V, Q, euler):
    T = triangles(Q)
    assert Q.shape[1] == 4 and len(V) == Q.max() + 1
    assert topology.is_manifold(T) and topology.is_oriented(T)
    assert topology.euler_characteristic(T) == euler


def test_torus_gives_a_regular_grid():
    V, F = datasets.torus(1.0, 0.4, 48, 20)
    result = quadrangulate(V, F, target_faces=300)
    Vq, Q, report = result
    assert report.extraction.complete and report.extraction.euler_input == 0
    assert_valid(Vq, Q, 0)
    assert len(report.singular_vertices) == 0 and report.irregular_vertices == 0
    assert (quad_quality(Vq, Q).valence == 4).all()
    assert 0.6 * 300 < len(Q) < 1.6 * 300
    assert report.min_scaled_jacobian > 0


def test_cube_gets_its_eight_valence_three_corners():
    V, F = datasets.cube(8)
    result = quadrangulate(V, F, target_faces=150, align="smooth")
    Vq, Q, report = result
    assert report.extraction.complete
    assert_valid(Vq, Q, 2)
    assert report.singular_indices.sum() == 8  # Poincaré–Hopf: 4χ
    valence = quad_quality(Vq, Q).valence
    assert (valence == 3).sum() == 8 and report.irregular_vertices == 8



def test_bumpy_cube_gets_its_eight_corners_and_no_flip(data_dir):
    # The shared bumpy-cube is a cube (corners at ±2.08) with one tall dome per face (its tip at
    # 4.34): the cube's 8 corners are index +1 singularities; each dome, whose cap holds about a
    # full turn of curvature and its foot as much negative, carries 4 more (+1) and 4 (−1) of
    # total 0 (a box on a box), 56 in all. Before the curvature weight went from 1e-2 to 1e-3 the
    # principal directions' noise made 104, MIQ had 81 flips left 79 and the extraction was cut.
    V, F = io.read_mesh(data_dir / "bumpy-cube.obj")
    Vq, Q, report = quadrangulate(V, F, target_faces=3000)
    vertices, indices = report.singular_vertices, report.singular_indices
    assert indices.sum() == 8
    P = np.abs(V[vertices])
    corner = np.all(np.isclose(P, 2.08201, atol=1e-4), axis=1)
    assert corner.sum() == 8 and np.all(indices[corner] == 1)
    # the others: per dome (the axis it stands on, and its side) index 0 and at most 4 + 4
    dome = np.argmax(P, axis=1) * 2 + (V[vertices, :][np.arange(len(P)), np.argmax(P, axis=1)] > 0)
    for d in range(6):
        mine = ~corner & (dome == d)
        assert indices[mine].sum() == 0 and mine.sum() <= 8
    assert len(vertices) <= 56
    assert report.flipped_before <= 40 and report.flipped_after == 0
    assert report.extraction.complete
    assert_valid(Vq, Q, 2)
    assert 0.8 * 3000 < len(Q) < 1.2 * 3000
    # as extracted the quads next to cones are the worst (non-convex, −0.17, with the merge at 3.5
    # quad edges; 0.12 at 4.0); the relaxing and the smoothing never lower the minimum (0.84)
    assert 0.2 < report.min_scaled_jacobian and report.min_scaled_jacobian >= report.min_scaled_jacobian_extracted

# The shared meshes at 3,000 quads: every one flip-free, complete, manifold, oriented, with the
# input's χ, and every quad convex after relaxing the worst ones and the tangential smoothing. The
# greedy rounding is chaotic: which integer a value within rounding error of a half goes to changes
# with OpenBLAS's kernel (CHOLMOD's supernodal solves) and with moving the vertices by 1e-9 of the
# diagonal, and so do the flips, the merge distance that ends them and the figures after it. The
# bounds come from a sweep (2026-12-03, MIQ's grid calibrated to the count and its repair solved
# locally): OpenBLAS's Haswell, SkylakeX and Sandybridge kernels × the mesh as read and three 1e-9
# perturbations. Measured ranges: minimum scaled Jacobian spot 0.27–0.41, pmp-bunny 0.24–0.30,
# rocker-arm 0.32–0.36, fertility 0.26, fandisk 0.32–0.35, kitten 0.23–0.66; irregular vertices
# 48, 28–30, 18–20, 36, 18–20, 24–28; mean |angle − 90°| 5.2–5.5°, 6.9–7.0°, 7.0–7.4°, 6.2°,
# 6.6–8.0°, 5.9–6.2°; MIQ attempts 1, 1, 1, 2, 1, 1; quads 2,943–3,079 (−1.9% to +2.6%). The second
# number bounds the irregular count from above: QuadriFlow's count on the same mesh at the same
# request (bench_quadrangulation.py, 2026-12-02: 62, 56, 44, 66, 40, 30), which the issue asks us
# to beat. The third bounds the mean angle deviation (QuadriFlow: 10.7°, 9.9°, 8.1°, 7.3°, 6.7°,
# 8.2°; fandisk's is above QuadriFlow's, not reached).
SHARED = {"spot.obj": (0.2, 62, 6.0), "pmp-bunny.off": (0.2, 56, 7.4), "rocker-arm.obj": (0.25, 44, 7.9),
          "fertility.off": (0.2, 66, 6.6), "fandisk.obj": (0.25, 40, 8.7), "kitten.off": (0.2, 30, 6.5)}


@pytest.mark.parametrize("name", sorted(SHARED))
def test_shared_meshes_give_closed_pure_quad_meshes(data_dir, name):
    V, F = io.read_mesh(data_dir / name)
    Vq, Q, report = quadrangulate(V, F, target_faces=3000)
    euler = topology.euler_characteristic(F)
    assert report.flipped_after == 0
    assert report.extraction.complete
    assert_valid(Vq, Q, euler)
    assert report.singular_indices.sum() == 4 * euler  # Poincaré–Hopf
    assert 0.95 * 3000 < len(Q) < 1.05 * 3000 and 0.95 * 3000 < len(Vq) < 1.05 * 3000  # the issue: within 10%
    min_jacobian, irregular_bound, angle_bound = SHARED[name]
    assert report.min_scaled_jacobian > min_jacobian
    assert report.irregular_vertices < irregular_bound
    assert report.mean_angle_deviation < angle_bound
    # flip-free within the first merge distances of the schedule (4.0 … 3.0 quad edges; at most 2 seen)
    assert report.miq_attempts <= 3 and report.merge_distance > 0


@pytest.mark.parametrize("name, quads", [("kitten.off", 2000), ("rocker-arm.obj", 5000), ("kitten.off", 5000)])
def test_other_sizes(data_dir, name, quads):
    # with the old shortest-first order kitten at 2,000 quads needed the merge at 2.5 quad edges,
    # rocker-arm at 5,000 2.5, kitten at 5,000 4.0 (every shorter distance left 1–4 degenerate
    # triangles); every size must end flip-free whatever distance gets there
    V, F = io.read_mesh(data_dir / name)
    Vq, Q, report = quadrangulate(V, F, target_faces=quads)
    assert report.flipped_after == 0
    assert report.extraction.complete and report.min_scaled_jacobian > 0
    assert_valid(Vq, Q, topology.euler_characteristic(F))
    assert abs(len(Q) - quads) < 0.05 * quads  # measured: −0.4% to +2.7%


def test_fandisk_keeps_its_sharp_edges_as_quad_edges(data_dir):
    # With sharp_angle MIQ holds fandisk's feature edges on integer iso-lines (lines of quad
    # edges) and the map is flip-free at the first merge distance. Measured at 3,000 quads: 681
    # of the 710 edges above 40° held (2026-12-03, three OpenBLAS kernels alike); in 3D
    # 85% of the feature points lie within 0.01 quad edges of a quad edge (the quad edges are
    # chords of the curved feature lines; 19% within 1e-6, on the straight ones).
    V, F = io.read_mesh(data_dir / "fandisk.obj")
    result = quadrangulate(V, F, target_faces=3000, sharp_angle=40)
    Vq, Q, report = result
    assert report.flipped_after == 0 and report.extraction.complete and report.min_scaled_jacobian > 0
    assert_valid(Vq, Q, 2)
    assert report.miq_attempts == 1 and report.feature_edges > 0.9 * 710
    field = cross_field(V, F, sharp_angle=40)
    edges, on_line = feature_edges_on_iso_lines(V, F, field, result.UV, 40)
    length = np.linalg.norm(V[edges[:, 1]] - V[edges[:, 0]], axis=1)
    assert length[on_line].sum() >= 0.95 * length.sum()
    # the quad mesh's edges: every feature point within 0.05 quad edges of one for ≥ 90% of them
    edges_q = np.unique(np.sort(np.stack([Q, np.roll(Q, -1, axis=1)], -1).reshape(-1, 2), axis=1), axis=0)
    A, B = Vq[edges_q[:, 0]], Vq[edges_q[:, 1]]
    points = (V[edges[:, 0]] + V[edges[:, 1]]) / 2
    t = np.clip(np.einsum("kij,ij->ki", points[:, None] - A, B - A) / ((B - A) ** 2).sum(1), 0, 1)
    distance = np.linalg.norm(A + t[..., None] * (B - A) - points[:, None], axis=2).min(axis=1)
    assert (distance < 0.05 * report.target_edge_length).mean() >= 0.9


def test_relaxation_keeps_thin_tips(data_dir):
    # The relaxation of poorly shaped quads moves vertices within the input's tangent plane: it
    # used to move them the whole way to their neighbours' mean, which shrank pmp-bunny's ear tips
    # (at 2,000 quads Hausdorff ÷ diagonal 0.037 as extracted, 0.098 relaxed; then 0.044), and
    # every quad is still convex. Since the field follows folds (crease_weight, 2026-12-04) the
    # extraction is closer (0.019) and the relaxed mesh 0.040. Measured with the uniform scale
    # (conformal_scale=0): with the conformal scale the ear tips get larger quads (extracted 0.038)
    # and the relaxation alone leaves a non-convex quad there (min scaled Jacobian −0.04; the
    # smoothing after it makes every quad convex: 0.32).
    from meshsmith import geometry
    V, F = io.read_mesh(data_dir / "pmp-bunny.off")
    plain = quadrangulate(V, F, target_faces=2000, relax=0, smooth=0, conformal_scale=0)
    relaxed = quadrangulate(V, F, target_faces=2000, smooth=0, conformal_scale=0)
    assert np.array_equal(plain.Q, relaxed.Q)
    assert plain.report.min_scaled_jacobian <= 0 < relaxed.report.min_scaled_jacobian
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    before = geometry.hausdorff_distance(plain.V, triangles(plain.Q), V, F) / diagonal
    after = geometry.hausdorff_distance(relaxed.V, triangles(relaxed.Q), V, F) / diagonal
    assert after < max(1.25 * before, 0.05)          # moving the whole way gave 0.098


def test_smoothing_brings_angles_closer_to_right_angles(data_dir):
    # the same quads with and without the tangential smoothing: the mean |angle − 90°| drops
    # (kitten at 3,000 quads: 7.7° → 5.6°; 8.1° → 6.0° and 7.9° → 6.0° with its vertices moved by
    # 1e-9 of the diagonal, seeds 1 and 3), no quad's scaled Jacobian falls below the unsmoothed
    # minimum, and the vertices stay on the input surface
    from meshsmith.geometry.metrics import SurfaceDistance
    V, F = io.read_mesh(data_dir / "kitten.off")
    plain = quadrangulate(V, F, target_faces=3000, smooth=0)
    smoothed = quadrangulate(V, F, target_faces=3000)
    assert np.array_equal(plain.Q, smoothed.Q)
    assert smoothed.report.mean_angle_deviation < plain.report.mean_angle_deviation - 0.5
    assert smoothed.report.min_scaled_jacobian >= plain.report.min_scaled_jacobian
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    assert SurfaceDistance(V, F).distances(smoothed.V).max() < 1e-9 * diagonal
    with pytest.raises(meshsmith.InputError):
        quadrangulate(V, F, target_faces=3000, smooth=-1)


def test_sphere_is_closed_and_valid():
    V, F = datasets.icosphere(3)
    Vq, Q, report = quadrangulate(V, F, target_faces=200)
    assert report.singular_indices.sum() == 8
    assert_valid(Vq, Q, 2 if report.extraction.complete else topology.euler_characteristic(triangles(Q)))
    assert report.flipped_after == 0 or not report.extraction.complete


def test_options_and_progress():
    V, F = datasets.torus(1.0, 0.4, 32, 12)
    with pytest.raises(meshsmith.InputError, match="not both"):
        quadrangulate(V, F, target_faces=100, target_edge_length=0.2)
    fractions = []
    quadrangulate(V, F, target_edge_length=0.3, progress=lambda f, s: fractions.append(f))
    assert fractions == sorted(fractions) and fractions[-1] == pytest.approx(1.0)
    with pytest.raises(meshsmith.Cancelled):
        quadrangulate(V, F, progress=lambda f, s: False)


def test_command_line_writes_a_quad_mesh(tmp_path, capsys):
    V, F = datasets.torus(1.0, 0.4, 32, 12)
    path = tmp_path / "torus.off"
    io.write_mesh(path, V, F)
    out, picture = tmp_path / "quads.obj", tmp_path / "quads.png"
    assert cli.main(["quadrangulate", str(path), "-o", str(out), "--faces", "120", "--picture", str(picture)]) == 0
    text = capsys.readouterr().out
    assert "quads" in text and "singularities" in text
    Vq, P = io.read_mesh(out, triangulate=False)
    assert (P.sizes == 4).all() and picture.stat().st_size > 0
    assert cli.main(["quadrangulate", str(path), "-o", str(out), "--faces", "10", "--edge-length", "0.2"]) == 2


@pytest.mark.parametrize("option, value", [("curvature_weight", 0.03), ("crease_weight", 0.2),
                                           ("conformal_scale", 0.0)])
def test_command_line_passes_the_field_weights(tmp_path, option, value):
    """--curvature-weight, --crease-weight and --conformal-scale reach quadrangulate (the quads
    equal the function's at that value, which differ from the defaults'), and are refused with
    another method or a negative value."""
    flag = "--" + option.replace("_", "-")
    V, F = datasets.torus(1.0, 0.4, 32, 12)
    path = tmp_path / "torus.off"
    io.write_mesh(path, V, F)
    out = tmp_path / "quads.obj"
    assert cli.main(["quadrangulate", str(path), "-o", str(out), "--faces", "120", flag, str(value)]) == 0
    Vq, P = io.read_mesh(out, triangulate=False)
    V0, F0 = io.read_mesh(path)
    expected = quadrangulate(V0, F0, target_faces=120, **{option: value})
    default = quadrangulate(V0, F0, target_faces=120)
    assert len(P.sizes) == len(expected.Q) and np.allclose(Vq, expected.V, atol=1e-6)
    assert default.V.shape != expected.V.shape or not np.allclose(default.V, expected.V, atol=1e-6)
    assert cli.main(["quadrangulate", str(path), "-o", str(out), "--faces", "120", "--method", "spectral",
                     flag, str(value)]) == 2
    assert cli.main(["quadrangulate", str(path), "-o", str(out), "--faces", "120", flag, "-1"]) == 2


def test_the_result_carries_the_merged_field_its_map_follows(data_dir):
    from meshsmith.quadrangulation import singularities
    V, F = io.read_mesh(data_dir / "spot.obj")
    result = quadrangulate(V, F, target_faces=1000)
    cones = singularities(V, F, result.field)
    assert np.array_equal(cones.vertices, result.report.singular_vertices)
    assert np.array_equal(cones.indices, result.report.singular_indices)
    assert cones.indices.sum() == 4 * topology.euler_characteristic(F)
    assert len(singularities(V, F, cross_field(V, F)).vertices) > len(cones.vertices)   # pairs were merged


def test_demo_quadrangulation_stage(tmp_path):
    import json

    from meshsmith import demo
    from meshsmith.demo.quadrangulation import stage_quadrangulation
    name, V, F, uv = demo.builtin_shape()
    context = demo.DemoContext(out=tmp_path, name=name, V=V, F=F, uv=uv)
    section = stage_quadrangulation(context)
    assert all((tmp_path / image).stat().st_size > 1000 for image, _ in section.images)
    figures = context.figures["quadrangulation"]
    assert figures["quads"] > 500 and figures["index sum (4χ)"] == 4 * topology.euler_characteristic(F)
    json.dumps(figures)
    # an input the pipeline cannot take (two components) is skipped with the reason
    V2 = np.vstack([V, V + 10.0])
    F2 = np.vstack([F, F + len(V)])
    context = demo.DemoContext(out=tmp_path, name=name, V=V2, F=F2, uv=None)
    section = stage_quadrangulation(context)
    assert "skipped" in context.figures["quadrangulation"] and not section.images


def test_conformal_scale_brings_fandisks_angles_below_the_peers(data_dir):
    """The grid's conformal scale (conformal_scale=1, the default) against the uniform one (0) on
    fandisk at 3,000 quads: mean |angle − 90°| 2.50–2.94° over four 1e-9 perturbations of the mesh
    (2026-12-04) against 5.96° uniform; Instant Meshes asked for a quarter (about as many quads)
    5.27°, QuadriFlow 6.72° on this mesh. The crease term (crease_weight=0.2, the default before the
    conformal scale) and curvature_weight are passed through (each changes the quads), each a
    valid quad mesh."""
    V, F = repair.clean(*io.read_mesh(data_dir / "fandisk.obj"))[:2]   # as the benchmark reads it
    default = quadrangulate(V, F, target_faces=3000)
    uniform = quadrangulate(V, F, target_faces=3000, conformal_scale=0)
    creased = quadrangulate(V, F, target_faces=3000, crease_weight=0.2)
    curved = quadrangulate(V, F, target_faces=3000, curvature_weight=0.03)
    for result in (default, uniform, creased, curved):
        assert result.report.flipped_after == 0 and result.report.extraction.complete
        assert result.report.min_scaled_jacobian > 0
        assert abs(result.report.quads - 3000) <= 300
    assert default.report.mean_angle_deviation < 5.27                 # Instant Meshes/4's on this mesh
    assert default.report.mean_angle_deviation < uniform.report.mean_angle_deviation - 1.5
    assert default.report.map_distortion < 0.6 * uniform.report.map_distortion
    assert not np.array_equal(creased.field.theta, default.field.theta)
    assert not np.array_equal(curved.field.theta, default.field.theta)


def test_doublets_are_merged_back_into_one_quad():
    """A cube whose top quad is split at a centre vertex of valence 2 (a doublet): the removal
    gives back the cube's six quads (top quad the same cycle), its eight vertices and χ = 2; a
    mesh without doublets comes back unchanged."""
    from meshsmith.quadrangulation.pipeline import _remove_doublets
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    Q = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])
    same_V, same_Q, none = _remove_doublets(V, Q)
    assert none == 0 and np.array_equal(same_Q, Q) and same_V is V
    centre = np.vstack([V, [[0.5, 0.5, 1.0]]])
    split = np.vstack([Q[[0, 2, 3, 4, 5]], [[8, 7, 4, 5], [8, 5, 6, 7]]])       # top (4, 5, 6, 7) in two
    Vd, Qd, removed = _remove_doublets(centre, split)
    assert removed == 1 and len(Vd) == 8 and len(Qd) == 6
    assert np.array_equal(Vd, V)
    top = Qd[-1]
    assert any(np.array_equal(np.roll(top, k), Q[1]) for k in range(4))
    assert len(Vd) - len(np.unique(np.sort(np.stack([Qd, np.roll(Qd, -1, 1)], -1).reshape(-1, 2), 1), axis=0)) + len(Qd) == 2


def test_features_leave_no_doublet_and_no_degenerate_quad(data_dir):
    """With feature iso-lines held, kitten's extraction at sharp_angle=40 left one interior vertex of
    valence 2, its two quads at ~174° there (min scaled Jacobian −0.004 after the relaxation); the
    doublet is merged and every quad is convex. (The installed wheel's build rounds this map
    otherwise: its extraction leaves one hole, said in report.extraction, with a valence-2 vertex
    on the hole's border, which is no doublet.)"""
    V, F = repair.clean(*io.read_mesh(data_dir / "kitten.off"))[:2]
    result = quadrangulate(V, F, target_faces=3000, sharp_angle=40)
    quality = quad_quality(result.V, result.Q)
    assert result.report.removed_doublets >= 1
    edges = np.sort(np.stack([result.Q, np.roll(result.Q, -1, axis=1)], -1).reshape(-1, 2), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    border = np.zeros(len(result.V), dtype=bool)
    border[unique[counts == 1].ravel()] = True
    assert not np.any((quality.valence == 2) & ~border)
    assert result.report.min_scaled_jacobian > 0
    assert result.report.flipped_after == 0


def test_crease_weight_defaults_to_the_crease_term_only_with_sharp_angle():
    """crease_weight=None (the default) is 0 without sharp_angle and 0.2 with it: the quads equal
    those of the explicit weight and differ from the other's (a bumpy cube: its edges fold by 90°,
    below sharp_angle=100, so that the crease term acts where no feature constraint does)."""
    V, F = datasets.cube(subdivisions=10)
    V = V + 0.03 * np.sin(7 * V[:, [1, 2, 0]]) * np.abs(V)
    for sharp, weight, other in ((None, 0.0, 0.2), (100.0, 0.2, 0.0)):
        default = quadrangulate(V, F, target_faces=200, sharp_angle=sharp)
        explicit = quadrangulate(V, F, target_faces=200, sharp_angle=sharp, crease_weight=weight)
        different = quadrangulate(V, F, target_faces=200, sharp_angle=sharp, crease_weight=other)
        assert np.array_equal(default.Q, explicit.Q) and np.array_equal(default.V, explicit.V)
        assert not np.array_equal(default.field.theta, different.field.theta)
