"""geometry measures: face areas, surface area, signed volume (§1.2).

Checked against libigl's doublearea, trimesh's volume and the README's signed volumes on the
shared meshes, and against analytic areas and volumes of procedural shapes.
"""
import re

import igl
import numpy as np
import pytest
import trimesh

import meshsmith
from meshsmith import datasets, geometry


# Read with libigl because meshsmith.io is being written in parallel; switch to meshsmith.io later.
def read_mesh(path):
    V, F = igl.read_triangle_mesh(str(path))
    return np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)


# Signed volumes from ../shared/data/README.md (closed, oriented meshes).
README_VOLUMES = {"bunny.off": None, "decimated-knight.off": 0.0244911, "fandisk.obj": 20.2434,
                  "fertility.off": 432186, "kitten.off": 97568.8, "spot.obj": 0.718259,
                  "torus.obj": 1.21878, "armadillo.obj": 0.0683229}


@pytest.mark.parametrize("name", sorted(README_VOLUMES))
def test_measures_match_libigl_trimesh_and_the_readme(data_dir, name):
    V, F = read_mesh(data_dir / name)
    areas = geometry.face_areas(V, F)
    assert areas.shape == (len(F),) and areas.dtype == np.float64
    assert np.allclose(areas, igl.doublearea(V, F) / 2, rtol=1e-12, atol=0)
    assert geometry.surface_area(V, F) == pytest.approx(areas.sum(), rel=1e-12)
    reference = trimesh.Trimesh(V, F, process=False)
    assert geometry.surface_area(V, F) == pytest.approx(reference.area, rel=1e-10)
    assert geometry.volume(V, F) == pytest.approx(reference.volume, rel=1e-10)
    if README_VOLUMES[name] is not None:
        assert geometry.volume(V, F) == pytest.approx(README_VOLUMES[name], rel=1e-5)


def test_cube_area_and_volume_are_exact():
    for size in (1.0, 2.5):
        V, F = datasets.cube(5, size=size)
        assert geometry.surface_area(V, F) == pytest.approx(6 * size ** 2, rel=1e-13)
        assert geometry.volume(V, F) == pytest.approx(size ** 3, rel=1e-13)
        assert np.allclose(geometry.face_areas(V, F), (size / 5) ** 2 / 2)


def test_sphere_area_and_volume_converge_to_the_analytic_values():
    errors = []
    for s in (3, 4, 5):
        V, F = datasets.icosphere(s, radius=2.0)
        area, volume = geometry.surface_area(V, F), geometry.volume(V, F)
        assert area < 4 * np.pi * 4 and volume < 4 / 3 * np.pi * 8   # inscribed polyhedron
        errors.append((4 * np.pi * 4 - area) / (4 * np.pi * 4))
    assert errors[-1] < 1e-3
    assert errors[0] / errors[1] == pytest.approx(4, rel=0.05)     # second order in edge length


def test_volume_is_signed_and_translation_invariant_on_closed_meshes():
    V, F = datasets.torus()
    volume = geometry.volume(V, F)
    assert volume > 0
    assert geometry.volume(V, F[:, ::-1]) == pytest.approx(-volume, rel=1e-14)
    assert geometry.volume(V + [10.0, -3.0, 7.0], F) == pytest.approx(volume, rel=1e-10)
    exact = 2 * np.pi ** 2 * 1.0 * 0.35 ** 2
    assert volume == pytest.approx(exact, rel=0.01)


def test_degenerate_faces_have_zero_area():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]])
    F = np.array([[0, 1, 2], [0, 1, 3], [1, 1, 3]])
    assert geometry.face_areas(V, F).tolist() == [0.0, 0.5, 0.0]


@pytest.mark.parametrize("function", [geometry.face_areas, geometry.surface_area, geometry.volume])
def test_bad_input_raises_input_error(function):
    V, F = datasets.icosphere(0)
    bad_V = V.copy()
    bad_V[2, 0] = np.inf
    for args, message in [((bad_V, F), "V[2, 0] is inf"), ((V, F + 1), "indexes vertex 12"),
                          ((V, F[:0]), "F is empty"), ((V[:, :2], F), "V has shape (12, 2)"),
                          ((V, F.astype(float)), "expected integer indices")]:
        with pytest.raises(meshsmith.InputError, match=re.escape(message)):
            function(*args)
