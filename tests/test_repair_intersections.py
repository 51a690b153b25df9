"""meshsmith.repair.self_intersections (§2.4): constructed cases of each kind of contact (no
common vertex, one, an edge, all three), none on closed clean meshes (procedural and shared), and
two overlapping spheres: exactly the faces pymeshlab selects as self-intersecting, where it is
installed, and otherwise the faces near the circle where the spheres cross."""
import numpy as np
import pytest

import meshsmith
from meshsmith import datasets, repair

TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=float)


def pairs(V, F):
    return repair.self_intersections(V, F).tolist()


def test_faces_without_a_common_vertex():
    piercing = np.vstack([TRIANGLE, [[0.2, 0.2, -1], [0.3, 0.2, 1], [0.2, 0.3, 1]]])
    assert pairs(piercing, [[0, 1, 2], [3, 4, 5]]) == [[0, 1]]
    apart = np.vstack([TRIANGLE, TRIANGLE + [0, 0, 1e-9]])
    assert pairs(apart, [[0, 1, 2], [3, 4, 5]]) == []
    touching = np.vstack([TRIANGLE, [[0.5, 0.5, 0], [0.5, 0.5, 1], [1, 1, 1]]])   # a corner on the hypotenuse
    assert pairs(touching, [[0, 1, 2], [3, 4, 5]]) == [[0, 1]]


def test_faces_with_a_common_vertex():
    V = np.vstack([TRIANGLE, [[0.5, -0.2, 0.3], [0.2, 0.5, -0.3]]])     # face 1's far edge crosses face 0
    assert pairs(V, [[0, 1, 2], [0, 3, 4]]) == [[0, 1]]
    V = np.vstack([TRIANGLE, [[-1, 0, 0.5], [0, -1, 0.5]]])             # only the vertex in common
    assert pairs(V, [[0, 1, 2], [0, 3, 4]]) == []


def test_faces_with_a_common_edge():
    folded = np.vstack([TRIANGLE, [[0.5, 0.2, 0]]])                     # coplanar, same side of the edge
    assert pairs(folded, [[0, 1, 2], [1, 0, 3]]) == [[0, 1]]
    hinge = np.vstack([TRIANGLE, [[0.5, 0.2, 1e-12]]])                  # same side, not coplanar
    assert pairs(hinge, [[0, 1, 2], [1, 0, 3]]) == []
    flat = np.vstack([TRIANGLE, [[0.5, -1, 0]]])                        # coplanar, other side: a flat mesh
    assert pairs(flat, [[0, 1, 2], [1, 0, 3]]) == []
    assert pairs(TRIANGLE, [[0, 1, 2], [0, 2, 1]]) == [[0, 1]]          # the same three vertices


def test_closed_clean_meshes_have_none():
    for V, F in (datasets.icosphere(4), datasets.torus(), datasets.cube(8), datasets.uv_sphere()):
        assert repair.self_intersections(V, F).shape == (0, 2)


def test_every_closed_shared_mesh_has_none(data_dir):
    for name in ("bunny.off", "armadillo.obj", "fandisk.obj", "kitten.off", "spot.obj", "torus.obj"):
        V, F = meshsmith.io.read_mesh(data_dir / name)
        assert repair.self_intersections(V, F).shape == (0, 2), name


def test_two_overlapping_spheres():
    V, F = datasets.icosphere(3)
    V2 = np.vstack([V, 0.9 * V + [0.5, 0, 0]])
    F2 = np.vstack([F, F + len(V)])
    found = repair.self_intersections(V2, F2)
    assert len(found) > 0
    assert (found[:, 0] < len(F)).all() and (found[:, 1] >= len(F)).all()    # no sphere meets itself
    assert (np.diff(found[:, 0]) >= 0).all()
    faces = np.unique(found)
    # Each face listed has corners on both sides of the other sphere (within a face's size).
    centre = V2[F2[faces]].mean(axis=1)
    other = np.where(faces[:, None] < len(F), np.linalg.norm(centre - [0.5, 0, 0], axis=1)[:, None] / 0.9,
                     np.linalg.norm(centre, axis=1)[:, None])
    assert (np.abs(other - 1) < 0.15).all()
    pymeshlab = pytest.importorskip("pymeshlab")
    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(pymeshlab.Mesh(V2, F2))
    meshes.compute_selection_by_self_intersections_per_face()
    selected = np.flatnonzero(meshes.current_mesh().face_selection_array())
    np.testing.assert_array_equal(selected, faces)


def test_bad_input():
    with pytest.raises(meshsmith.InputError):
        repair.self_intersections(TRIANGLE, [[0, 1, 3]])
    with pytest.raises(meshsmith.Cancelled):
        V, F = datasets.icosphere(2)
        repair.self_intersections(V, F, progress=lambda fraction, stage: False)
