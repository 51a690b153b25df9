"""Cutting through the singularities (§5.2.2 step 2): the cut surface is a disk (one boundary
loop, χ = 1), every singular vertex lies on the seam, and the combed field has no period jump
across an uncut edge."""
import numpy as np
import pytest

from meshsmith import datasets, io
from meshsmith import _core
from meshsmith.parametrization import cut_to_disk
from meshsmith.quadrangulation import cross_field, cut_graph
from meshsmith.topology import boundary_loops, euler_characteristic


def check_cut(V, F, field):
    result = cut_graph(V, F, field)
    cut = result.cut
    assert euler_characteristic(cut.F) == 1 and len(boundary_loops(cut.F)) == 1
    on_seam = set(cut.seam_edges.ravel())
    boundary = set(np.concatenate(boundary_loops(F))) if len(boundary_loops(F)) else set()
    assert all(v in on_seam or v in boundary for v in result.singularities.vertices)
    edges = _core.quadrangulation.field_edges(V, F, result.combed_theta)
    seam = {tuple(e) for e in cut.seam_edges}
    interior = edges["edge_faces"][:, 1] >= 0
    uncut = np.array([interior[k] and tuple(edges["edges"][k]) not in seam for k in range(len(interior))])
    assert np.all(edges["period_jumps"][uncut] == 0)
    # seam_jumps are the combed jumps across the seam edges, in seam order
    index = {tuple(e): k for k, e in enumerate(edges["edges"])}
    jumps = edges["period_jumps"][[index[tuple(e)] for e in cut.seam_edges]]
    assert np.array_equal(jumps, result.seam_jumps)
    return result


def test_sphere_cut_passes_through_all_eight_singularities():
    V, F = datasets.icosphere(3)
    result = check_cut(V, F, cross_field(V, F))
    assert len(result.singularities.vertices) == 8


def test_torus_without_singularities_is_cut_along_its_two_loops():
    V, F = datasets.torus(n_major=32, n_minor=12)
    result = check_cut(V, F, cross_field(V, F))
    assert len(result.singularities.vertices) == 0
    assert len(result.cut.seam_edges) >= 32 // 2


def test_disk_with_interior_singularity_is_cut_to_it():
    V, F = datasets.disk(n_rings=8, n_segments=32)
    field = cross_field(V, F, align="smooth")  # boundary ignored: singular vertices inside
    result = check_cut(V, F, field)
    assert result.singularities.indices.sum() != 0


@pytest.mark.parametrize("name", ["fertility.off", "rocker-arm.obj", "spot.obj"])
def test_shared_meshes_cut_to_a_disk_through_the_singularities(data_dir, name):
    V, F = io.read_mesh(data_dir / name)
    check_cut(V, F, cross_field(V, F))


def test_cut_to_disk_through_vertices_keeps_them_on_the_seam():
    V, F = datasets.torus(n_major=24, n_minor=10)
    through = [5, 77, 130]
    cut = cut_to_disk(V, F, through=through)
    assert euler_characteristic(cut.F) == 1 and len(boundary_loops(cut.F)) == 1
    assert set(through) <= set(cut.seam_edges.ravel())
    plain = cut_to_disk(V, F)
    assert len(cut.seam_edges) > len(plain.seam_edges)
