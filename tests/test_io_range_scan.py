"""io.read_range_scan: PLY range scans (a range_grid element) meshed from their scanner grid."""
import struct
import warnings

import numpy as np
import pytest

from meshsmith import InputError, io, repair, topology


def grid_ply(path, P, grid, *, binary=False, rows=None, cols=None, cell_lists=None):
    """A range-scan PLY like Stanford's: vertices, then one list per grid cell (row-major) of the
    vertex sampled there (empty where none); `cell_lists` overrides the lists."""
    rows = grid.shape[0] if rows is None else rows
    cols = grid.shape[1] if cols is None else cols
    lists = cell_lists if cell_lists is not None else [[] if g < 0 else [int(g)] for g in grid.ravel()]
    header = ["ply", f"format {'binary_little_endian' if binary else 'ascii'} 1.0",
              f"obj_info num_cols {cols}", f"obj_info num_rows {rows}",
              f"element vertex {len(P)}", "property float x", "property float y", "property float z",
              f"element range_grid {len(lists)}", "property list uchar int vertex_indices", "end_header"]
    if binary:
        body = b"".join(struct.pack("<3f", *p) for p in P)
        body += b"".join(struct.pack(f"<B{len(c)}i", len(c), *c) for c in lists)
        path.write_bytes(("\n".join(header) + "\n").encode() + body)
    else:
        lines = [" ".join(f"{x:g}" for x in p) for p in P] + [" ".join(map(str, [len(c)] + list(c))) for c in lists]
        path.write_text("\n".join(header + lines) + "\n")
    return path


def plane_scan(rows=4, cols=5, missing=((1, 2),)):
    """Samples of the plane z = 1 on a unit grid (x = column, y = −row: row 0 on top, the other
    way round from Stanford's scans), with some cells unsampled."""
    grid = -np.ones((rows, cols), dtype=np.int64)
    P = []
    for r in range(rows):
        for c in range(cols):
            if (r, c) in missing:
                continue
            grid[r, c] = len(P)
            P.append((c, -r, 1.0))
    return np.array(P, dtype=np.float64), grid


