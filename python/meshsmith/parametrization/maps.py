"""Boundary maps, harmonic/Tutte maps, stretch-minimizing maps and LSCM (§5.1.1–5.1.2); binding cpp/python/parametrization_maps.cpp.

Every map runs on the vertices some face uses (repair.unreferenced.on_referenced_vertices) and
answers on the caller's vertex indices: NaN rows of UV for unreferenced vertices.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import NamedTuple

from .._core import parametrization as _core
from .._deprecation import positional_options
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..repair.unreferenced import on_referenced_vertices

__all__ = ["PinnedVertices", "map_boundary", "harmonic", "StretchResult", "stretch_minimizing", "lscm",
           "default_lscm_pins", "lscm_spectral"]


class PinnedVertices(NamedTuple):
    """Vertices with prescribed UV positions (:func:`map_boundary`, :func:`default_lscm_pins`);
    unpacks as ``indices, uv``, which :func:`harmonic` and :func:`lscm` take as their
    ``boundary, boundary_uv`` and ``pinned, pinned_uv``."""

    indices: IndexArray  #: (b,) vertex indices
    uv: FloatArray       #: (b, 2) their positions


def map_boundary(V: ArrayLike, F: ArrayLike, boundary: ArrayLike | None = None, *,
                 shape: str = "circle") -> PinnedVertices:
    """Map a boundary loop onto a convex polygon with arc-length spacing (§5, §5.1.1 step 1).

    V: (n, 3) float array, F: (m, 3) integer array.
    shape: "circle" (the unit circle, starting at (1, 0), counter-clockwise: exactly libigl's
        ``map_vertices_to_circle``) or "square" (the unit square [0, 1]^2 from (0, 0),
        counter-clockwise; the loop vertices nearest each quarter of the arc length are the corners).
    boundary: (b,) vertex indices of an ordered loop; default: the longest boundary loop of F,
        walked along the faces' orientation (so the map keeps triangles counter-clockwise).
    Returns a :class:`PinnedVertices` (boundary_indices (b,) int64, boundary_uv (b, 2) float64).
    Raises InputError for a mesh that is not a clean, connected, oriented manifold with a boundary
    (a closed mesh: cut it with :func:`cut_to_disk`), or a bad loop.
    The 0.1 form ``map_boundary(V, F, "square")`` (shape third) still works, with a DeprecationWarning.
    """
    if isinstance(boundary, str):
        warnings.warn("map_boundary(): pass shape= by keyword; the boundary loop is the third argument since "
                      "meshsmith 0.2.0", DeprecationWarning, stacklevel=2)
        shape, boundary = boundary, None
    mesh = on_referenced_vertices(V, F)
    loop = None if boundary is None else mesh.from_input_indices(boundary, "boundary")
    indices, uv = _core.map_boundary(mesh.V, mesh.F, shape, loop)
    return PinnedVertices(mesh.to_input_indices(indices), uv)


@positional_options("weights")
def harmonic(V: ArrayLike, F: ArrayLike, boundary: ArrayLike | None = None, boundary_uv: ArrayLike | None = None, *,
             weights: str = "uniform", shape: str = "circle") -> FloatArray:
    """Harmonic parametrization with a fixed boundary (§5.1.1): sum_j w_ij (u_j - u_i) = 0 inside.

    V: (n, 3) float array, F: (m, 3) integer array.
    boundary: (b,) fixed vertex indices; default: the longest boundary loop (the mesh must then be
        a topological disk). boundary_uv: (b, 2) their positions; default: `boundary` taken as an
        ordered loop mapped onto `shape` ("circle" or "square") by :func:`map_boundary`.
    weights: "uniform" (Tutte's embedding), "cotan" (the discrete harmonic map; the same as
        ``igl.harmonic(V, F, b, bc, 1)``) or "mean_value" (Floater). Uniform and mean-value
        weights are positive, so the map is bijective on a convex boundary; cotan may fold.
    Returns UV, (n, 2) float64 (NaN rows for vertices no face uses).
    Raises InputError for bad input (non-disk without an explicit boundary, non-manifold,
    several components, a boundary vertex no face uses, zero-area faces, bad boundary arrays); SolverError if
    the system is singular.
    """
    mesh = on_referenced_vertices(V, F)
    fixed = None if boundary is None else mesh.from_input_indices(boundary, "boundary")
    return mesh.to_input_rows(_core.harmonic(mesh.V, mesh.F, fixed, boundary_uv, weights, shape))


@dataclass(frozen=True)
class StretchResult(Unpackable):
    """The result of :func:`stretch_minimizing`; unpacks as ``uv, stretch, best_iteration``.

    uv: (n, 2) float64, the map of lowest stretch met (NaN rows for vertices no face uses); stretch: (k,) float64, Sander et al.'s
    scale-invariant L2 stretch (1 for an isometry up to scale) of the harmonic start (entry 0)
    and after every reweighting step; best_iteration: the index into `stretch` of `uv`.
    """

    uv: FloatArray
    stretch: FloatArray
    best_iteration: int


@positional_options("iterations")
def stretch_minimizing(V: ArrayLike, F: ArrayLike, *, iterations: int = 10, weights: str = "mean_value",
                       shape: str = "circle", progress: ProgressCallback = None) -> StretchResult:
    """Stretch-minimizing parametrization of a disk (§5.1.1; Yoshizawa, Belyaev & Seidel 2004).

    Starts from :func:`harmonic` with `weights` on the `shape` boundary, then repeats: per-vertex
    stretch s_i = area-weighted average of the triangle stretch sqrt((sigma1^2 + sigma2^2) / 2)
    (:func:`meshsmith.geometry.triangle_distortion`), weights w_ij <- w_ij / ((s_i + s_j) / 2),
    solve again. Stops after `iterations` steps or as soon as the stretch grows, and returns the
    best map. Positive starting weights ("uniform", "mean_value") keep every map bijective.

    V: (n, 3) float array, F: (m, 3) integer array (a topological disk); iterations >= 0;
    progress: optional callback (fraction, stage) -> bool (False cancels).
    Returns a :class:`StretchResult`. Raises InputError as :func:`harmonic`, or for iterations < 0.
    """
    mesh = on_referenced_vertices(V, F)
    result = _core.stretch_minimizing(mesh.V, mesh.F, iterations, weights, shape, progress)
    return StretchResult(**{**result, "uv": mesh.to_input_rows(result["uv"])})


def lscm(V: ArrayLike, F: ArrayLike, pinned: ArrayLike | None = None, pinned_uv: ArrayLike | None = None
         ) -> FloatArray:
    """Least-squares conformal map with pinned vertices (§5.1.2; Lévy et al. 2002).

    Minimizes sum over triangles of A |grad v - R90 grad u|^2 (twice the conformal energy
    Dirichlet - signed area) with a free boundary. Equal to ``igl.lscm(V, F, pinned, pinned_uv)``.

    V: (n, 3) float array, F: (m, 3) integer array (connected, oriented manifold with a boundary).
    pinned: (p,) p >= 2 vertex indices; pinned_uv: (p, 2) their positions (not all equal).
    Default (both None; the mesh must then be a disk): the two boundary vertices farthest apart
    (a double sweep on the longest loop) at (0, 0) and (their 3D distance, 0) — see
    :func:`default_lscm_pins`.
    Returns UV, (n, 2) float64, triangles counter-clockwise (NaN rows for vertices no face uses).
    Raises InputError for bad input (closed: cut with :func:`cut_to_disk`; non-manifold: clean
    with :func:`meshsmith.repair.clean`; several components, a pin no face uses,
    zero-area faces, bad pins); SolverError if the system is singular.
    """
    mesh = on_referenced_vertices(V, F)
    pins = None if pinned is None else mesh.from_input_indices(pinned, "pinned")
    return mesh.to_input_rows(_core.lscm(mesh.V, mesh.F, pins, pinned_uv))


def default_lscm_pins(V: ArrayLike, F: ArrayLike) -> PinnedVertices:
    """The pins :func:`lscm` uses when none are given: a :class:`PinnedVertices` (indices (2,)
    int64, uv (2, 2) float64)."""
    mesh = on_referenced_vertices(V, F)
    indices, uv = _core.default_lscm_pins(mesh.V, mesh.F)
    return PinnedVertices(mesh.to_input_indices(indices), uv)


def lscm_spectral(V: ArrayLike, F: ArrayLike) -> FloatArray:
    """Spectral conformal parametrization: LSCM with a free boundary and no pins (Mullen et al. 2008).

    The generalized eigenvector x of Q x = lambda B x (Q: the LSCM/conformal energy matrix,
    B: lumped boundary lengths) with the smallest lambda once translations are removed, found
    with Spectra's shift-invert Lanczos. Centred at the origin, scaled to the surface's area,
    triangles counter-clockwise; unique up to a rotation.

    V: (n, 3) float array, F: (m, 3) integer array (connected, oriented manifold with a boundary).
    Returns UV, (n, 2) float64 (NaN rows for vertices no face uses). Raises InputError as
    :func:`lscm`; SolverError if the
    eigensolver fails.
    """
    mesh = on_referenced_vertices(V, F)
    return mesh.to_input_rows(_core.lscm_spectral(mesh.V, mesh.F))
