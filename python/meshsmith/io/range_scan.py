"""Range scans stored with their scanner grid: PLY files with a ``range_grid`` element (the
Stanford scans, e.g. bun000.ply), meshed from that grid.

Such a file holds the samples as vertices and, per cell of a num_rows × num_cols grid (given by
``obj_info num_rows R`` / ``obj_info num_cols C`` in the header), the list of the vertex sampled
there (one index, or none where the scanner saw nothing). :func:`meshsmith.io.read_mesh` reads the
vertices only (with a :class:`~meshsmith.io.SkippedDataWarning` naming this reader); the grid gives
the connectivity a scanner's software would use.
"""
from __future__ import annotations

import math
import os
from typing import NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import io as _core
from .._typing import FloatArray, IndexArray, PathLike
from ._skipped import warn_skipped


class RangeScan(NamedTuple):
    """A range scan meshed from its grid (:func:`read_range_scan`); unpacks as ``V, F, grid, spacing``.

    V: (n, 3) float64, every vertex record of the file; F: (m, 3) int64 triangles, consistently
    oriented, facing the scanner (their area-weighted normal points to +z, the scanner's side in
    its frame); no edge has more than two triangles, but a vertex where only diagonally opposite
    cells were sampled joins two fans (a non-manifold vertex); grid: (rows, cols)
    int64, the vertex of each cell or -1; spacing: the median length of the top edges of the fully
    sampled cells (the scanner's resolution; 0.0 when no cell is fully sampled).
    """

    V: FloatArray
    F: IndexArray
    grid: IndexArray
    spacing: float


@_arguments.real_options
def read_range_scan(path: PathLike, *, max_edge: float | None = 4.0) -> RangeScan:
    """Read a range scan (PLY with a ``range_grid`` element) and mesh it from its grid.

    Each grid cell whose four corners were sampled gives two triangles, split along its shorter
    diagonal; a cell with three gives one. Triangles with an edge longer than ``max_edge`` grid
    spacings are dropped: they span depth jumps and silhouettes, where neighbouring samples lie on
    different parts of the surface (None: keep every triangle). Nothing else is changed: the
    triangles are not cleaned (a grazing-angle triangle can fold over its neighbour; see
    :func:`meshsmith.repair.self_intersections`) and unreferenced vertices stay.

    Raises InputError for a file read_mesh refuses, a file without a range grid (or whose grid
    does not match the header's num_rows × num_cols), and max_edge not positive and finite.
    """
    if max_edge is not None and not (math.isfinite(max_edge) and max_edge > 0):
        raise InputError(f"read_range_scan: max_edge must be positive and finite, got {max_edge}")
    out = _core.read_mesh(os.fsdecode(path), "ply", True, False, False, False)
    warn_skipped(path, [m for m in out["warnings"] if "range_grid" not in m], stacklevel=3)  # above the option check
    grid = out["range_grid"]
    if grid is None:
        reasons = [m for m in out["warnings"] if "range_grid" in m]
        raise InputError(f"{os.fsdecode(path)}: no range grid"
                         + (f" ({reasons[0]})" if reasons else " (a PLY 'range_grid' element with "
                            "'obj_info num_rows' and 'obj_info num_cols' in the header)"))
    V = out["V"]
    a, b = grid[:-1, :-1].ravel(), grid[:-1, 1:].ravel()
    c, d = grid[1:, :-1].ravel(), grid[1:, 1:].ravel()
    full = (a >= 0) & (b >= 0) & (c >= 0) & (d >= 0)
    spacing = float(np.median(np.linalg.norm(V[b[full]] - V[a[full]], axis=1))) if full.any() else 0.0
    # the shorter diagonal of a full cell: b–c, else a–d
    short_bc = full & (np.linalg.norm(V[b] - V[c], axis=1) <= np.linalg.norm(V[a] - V[d], axis=1))
    short_ad = full & ~short_bc
    three = (a >= 0).astype(int) + (b >= 0) + (c >= 0) + (d >= 0) == 3
    F = np.vstack([np.column_stack(t)[keep] for t, keep in [
        ((b, c, a), short_bc), ((d, c, b), short_bc), ((d, c, a), short_ad), ((b, d, a), short_ad),
        ((b, c, a), three & (d < 0)), ((d, c, b), three & (a < 0)), ((b, d, a), three & (c < 0)),
        ((d, c, a), three & (b < 0))]]).astype(np.int64).reshape(-1, 3)
    if max_edge is not None and len(F):
        longest = np.linalg.norm(V[F] - V[np.roll(F, -1, axis=1)], axis=2).max(axis=1)
        F = F[longest <= max_edge * spacing]
    # All triangles turn the same way through the grid; which way depends on the order the file
    # stores the rows in (Stanford's scans: upwards in y). The scanner looks down −z: face it.
    if len(F) and np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])[:, 2].sum() < 0:
        F = F[:, ::-1]
    return RangeScan(V, np.ascontiguousarray(F), grid, spacing)
