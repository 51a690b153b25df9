"""ABF and ABF++ (§5.1.3): convergence, bijectivity, analytic truth on developable surfaces,
ABF == ABF++, angle distortion against LSCM and Tutte, progress and cancellation, bad input.

Measured here (ABF++, tolerance 1e-8; residual = infinity-norm of the triangle, vertex and wheel
conditions; angle distortion = RMS relative / mean absolute (rad) error of the UV angles against
the 3D angles; LSCM and Tutte (uniform harmonic, circle boundary) from this chapter):

    mesh                  faces  iterations  residual   ABF++          LSCM           Tutte
    hemisphere cap         1024      3       8.9e-14   0.0212/0.0198  0.0214/0.0198  0.2600/0.1728
    bumpy disk             1024      2       8.7e-10   0.0060/0.0053  0.0060/0.0054  0.3281/0.2308
    camelhead             22704      6       3.7e-10   0.0447/0.0239  0.0465/0.0246  3.3176/0.4085
    hand_lowres            1602      5       5.5e-10   0.2472/0.1632  0.2666/0.1819  0.5473/0.3140
    bunny (cut_to_disk)    6966      5       1.1e-09   0.0683/0.0428  0.0735/0.0460  0.6736/0.3540
    spot (cut_to_disk)     5856      4       1.3e-09   0.0696/0.0469  0.0716/0.0487  0.5544/0.3208
    fertility (cut)        9000      4       1.6e-10   0.0368/0.0254  0.0425/0.0287  1.1682/0.6629

No flipped triangle anywhere, and every layout bijective (check_bijectivity), though ABF itself
guarantees local injectivity only.
"""
import igl
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, io, parametrization
from meshsmith.geometry import triangle_distortion

# ---------------------------------------------------------------- helpers (independent of the core)


def corner_angles(X, F):
    """(m, 3) interior angles of the triangles of X (2D or 3D points), column k at corner k."""
    X = np.asarray(X, dtype=float)
    if X.shape[1] == 2:
        X = np.hstack([X, np.zeros((len(X), 1))])
    angles = np.empty(F.shape)
    for k in range(3):
        e1 = X[F[:, (k + 1) % 3]] - X[F[:, k]]
        e2 = X[F[:, (k + 2) % 3]] - X[F[:, k]]
        angles[:, k] = np.arctan2(np.linalg.norm(np.cross(e1, e2), axis=1), (e1 * e2).sum(1))
    return angles


def signed_areas(UV, F):
    a, b, c = UV[F[:, 0]], UV[F[:, 1]], UV[F[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def interior_vertices(F, n):
    interior = np.ones(n, dtype=bool)
    interior[igl.boundary_loop(F)] = False
    return interior


def constraint_residuals(F, angles, n):
    """Triangle, vertex and wheel residuals of ABF's conditions, computed with numpy."""
    triangle = np.abs(angles.sum(1) - np.pi).max()
    interior = interior_vertices(F, n)
    vertex_sum = np.bincount(F.ravel(), angles.ravel(), n)
    vertex = np.abs(vertex_sum[interior] - 2 * np.pi).max()
    log_sine = np.log(np.sin(angles))
    wheel_sum = np.zeros(n)
    for k in range(3):   # corner k: its next angle is column k+1, its previous one column k+2
        wheel_sum += np.bincount(F[:, k], log_sine[:, (k + 1) % 3] - log_sine[:, (k + 2) % 3], n)
    wheel = np.abs(wheel_sum[interior]).max()
    return triangle, vertex, wheel


def similarity_fit_error(A, B):
    """max |s R A + t - B| over the best similarity (least squares) of 2D points A onto B."""
    a, b = A - A.mean(0), B - B.mean(0)
    za, zb = a[:, 0] + 1j * a[:, 1], b[:, 0] + 1j * b[:, 1]
    scale_rotation = (np.conj(za) @ zb) / (np.conj(za) @ za)
    fitted = scale_rotation * za
    return np.abs(fitted - zb).max()


def hemisphere_cap(n_rings=16, n_segments=64, opening=0.45 * np.pi):
    """datasets.disk wrapped onto the unit sphere: the cap of polar angle `opening` (non-developable)."""
    V, F = datasets.disk(n_rings, n_segments)
    r = np.linalg.norm(V[:, :2], axis=1)
    phi = np.arctan2(V[:, 1], V[:, 0])
    theta = r * opening
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], 1), F


def bumpy_disk(n_rings=16, n_segments=64):
    V, F = datasets.disk(n_rings, n_segments)
    V = V.copy()
    V[:, 2] = 0.25 * np.sin(3 * V[:, 0]) * np.cos(2 * V[:, 1])
    return V, F