def triangle_areas(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


@pytest.mark.parametrize("binary", [False, True])
def test_a_planar_grid_with_a_hole_gives_the_expected_triangles(tmp_path, binary):
    P, grid = plane_scan()
    path = grid_ply(tmp_path / "plane.ply", P, grid, binary=binary)
    V, F, read_grid, spacing = io.read_range_scan(path)
    np.testing.assert_array_equal(V, P)
    np.testing.assert_array_equal(read_grid, grid)
    assert spacing == 1.0
    # 3 × 4 cells; the missing sample (1, 2) leaves the 4 cells around it with three corners each
    assert len(F) == 2 * 8 + 4
    assert np.isclose(triangle_areas(V, F).sum(), 12 - 4 * 0.5)
    # every triangle faces the scanner (+z), the mesh is manifold and consistently oriented
    normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    assert np.all(normals[:, 2] > 0)
    assert len(topology.non_manifold_edges(F)) == 0 and topology.is_oriented(F)
    # the sample above the hole, on the top row, is where the two cells beside it meet corner to
    # corner: the one non-manifold vertex
    np.testing.assert_array_equal(topology.non_manifold_vertices(F), [grid[0, 2]])
    # read_mesh keeps the vertices only and says where the grid went
    with pytest.warns(io.SkippedDataWarning, match="read_range_scan"):
        V2, F2 = io.read_mesh(path)
    np.testing.assert_array_equal(V2, P)
    assert F2.shape == (0, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        P2, _ = io.read_points(path)
    np.testing.assert_array_equal(P2, P)


def test_long_edges_are_dropped_and_cells_split_along_their_shorter_diagonal(tmp_path):
    P, grid = plane_scan(rows=3, cols=3, missing=())
    P[grid[2, 2], 2] = 10.0   # a depth jump at the corner sample
    P[grid[0, 0]] += (0.3, -0.3, 0)  # the top-left cell's a–d diagonal is now the shorter one
    path = grid_ply(tmp_path / "jump.ply", P, grid)
    F = io.read_range_scan(path).F
    # the jump's cell splits along b–c (the a–d diagonal climbs 9 units): its triangle at d goes
    assert len(F) == 7 and not np.isin(grid[2, 2], F)
    assert len(io.read_range_scan(path, max_edge=None).F) == 8
    corners = {tuple(sorted(f)) for f in F.tolist()}
    a, d = grid[0, 0], grid[1, 1]
    assert sum(a in f and d in f for f in corners) == 2    # split along a–d
    b, c = grid[1, 1], grid[2, 0]     # equal diagonals: b–c
    assert sum(b in f and c in f for f in corners) == 2


def test_bun000_is_meshed_from_its_grid(data_dir):
    path = data_dir / "bun000.ply"
    if not path.is_file():
        pytest.skip("bun000.ply is not in the shared data")
    V, F, grid, spacing = io.read_range_scan(path)
    P, _ = io.read_points(path)
    np.testing.assert_array_equal(V, P)
    assert grid.shape == (400, 512)
    sampled = grid[grid >= 0]
    np.testing.assert_array_equal(np.sort(sampled), np.arange(len(V)))    # each sample in one cell
    # every cell with 4 samples gives 2 triangles, with 3 one; those with an edge > 4 spacings go
    a, b, c, d = grid[:-1, :-1], grid[:-1, 1:], grid[1:, :-1], grid[1:, 1:]
    count = (a >= 0).astype(int) + (b >= 0) + (c >= 0) + (d >= 0)
    assert len(io.read_range_scan(path, max_edge=None).F) == 2 * (count == 4).sum() + (count == 3).sum()
    longest = np.linalg.norm(V[F] - V[np.roll(F, -1, axis=1)], axis=2).max(axis=1)
    assert longest.max() <= 4 * spacing and len(F) > 0.95 * (2 * (count == 4).sum() + (count == 3).sum())
    assert 0.0005 < spacing < 0.0006    # Cyberware's ~0.56 mm between samples (bunny in metres)
    # no edge of three triangles; vertices where only diagonally opposite cells were sampled join
    # two fans, which repair.clean splits
    assert len(topology.non_manifold_edges(F)) == 0 and topology.is_oriented(F)
    assert len(topology.non_manifold_vertices(F)) > 0
    assert topology.is_manifold(repair.clean(V, F).F)
    normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    assert normals[:, 2].sum() > 0.5 * np.linalg.norm(normals, axis=1).sum()   # towards the scanner (0.75)


def test_bad_range_grids_are_input_errors(tmp_path):
    P, grid = plane_scan()
    plain = tmp_path / "plain.ply"
    plain.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n")
    with pytest.raises(InputError, match="no range grid"):
        io.read_range_scan(plain)
    wrong_size = grid_ply(tmp_path / "size.ply", P, grid, rows=5)
    with pytest.raises(InputError, match="not num_rows × num_cols"):
        io.read_range_scan(wrong_size)
    with pytest.warns(io.SkippedDataWarning, match="range_grid element is not kept"):
        io.read_mesh(wrong_size)
    lists = [[] if g < 0 else [int(g)] for g in grid.ravel()]
    two = grid_ply(tmp_path / "two.ply", P, grid, cell_lists=[[0, 1]] + lists[1:])
    with pytest.raises(InputError, match="range grid cell with 2 vertex indices"):
        io.read_range_scan(two)
    outside = grid_ply(tmp_path / "outside.ply", P, grid, cell_lists=[[len(P)]] + lists[1:], binary=True)
    with pytest.raises(InputError, match="outside"):
        io.read_range_scan(outside)
    truncated = tmp_path / "truncated.ply"
    truncated.write_bytes(grid_ply(tmp_path / "whole.ply", P, grid, binary=True).read_bytes()[:-7])
    with pytest.raises(InputError):
        io.read_range_scan(truncated)
    good = grid_ply(tmp_path / "good.ply", P, grid)
    for bad in (0, -1.0, float("nan"), float("inf")):
        with pytest.raises(InputError, match="max_edge"):
            io.read_range_scan(good, max_edge=bad)
    with pytest.raises(InputError, match="max_edge"):
        io.read_range_scan(good, max_edge="4")
    with pytest.raises(InputError):
        io.read_range_scan(tmp_path / "missing.ply")
