"""Quad meshes as first-class data (issue 15 part 5): read and written with their quads in
OBJ/OFF/PLY, rendered with their edges (not the triangulation's diagonals), summarised by
topology.info with the quads' own face and edge counts."""
import json

import numpy as np
import pytest

import meshsmith
from meshsmith import io, render, topology
from meshsmith.io import Polygons


def quad_grid(k=4):
    """k×k unit quads on [0, 1]^2, counter-clockwise seen from +z."""
    x = np.linspace(0.0, 1.0, k + 1)
    X, Y = np.meshgrid(x, x, indexing="ij")
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    idx = np.arange((k + 1) ** 2).reshape(k + 1, k + 1)
    Q = np.stack([idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]], -1).reshape(-1, 4)
    return V, Q.astype(np.int64)


def quad_cube():
    """The cube's surface as 6 quads, outward."""
    V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    Q = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
    return V, Q


@pytest.mark.parametrize("extension", ["obj", "off", "ply"])
def test_quads_round_trip_through_obj_off_ply(tmp_path, extension):
    V, Q = quad_grid(3)
    path = tmp_path / f"quads.{extension}"
    io.write_mesh(path, V, Q)  # a (k, 4) array is written as quads
    V2, P = io.read_mesh(path, triangulate=False)
    assert isinstance(P, Polygons) and (P.sizes == 4).all()
    np.testing.assert_array_equal(P.to_array(), Q)
    np.testing.assert_allclose(V2, V)
    # the default read still triangulates, as a fan of each quad
    V3, F = io.read_mesh(path)
    assert F.shape == (2 * len(Q), 3)
    np.testing.assert_array_equal(F[::2], Q[:, [0, 1, 2]])
    np.testing.assert_array_equal(F[1::2], Q[:, [0, 2, 3]])


def test_polygons_from_and_to_arrays():
    V, Q = quad_grid(2)
    P = Polygons.from_array(Q)
    assert len(P) == 4 and P.to_array().dtype == np.int64
    np.testing.assert_array_equal(P.to_array(), Q)
    mixed = Polygons.from_list([[0, 1, 2, 3], [3, 2, 4]])
    with pytest.raises(meshsmith.InputError, match="polygon 1 has 3 corners"):
        mixed.to_array()
    triangles, masks, polygon_of = mixed.fan_triangles()
    np.testing.assert_array_equal(triangles, [[0, 1, 2], [0, 2, 3], [3, 2, 4]])
    # bit k: the edge opposite corner k is a polygon edge (the diagonal 2-0 / 0-2 is not)
    np.testing.assert_array_equal(masks, [0b101, 0b011, 0b111])
    np.testing.assert_array_equal(polygon_of, [0, 0, 1])
    with pytest.raises(meshsmith.InputError):
        Polygons.from_array(np.zeros((3, 2), int))


def test_topology_info_counts_quads_and_their_edges():
    V, Q = quad_grid(4)
    summary = topology.info(V, Q)
    assert (summary.n_vertices, summary.n_faces, summary.n_edges) == (25, 16, 40)
    assert summary.euler_characteristic == 25 - 40 + 16 == 1
    assert summary.n_boundary_loops == 1 and summary.n_boundary_edges == 16
    assert summary.is_manifold and summary.is_oriented and summary.genus == 0
    assert summary.surface_area == pytest.approx(1.0)
    V, Q = quad_cube()
    summary = topology.info(V, Q)
    assert (summary.n_faces, summary.n_edges, summary.euler_characteristic) == (6, 12, 2)
    assert summary.volume == pytest.approx(1.0) and summary.surface_area == pytest.approx(6.0)
    same = topology.info(V, Polygons.from_array(Q))
    assert same.as_dict() == summary.as_dict()


def luminance(image):
    return image[..., :3].astype(float) @ [0.299, 0.587, 0.114]


def test_render_draws_quad_edges_and_not_the_diagonals():
    k = 4
    V, Q = quad_grid(k)
    options = dict(size=(400, 400), view="front", projection="orthographic", background="white",
                   lighting=False)
    quads = render.render(V, Q, **options)  # wireframe on by default for quads
    triangles = render.render(V, np.concatenate([Q[:, [0, 1, 2]], Q[:, [0, 2, 3]]]), wireframe=True, **options)
    plain = render.render(V, Q, wireframe=False, **options)
    rows, columns = np.nonzero(np.any(plain != 255, axis=2))
    top, left = rows.min(), columns.min()
    side = (rows.max() - top + 1) / k

    def pixel(image, x, y):  # darkest luminance within 2 pixels of grid point (x right, y up)
        row, column = int(round(top + (k - y) * side)), int(round(left + x * side))
        return luminance(image)[row - 2:row + 3, column - 2:column + 3].min()

    cell_centre = (1.5, 2.5)   # on the diagonal of both triangles of a quad
    edge_middle = (1.5, 2.0)   # on a quad edge
    assert pixel(triangles, *cell_centre) < pixel(plain, *cell_centre) - 15
    assert pixel(quads, *cell_centre) == pytest.approx(pixel(plain, *cell_centre), abs=2)
    assert pixel(quads, *edge_middle) < pixel(plain, *edge_middle) - 15
    # per-corner uv of a quad mesh, (k, 4, 2)
    uv = V[Q][:, :, :2]
    checker = render.render(V, Q, uv=uv, checker_size=0.25, wireframe=False, **options)
    assert (checker != plain).any()
    with pytest.raises(meshsmith.InputError, match="uv has shape"):
        render.render(V, Q, uv=uv[:, :3], **options)


def test_cli_info_and_render_keep_quads(tmp_path, capsys):
    from meshsmith import cli
    V, Q = quad_grid(4)
    path = tmp_path / "quads.obj"
    io.write_mesh(path, V, Q)
    assert cli.main(["info", str(path), "--json"]) == 0
    figures = json.loads(capsys.readouterr().out)
    assert (figures["n_faces"], figures["n_edges"], figures["euler_characteristic"]) == (16, 40, 1)
    picture = tmp_path / "quads.png"
    assert cli.main(["render", str(path), "-o", str(picture), "--scalar", "valence"]) == 0
    assert picture.stat().st_size > 0
    capsys.readouterr()
    # a mixed mesh (a quad and a triangle) stays polygons
    mixed = tmp_path / "mixed.off"
    io.write_mesh(mixed, np.vstack([V[:4], [[2.0, 0.0, 0.0]]]), Polygons.from_list([[0, 1, 2, 3], [1, 4, 2]]))
    assert cli.main(["info", str(mixed), "--json"]) == 0
    figures = json.loads(capsys.readouterr().out)
    assert (figures["n_faces"], figures["n_edges"]) == (2, 6)