def cylinder_strip(n_around=24, n_along=10, radius=1.0, sweep=1.5 * np.pi, height=2.0):
    """datasets.grid rolled onto a cylinder over `sweep` radians: developable, one boundary loop."""
    V, F = datasets.grid(n_around, n_along)
    u, v = V[:, 0], V[:, 1]
    angle = u * sweep
    rolled = np.stack([radius * np.cos(angle), radius * np.sin(angle), v * height], 1)
    step = 1.0 / n_around                           # the mesh's edges are chords of the circle
    flat = np.stack([u / step * 2 * radius * np.sin(0.5 * sweep * step), v * height], 1)
    return rolled, F, flat


def angle_errors(V, F, UV):
    """(RMS of (UV angle - 3D angle) / 3D angle, mean |UV angle - 3D angle|) over all corners:
    the relative error is what ABF minimizes (against the 3D angles, not its rescaled targets)."""
    flipped = signed_areas(UV, F) < 0
    uv_angles = corner_angles(UV, F)
    uv_angles[flipped] = -uv_angles[flipped]      # a reversed triangle counts as such
    angles = corner_angles(V, F)
    return np.sqrt((((uv_angles - angles) / angles) ** 2).mean()), np.abs(uv_angles - angles).mean()


def shared(data_dir, name):
    V, F = io.read_mesh(data_dir / name)
    return np.asarray(V), np.asarray(F)


# ---------------------------------------------------------------- convergence and bijectivity

@pytest.mark.parametrize("name, max_iterations", [("camelhead.off", 10), ("hand_lowres.obj", 10)])
def test_abf_plus_plus_converges_without_flips_on_shared_disks(data_dir, name, max_iterations):
    V, F = shared(data_dir, name)
    result = parametrization.abf(V, F)
    assert result.residual <= 1e-8
    assert 1 <= result.iterations <= max_iterations
    assert len(result.residual_history) == result.iterations + 1
    assert result.residual_history[-1] == result.residual
    assert result.residual_history[0] > 1e-3          # the 3D angles were not already flat
    # The constraints, checked independently of the core.
    assert max(constraint_residuals(F, result.angles, len(V))) <= 1e-8
    assert result.uv.shape == (len(V), 2) and np.isfinite(result.uv).all()
    assert (signed_areas(result.uv, F) > 0).all()
    assert len(triangle_distortion(V, F, result.uv).flipped_faces) == 0
    # The layout reproduces the optimized angles (they are consistent, so least squares is exact).
    assert np.abs(corner_angles(result.uv, F) - result.angles).max() < 1e-6


@pytest.mark.parametrize("make", [hemisphere_cap, bumpy_disk], ids=["hemisphere_cap", "bumpy_disk"])
def test_abf_plus_plus_converges_on_procedural_disks(make):
    V, F = make()
    result = parametrization.abf(V, F)
    assert result.residual <= 1e-8 and 1 <= result.iterations <= 10
    assert max(constraint_residuals(F, result.angles, len(V))) <= 1e-8
    assert (signed_areas(result.uv, F) > 0).all()
    # β: the 3D angles rescaled to 2π at interior vertices (boundary corners keep theirs).
    beta = corner_angles(V, F)
    interior = interior_vertices(F, len(V))
    scale = 2 * np.pi / np.bincount(F.ravel(), beta.ravel(), len(V))
    expected = np.where(interior[F], beta * scale[F], beta)
    np.testing.assert_allclose(result.optimal_angles, expected, atol=1e-12)
    # The optimum moves away from β, but not by much on these smooth shapes.
    assert 1e-4 < np.abs(result.angles - result.optimal_angles).max() < 0.5


def test_a_tighter_tolerance_only_refines_the_optimum():
    V, F = hemisphere_cap(8, 32)
    loose = parametrization.abf(V, F, tolerance=1e-6)
    tight = parametrization.abf(V, F, tolerance=1e-13)
    assert tight.residual <= 1e-13 and tight.iterations >= loose.iterations
    assert np.abs(loose.angles - tight.angles).max() < 1e-4
    # The energy of the converged angles is below that of any feasible angles we can make from
    # a layout: those of the LSCM map, for example.
    energy = lambda a: (((a - tight.optimal_angles) / tight.optimal_angles) ** 2).sum()  # noqa: E731
    assert energy(tight.angles) < energy(corner_angles(parametrization.lscm(V, F), F))


# ---------------------------------------------------------------- analytic truth

