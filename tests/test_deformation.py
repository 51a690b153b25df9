"""Deformation chapter: k-harmonic interpolation and handle-based deformation against libigl
(igl.harmonic), the detail-preserving variant's invariants, ARAP against libigl's
arap_precomputation/arap_solve, and bad input."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, deformation, io

igl = pytest.importorskip("igl")


def bbox_diagonal(V):
    return float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))


def sphere_regions(V):
    """A cap on top (handle) and one at the bottom (fixed) of a unit-ish sphere."""
    z = V[:, 2]
    handle = np.flatnonzero(z > 0.7 * z.max())
    fixed = np.flatnonzero(z < 0.7 * z.min())
    return handle, fixed


def rotation_about(axis, angle, center):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = center - R @ center
    return T


def apply(T, P):
    return P @ T[:3, :3].T + T[:3, 3]


@pytest.mark.parametrize("order", [1, 2, 3])
def test_harmonic_equals_libigl(order):
    V, F = datasets.disk(n_rings=12, n_segments=48)
    V = V + 0.05 * np.sin(3 * V[:, [1, 2, 0]])  # not planar, not symmetric
    b = np.flatnonzero(np.linalg.norm(V[:, :2], axis=1) > 0.9)
    bc = np.column_stack([np.cos(5 * V[b, 0]), V[b, 1] ** 2])
    ours = deformation.harmonic(V, F, b, bc, order=order)
    theirs = igl.harmonic(V, F.astype(np.int64), b.astype(np.int64), bc, order)
    assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()


@pytest.mark.parametrize("columns", [1, 3, 5, 8])
def test_harmonic_any_column_count_equals_libigl(columns):
    """The substitution runs 1, 2 or 4 columns per pass (3 padded to 4; 5 = 4 + 1); values at
    a few vertices only (a sparse right-hand side: the forward pass skips zero supernodes)."""
    V, F = datasets.disk(n_rings=20, n_segments=64)
    V = V + 0.05 * np.sin(3 * V[:, [1, 2, 0]])
    b = np.flatnonzero(np.linalg.norm(V[:, :2], axis=1) > 0.9)
    rng = np.random.default_rng(columns)
    bc = np.zeros((len(b), columns))
    some = rng.choice(len(b), size=5, replace=False)
    bc[some] = rng.normal(size=(5, columns))
    ours = deformation.harmonic(V, F, b, bc, order=2)
    theirs = igl.harmonic(V, F.astype(np.int64), b.astype(np.int64), bc, 2)
    assert np.abs(theirs).max() > 1e-3
    assert np.abs(ours - theirs).max() <= 1e-9 * np.abs(theirs).max()


@pytest.mark.parametrize("order", [1, 2, 3])
def test_deformer_displacement_equals_libigl_harmonic(order):
    V, F = datasets.icosphere(4)
    handle, fixed = sphere_regions(V)
    T = rotation_about([1, 0, 0], 0.6, V[handle].mean(axis=0))
    T[:3, 3] += [0.1, 0.3, 0.2]
    moved = apply(T, V[handle])
    deformer = deformation.Deformer(V, F, handle, fixed, order=order)
    U = deformer.deform(moved)
    b = np.concatenate([handle, fixed])
    D_b = np.concatenate([moved - V[handle], np.zeros((len(fixed), 3))])
    D = igl.harmonic(V, F.astype(np.int64), b.astype(np.int64), D_b, order)
    assert np.abs(U - (V + D)).max() <= 1e-8 * bbox_diagonal(V)
    # The affine path (four control points, no back-substitution) gives the same surface.
    assert np.abs(deformer.transform(T) - U).max() <= 1e-10 * bbox_diagonal(V)
    assert np.array_equal(U[fixed], V[fixed]) and np.array_equal(U[handle], moved)


def test_deformer_on_shared_mesh_equals_libigl(data_dir):
    V, F = io.read_mesh(data_dir / "camelhead.off")
    handle = np.flatnonzero(V[:, 1] > np.quantile(V[:, 1], 0.9))
    boundary = np.unique(igl.boundary_loop(F.astype(np.int64)))
    fixed = np.setdiff1d(boundary, handle)
    T = rotation_about([0, 0, 1], 0.4, V[handle].mean(axis=0))
    U = deformation.Deformer(V, F, handle, fixed).transform(T)
    b = np.concatenate([handle, fixed])
    D_b = np.concatenate([apply(T, V[handle]) - V[handle], np.zeros((len(fixed), 3))])
    D = igl.harmonic(V, F.astype(np.int64), b.astype(np.int64), D_b, 2)
    assert np.abs(U - (V + D)).max() <= 1e-8 * bbox_diagonal(V)


def test_identity_moves_nothing_and_unreferenced_vertices_stay():
    V, F = datasets.icosphere(3)
    V = np.vstack([V, [[5.0, 5.0, 5.0]]])  # used by no face
    handle, fixed = sphere_regions(V[:-1])
    for details in (False, True):
        deformer = deformation.Deformer(V, F, handle, fixed, details=details)
        assert np.abs(deformer.transform(np.eye(4)) - V).max() <= 1e-12
        assert np.abs(deformer.deform(V[handle]) - V).max() <= 1e-12
        U = deformer.transform(rotation_about([0, 1, 0], 1.0, np.zeros(3)))
        assert np.array_equal(U[-1], V[-1])


def bumpy_strip():
    V, F = datasets.grid(60, 12, size=(3.0, 0.6))
    V = V.copy()
    V[:, 2] += 0.03 * np.sin(12 * V[:, 0]) * np.sin(20 * V[:, 1])
    return V, F


def test_detail_preserving_keeps_detail_lengths_and_turns_them():
    V, F = bumpy_strip()
    x = V[:, 0]
    fixed = np.flatnonzero(x < x.min() + 0.3)
    handle = np.flatnonzero(x > x.max() - 0.3)
    T = rotation_about([0, 1, 0], np.pi / 2, V[handle].mean(axis=0))
    T[:3, 3] += [-0.6, 0.0, 0.8]
    plain = deformation.Deformer(V, F, handle, fixed)
    detailed = deformation.Deformer(V, F, handle, fixed, details=True)
    U_plain, U_detail = plain.transform(T), detailed.transform(T)
    # Details are re-added with their lengths: |U - base'| = |V - base| per vertex, where base' is
    # the moved base; the base moves by the plain displacement field.
    constrained = np.concatenate([handle, fixed])
    faired = meshsmith.deformation.harmonic(V, F, constrained, V[constrained], order=2)
    moved_base = faired + (U_plain - V)
    lengths_before = np.linalg.norm(V - faired, axis=1)
    lengths_after = np.linalg.norm(U_detail - moved_base, axis=1)
    assert np.abs(lengths_after - lengths_before).max() <= 1e-9
    # The detail's normal component is measured along the moved base's normal: the bumps turn
    # with the surface. The plain deformation keeps them along the rest normals instead, which
    # differ by up to the 90° of the bend.
    free = np.setdiff1d(np.arange(len(V)), constrained)
    normals = meshsmith.geometry.vertex_normals(faired, F)
    moved_normals = meshsmith.geometry.vertex_normals(moved_base, F)
    normal_before = np.einsum("ij,ij->i", V - faired, normals)[free]
    normal_detail = np.einsum("ij,ij->i", U_detail - moved_base, moved_normals)[free]
    normal_plain = np.einsum("ij,ij->i", U_plain - moved_base, moved_normals)[free]
    assert np.abs(normal_detail - normal_before).max() <= 1e-9
    assert np.abs(normal_plain - normal_before).max() > 0.3 * np.abs(normal_before).max()


def libigl_arap(V, F, handles, positions, initial, iterations):
    data = igl.ARAPData()
    data.max_iter = iterations
    igl.arap_precomputation(V, F.astype(np.int64), 3, handles.astype(np.int32), data)
    return igl.arap_solve(positions, data, initial)


@pytest.mark.parametrize("iterations", [1, 5, 20])
def test_arap_energy_no_higher_than_libigl(iterations):
    V, F = datasets.icosphere(4)
    handle, fixed = sphere_regions(V)
    handles = np.concatenate([handle, fixed])
    T = rotation_about([1, 0, 0], 0.8, V[handle].mean(axis=0))
    positions = np.concatenate([apply(T, V[handle]), V[fixed]])
    arap = deformation.ArapDeformer(V, F, handles)
    initial = arap.solve(positions, 0)  # the harmonic start, handles placed
    ours = arap.solve(positions, iterations, initial=initial)
    theirs = libigl_arap(V, F, handles, positions, initial, iterations)
    e_ours, e_theirs = arap.energy(ours), arap.energy(theirs)
    assert e_ours <= e_theirs * (1 + 1e-7) + 1e-14
    assert e_ours < arap.energy(initial)
    assert np.abs(ours[handles] - positions).max() == 0.0


def test_arap_energy_decreases_every_iteration_and_matches_the_function():
    V, F = datasets.icosphere(3)
    handle, fixed = sphere_regions(V)
    handles = np.concatenate([handle, fixed])
    positions = np.concatenate([V[handle] + [0.0, 0.4, 0.3], V[fixed]])
    arap = deformation.ArapDeformer(V, F, handles)
    U = arap.solve(positions, 0)
    energies = [arap.energy(U)]
    for _ in range(8):
        U = arap.solve(positions, 1, initial=U)
        energies.append(arap.energy(U))
    assert all(b <= a * (1 + 1e-12) for a, b in zip(energies, energies[1:]))
    assert deformation.arap_energy(V, F, U) == pytest.approx(energies[-1], rel=1e-12)
    assert np.allclose(deformation.arap(V, F, handles, positions, iterations=8), U, atol=1e-12)


def test_arap_energy_vanishes_for_rigid_motions_which_are_fixed_points():
    V, F = datasets.torus(n_major=32, n_minor=12)
    T = rotation_about([1, 2, 3], 0.9, np.array([0.2, 0.0, -0.1]))
    T[:3, 3] += [1.0, -2.0, 0.5]
    W = apply(T, V)
    assert deformation.arap_energy(V, F, W) <= 1e-20 * len(V)
    handles = np.arange(0, len(V), 37)
    U = deformation.arap(V, F, handles, W[handles], iterations=2, initial=W)
    assert np.abs(U - W).max() <= 1e-10


def two_spheres():
    V, F = datasets.icosphere(2)
    return np.vstack([V, V + [3.0, 0, 0]]), np.vstack([F, F + len(V)]), len(V)


@pytest.mark.parametrize("make", [
    lambda V, F, n: deformation.Deformer(V, F, [0, 1, 2], [2, 5]),                       # overlap
    lambda V, F, n: deformation.Deformer(V, F, [], [5]),                                  # empty handle
    lambda V, F, n: deformation.Deformer(V, F, [0, 1], [5]),                              # second sphere free
    lambda V, F, n: deformation.Deformer(V, F, [0, 0], [n]),                              # repeated
    lambda V, F, n: deformation.Deformer(V, F, [0], [2 * n]),                             # out of range
    lambda V, F, n: deformation.Deformer(V, F, [0], [n], order=4),                        # order
    lambda V, F, n: deformation.Deformer(V, F, [0], [n]).transform(np.full((4, 4), np.nan)),
    lambda V, F, n: deformation.Deformer(V, F, [0], [n]).transform(np.ones((4, 4))),      # projective
    lambda V, F, n: deformation.Deformer(V, F, [0], [n]).transform(np.eye(3)),
    lambda V, F, n: deformation.Deformer(V, F, [0], [n]).deform([[np.nan, 0, 0]]),
    lambda V, F, n: deformation.Deformer(V, F, [0], [n]).deform([[0, 0, 0], [1, 1, 1]]),
    lambda V, F, n: deformation.ArapDeformer(V, F, []),
    lambda V, F, n: deformation.ArapDeformer(V, F, [0, 1]),                               # second sphere free
    lambda V, F, n: deformation.ArapDeformer(V, F, [0, n]).solve([[0, 0, 0], [np.inf, 0, 0]], 3),
    lambda V, F, n: deformation.ArapDeformer(V, F, [0, n]).solve(np.zeros((2, 3)), -1),
    lambda V, F, n: deformation.ArapDeformer(V, F, [0, n]).solve(np.zeros((2, 3)), 1, initial=np.zeros((3, 3))),
    lambda V, F, n: deformation.harmonic(V, F, [0, 1], [[0.0], [1.0]]),                   # second sphere free
    lambda V, F, n: deformation.harmonic(V, F, [0, n], [[0.0], [1.0], [2.0]]),
])
def test_bad_input_is_an_input_error(make):
    V, F, n = two_spheres()
    before = V.copy()
    with pytest.raises(meshsmith.InputError):
        make(V, F, n)
    assert np.array_equal(V, before)


def test_singular_part_is_named_not_left_to_cholmod():
    V, F, n = two_spheres()
    with pytest.raises(meshsmith.InputError, match=rf"vertex {n} is in a connected part of {n} vertices"):
        deformation.Deformer(V, F, [0], [1])
    with pytest.raises(meshsmith.InputError, match="both in handle and in fixed"):
        deformation.Deformer(V, F, [0, 7], [7, n])


def test_poisson_edit_without_rotations_is_the_bilaplacian_deformation():
    V, F = datasets.icosphere(3)
    handle, fixed = sphere_regions(V)
    moved = V[handle] + [0.2, 0.1, 0.3]
    ours = deformation.poisson_edit(V, F, handle, moved, fixed=fixed, rotate=False)
    assert np.abs(ours - deformation.Deformer(V, F, handle, fixed).deform(moved)).max() <= 1e-10 * bbox_diagonal(V)


def test_poisson_edit_carries_a_rigid_handle_motion_to_the_whole_surface():
    V, F = datasets.torus(n_major=40, n_minor=16)
    handle = np.arange(0, 60)
    T = rotation_about([1, 1, 0], 0.7, V[handle].mean(axis=0))
    T[:3, 3] += [0.3, -0.2, 0.1]
    rigid = apply(T, V)
    # Only the handle is constrained: the weights are 1 everywhere, so every Laplacian coordinate
    # turns with the handle and the rigid motion of the whole surface solves the system exactly.
    turned = deformation.poisson_edit(V, F, handle, rigid[handle])
    assert np.abs(turned - rigid).max() <= 1e-9 * bbox_diagonal(V)
    plain = deformation.poisson_edit(V, F, handle, rigid[handle], rotate=False)
    assert np.abs(plain - rigid).max() > 0.05 * bbox_diagonal(V)


def test_multiresolution_edit_keeps_details_under_identity_and_rigid_base_edits():
    V, F = bumpy_strip()
    fixed = np.flatnonzero((V[:, 0] < 0.3) | (V[:, 0] > 2.7))
    assert np.abs(deformation.multiresolution_edit(V, F, fixed, lambda base: base) - V).max() <= 1e-12
    T = rotation_about([0, 1, 1], 1.1, np.array([1.0, 0.3, 0.0]))
    edited = deformation.multiresolution_edit(V, F, fixed, lambda base: apply(T, base))
    assert np.abs(edited - apply(T, V)).max() <= 1e-10
    # A non-rigid base edit (bending the base up in the middle) keeps each detail's length.
    bump = lambda base: base + np.outer(np.sin(np.pi * base[:, 0] / 3.0) ** 2, [0, 0, 0.5])  # noqa: E731
    constrained_base = deformation.harmonic(V, F, fixed, V[fixed], order=2)
    bent = deformation.multiresolution_edit(V, F, fixed, bump)
    assert np.allclose(np.linalg.norm(bent - bump(constrained_base), axis=1),
                       np.linalg.norm(V - constrained_base, axis=1), atol=1e-10)
    with pytest.raises(meshsmith.InputError):
        deformation.multiresolution_edit(V, F, fixed, lambda base: base[:-1])


def test_demo_stage_pictures_and_arap_lowest_energy(tmp_path):
    from meshsmith.demo import DemoContext, builtin_shape
    from meshsmith.demo.deformation import stage_deformation
    name, V, F, uv = builtin_shape()
    context = DemoContext(tmp_path, name, V, F, uv)
    section = stage_deformation(context)
    assert len(section.images) == 3 and all((tmp_path / image).stat().st_size > 1000 for image, _ in section.images)
    energy = {key.split(":")[0]: value for key, value in context.figures["deformation"].items() if "energy" in key}
    assert energy["ARAP, 10 iterations"] < min(energy["bi-Laplacian"], energy["bi-Laplacian with details"])