def test_flat_disk_is_reproduced_exactly():
    V, F = datasets.disk(12, 48)
    result = parametrization.abf(V, F)
    assert result.iterations == 0 and result.residual < 1e-12
    np.testing.assert_allclose(result.angles, corner_angles(V, F), atol=1e-12)
    # The layout is the disk itself up to a similarity (rotation, translation, scale).
    assert similarity_fit_error(result.uv, V[:, :2]) < 1e-9
    # Scaled to the surface's area: the same triangles, up to a rigid motion.
    np.testing.assert_allclose(signed_areas(result.uv, F), signed_areas(V[:, :2], F), rtol=1e-8)


def test_cylinder_strip_unrolls_isometrically():
    V, F, flat = cylinder_strip()
    result = parametrization.abf(V, F)
    assert result.residual <= 1e-8 and result.iterations <= 1
    np.testing.assert_allclose(result.angles, corner_angles(V, F), atol=1e-10)
    assert similarity_fit_error(result.uv, flat) < 1e-8
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    uv_length = np.linalg.norm(result.uv[edges[:, 0]] - result.uv[edges[:, 1]], axis=1)
    flat_length = np.linalg.norm(flat[edges[:, 0]] - flat[edges[:, 1]], axis=1)
    np.testing.assert_allclose(uv_length, flat_length, rtol=1e-8)   # scaled to the surface area: isometric


def test_abf_and_abf_plus_plus_give_the_same_angles():
    V, F = hemisphere_cap(10, 40)
    fast = parametrization.abf(V, F, method="abf++")
    full = parametrization.abf(V, F, method="abf")
    assert full.iterations == fast.iterations and full.residual <= 1e-8
    np.testing.assert_allclose(full.angles, fast.angles, atol=1e-8)
    np.testing.assert_allclose(full.uv, fast.uv, atol=1e-7)


def test_abf_and_abf_plus_plus_agree_on_hand(data_dir):
    V, F = shared(data_dir, "hand_lowres.obj")
    fast = parametrization.abf(V, F, method="abf++")
    full = parametrization.abf(V, F, method="abf")
    np.testing.assert_allclose(full.angles, fast.angles, atol=1e-8)


def test_uv_from_angles_lays_out_consistent_angles_exactly():
    V, F = bumpy_disk(8, 32)
    UV_true = V[:, :2] + 0.1 * np.sin(V[:, :2])         # some planar embedding of the mesh
    angles = corner_angles(UV_true, F)
    UV = parametrization.uv_from_angles(F, angles, pinned=[F[0, 0], F[0, 1]],
                                        pinned_uv=UV_true[F[0, :2]])
    np.testing.assert_allclose(UV, UV_true, atol=1e-10)
    default = parametrization.uv_from_angles(F, angles)
    assert similarity_fit_error(default, UV_true) < 1e-10
    np.testing.assert_allclose(default[F[0, :2]], [[0, 0], [1, 0]], atol=0)


# ---------------------------------------------------------------- distortion: ABF++ < LSCM < Tutte

def _distortion_table(V, F):
    maps = {"abf++": parametrization.abf(V, F).uv, "lscm": parametrization.lscm(V, F),
            "tutte": parametrization.harmonic(V, F, weights="uniform")}
    return {name: angle_errors(V, F, uv) for name, uv in maps.items()}


def _assert_abf_below_lscm_below_tutte(table):
    for measure in range(2):
        assert table["abf++"][measure] < table["lscm"][measure] < table["tutte"][measure]


@pytest.mark.parametrize("make", [hemisphere_cap, bumpy_disk], ids=["hemisphere_cap", "bumpy_disk"])
def test_angle_distortion_abf_below_lscm_below_tutte_procedural(make):
    _assert_abf_below_lscm_below_tutte(_distortion_table(*make()))


@pytest.mark.parametrize("name", ["camelhead.off", "hand_lowres.obj"])
def test_angle_distortion_abf_below_lscm_below_tutte_shared(data_dir, name):
    _assert_abf_below_lscm_below_tutte(_distortion_table(*shared(data_dir, name)))


# ---------------------------------------------------------------- cut closed meshes

@pytest.mark.parametrize("name", ["bunny.off", "spot.obj", "fertility.off"])
def test_abf_plus_plus_on_cut_closed_meshes(data_dir, name):
    V, F = shared(data_dir, name)
    Vc, Fc, _, seam_edges = parametrization.cut_to_disk(V, F)
    assert len(seam_edges) > 0
    result = parametrization.abf(Vc, Fc)
    assert result.residual <= 1e-8 and result.iterations <= 10
    assert (signed_areas(result.uv, Fc) > 0).all()          # no flipped triangle
    report = parametrization.check_bijectivity(result.uv, Fc)
    assert report.bijective, report                         # and no boundary overlap either
    _assert_abf_below_lscm_below_tutte(_distortion_table(Vc, Fc))


@pytest.mark.parametrize("make", [lambda: hemisphere_cap(opening=0.95 * np.pi),
                                  lambda: tuple(parametrization.cut_to_disk(*datasets.torus()))[:2]],
                         ids=["sphere_with_small_hole", "cut_torus"])
def test_abf_plus_plus_on_hard_procedural_disks(make):
    V, F = make()
    result = parametrization.abf(V, F)
    assert result.residual <= 1e-8 and result.iterations <= 10
    assert max(constraint_residuals(F, result.angles, len(V))) <= 1e-8
    assert parametrization.is_bijective(result.uv, F)


# ---------------------------------------------------------------- progress and cancellation

def test_progress_reports_newton_iterations():
    V, F = hemisphere_cap(8, 32)
    calls = []
    result = parametrization.abf(V, F, progress=lambda fraction, stage: calls.append((fraction, stage)))
    fractions = [fraction for fraction, _ in calls]
    assert fractions == sorted(fractions) and 0 <= fractions[0] and fractions[-1] == 1.0
    assert any(stage.startswith("ABF++ Newton iteration 1,") for _, stage in calls)
    assert result.residual <= 1e-8


def test_cancelling_stops_with_cancelled():
    V, F = hemisphere_cap(8, 32)
    stages = []

    def stop(fraction, stage):
        stages.append(stage)
        return False

    with pytest.raises(meshsmith.Cancelled):
        parametrization.abf(V, F, progress=stop)
    assert len(stages) == 1 and "Newton iteration 1" in stages[0]


# ---------------------------------------------------------------- bad input

def test_closed_mesh_asks_for_a_cut():
    V, F = datasets.icosphere(2)
    with pytest.raises(meshsmith.InputError, match="closed.*cut_to_disk"):
        parametrization.abf(V, F)


def test_several_boundary_loops_are_rejected():
    V, F = datasets.disk(6, 24)
    keep = ~(F == 0).any(1)                      # remove the center fan: an annulus
    used = np.unique(F[keep])
    remap = np.full(len(V), -1)
    remap[used] = np.arange(len(used))
    with pytest.raises(meshsmith.InputError, match="2 boundary loops"):
        parametrization.abf(V[used], remap[F[keep]])


def test_several_components_are_rejected():
    V, F = datasets.disk(4, 12)
    V2 = np.vstack([V, V + [3.0, 0.0, 0.0]])
    F2 = np.vstack([F, F + len(V)])
    with pytest.raises(meshsmith.InputError, match="2 connected components"):
        parametrization.abf(V2, F2)


def test_non_manifold_input_is_rejected():
    V, F = datasets.disk(4, 12)
    # A second disk sharing only its center with the first one: a pinch vertex.
    V2 = np.vstack([V, V[1:] + [0.0, 0.0, 1.0]])
    shift = np.where(F == 0, 0, F + len(V) - 1)
    F2 = np.vstack([F, shift])
    with pytest.raises(meshsmith.InputError, match="vertex 0 is non-manifold"):
        parametrization.abf(V2, F2)
    # A fin: a third triangle on an interior edge.
    a, b = F[0, 0], F[0, 1]
    V3 = np.vstack([V, [[0.0, 0.0, 1.0]]])
    F3 = np.vstack([F, [[a, b, len(V)]]])
    with pytest.raises(meshsmith.InputError, match=r"edge \(\d+, \d+\) has 3 incident faces \(non-manifold\)"):
        parametrization.abf(V3, F3)


def test_isolated_vertex_gets_a_nan_row():
    # Unreferenced vertices are left out and the map comes back on the caller's indices.
    V, F = datasets.disk(4, 12)
    V2 = np.vstack([[[5.0, 5.0, 0.0]], V, [[6.0, 5.0, 0.0]]])
    result = parametrization.abf(V2, F + 1)
    assert np.isnan(result.uv[[0, len(V) + 1]]).all()
    np.testing.assert_array_equal(result.uv[1:-1], parametrization.abf(V, F).uv)


def test_face_repeating_a_vertex_is_rejected():
    V, F = datasets.disk(4, 12)
    F2 = F.copy()
    F2[5, 2] = F2[5, 0]
    with pytest.raises(meshsmith.InputError, match="face 5 repeats a vertex"):
        parametrization.abf(V, F2)


def test_inconsistent_orientation_is_rejected():
    V, F = datasets.disk(4, 12)
    F2 = F.copy()
    F2[7] = F2[7, ::-1]
    with pytest.raises(meshsmith.InputError, match="oriented"):
        parametrization.abf(V, F2)


def test_zero_area_triangles_are_rejected_and_needles_handled():
    V, F = bumpy_disk(8, 32)
    V = V.copy()
    v, a, b = F[40]
    collapsed = V.copy()
    collapsed[v] = collapsed[a]                   # face 40 (and its neighbour on v-a) lose their area
    with pytest.raises(meshsmith.InputError, match=r"face \d+ has zero area"):
        parametrization.abf(collapsed, F)
    # Face 40 made a needle: its first corner moved to 1e-9 from the middle of its opposite side,
    # so its 3D angles are ~1e-8, ~1e-8 and ~π.
    side = (V[b] - V[a]) / np.linalg.norm(V[b] - V[a])
    V[v] = 0.5 * (V[a] + V[b]) + 1e-9 * np.cross(side, [0.0, 0.0, 1.0])
    needle = corner_angles(V, F)[40]
    assert needle.min() < 1e-7
    result = parametrization.abf(V, F)
    assert result.residual <= 1e-8 and np.isfinite(result.uv).all()
    np.testing.assert_allclose(np.sort(result.optimal_angles[40])[:2], 1e-4)   # clamped β
    assert (signed_areas(result.uv, F) > 0).all()


def test_non_convergence_is_a_solver_error_with_the_residual(data_dir):
    V, F = shared(data_dir, "camelhead.off")
    with pytest.raises(meshsmith.SolverError, match=r"did not converge in 2 Newton iterations: constraint "
                                                      r"residual \(∞-norm\) [0-9.e-]+ > tolerance 1e-08"):
        parametrization.abf(V, F, max_iterations=2)


def test_bad_options_and_arrays():
    V, F = datasets.disk(4, 12)
    with pytest.raises(meshsmith.InputError, match="unknown method 'lscm'"):
        parametrization.abf(V, F, method="lscm")
    with pytest.raises(meshsmith.InputError, match="max_iterations"):
        parametrization.abf(V, F, max_iterations=0)
    with pytest.raises(meshsmith.InputError, match="tolerance"):
        parametrization.abf(V, F, tolerance=0.0)
    V_nan = V.copy()
    V_nan[3, 1] = np.nan
    with pytest.raises(meshsmith.InputError):
        parametrization.abf(V_nan, F)
    with pytest.raises(meshsmith.InputError):
        parametrization.abf(V[:, :2], F)
    with pytest.raises(meshsmith.InputError, match="not in \\(0, π\\)"):
        parametrization.uv_from_angles(F, np.zeros(F.shape))
    angles = np.full(F.shape, np.pi / 3)
    with pytest.raises(meshsmith.InputError, match="one row of three angles per face"):
        parametrization.uv_from_angles(F, angles[1:])
    with pytest.raises(meshsmith.InputError, match="two pins must be distinct"):
        parametrization.uv_from_angles(F, angles, pinned=[3, 3])
    with pytest.raises(meshsmith.InputError, match="pinned vertex 99 is outside"):
        parametrization.uv_from_angles(F, angles, pinned=[0, 99])
    with pytest.raises(meshsmith.InputError, match="pinned vertex 31 is used by no face"):
        parametrization.uv_from_angles(F, angles, n_vertices=len(V) + 1, pinned=[0, 31])


def test_uv_from_angles_gives_unused_vertices_nan_rows_and_the_rest_unchanged():
    """Like the other parametrizations: the layout of the used vertices, NaN rows for the others
    (an extra vertex at the end, or one in the middle of the numbering)."""
    V, F = hemisphere_cap(6, 24)
    angles = parametrization.abf(V, F).angles
    reference = parametrization.uv_from_angles(F, angles)
    extra = parametrization.uv_from_angles(F, angles, n_vertices=len(V) + 2)
    np.testing.assert_array_equal(extra[:len(V)], reference)
    assert np.all(np.isnan(extra[len(V):]))
    shifted = np.where(F >= 5, F + 1, F)  # vertex 5 unused
    middle = parametrization.uv_from_angles(shifted, angles, pinned=[shifted[0, 0], shifted[0, 1]])
    np.testing.assert_array_equal(np.delete(middle, 5, axis=0), reference)
    assert np.all(np.isnan(middle[5]))


def test_inputs_are_not_modified():
    V, F = hemisphere_cap(6, 24)
    V0, F0 = V.copy(), F.copy()
    parametrization.abf(V, F)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(F, F0)
