"""Discrete differential geometry (§1.2, §3.0.2): normals, Laplacians, mass matrices, curvatures, eigenpairs; binding cpp/python/geometry_differential.cpp.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
import scipy.sparse

from .. import _arguments
from .._core import core as _core_checks
from .._core import geometry as _geometry
from .._deprecation import positional_options
from .._typing import ArrayLike, FloatArray, ProgressCallback

__all__ = ["face_normals", "vertex_normals", "cotan_laplacian", "uniform_laplacian", "mean_value_laplacian",
           "mass_matrix", "vertex_areas", "gaussian_curvature", "MeanCurvature", "mean_curvature",
           "PrincipalCurvatures", "principal_curvatures", "Eigenpairs", "laplacian_eigenpairs"]


class MeanCurvature(NamedTuple):
    """Result of :func:`mean_curvature`; unpacks as ``H, Hn``."""

    H: FloatArray   #: (n,) signed mean curvature, per unit length (1/r on a sphere of radius r)
    Hn: FloatArray  #: (n, 3) mean-curvature normal H n


class PrincipalCurvatures(NamedTuple):
    """Result of :func:`principal_curvatures`; unpacks as ``k1, k2, d1, d2``."""

    k1: FloatArray  #: (n,) largest principal curvature, per unit length
    k2: FloatArray  #: (n,) smallest principal curvature (k2 <= k1)
    d1: FloatArray  #: (n, 3) unit direction of k1
    d2: FloatArray  #: (n, 3) unit direction of k2, d2 = n x d1


class Eigenpairs(NamedTuple):
    """Result of :func:`laplacian_eigenpairs`; unpacks as ``values, vectors``."""

    values: FloatArray   #: (k,) ascending eigenvalues
    vectors: FloatArray  #: (n, k) M-orthonormal eigenvectors, column j for values[j]


def _csc(parts: Any) -> scipy.sparse.csc_matrix:
    data, indices, indptr, rows, cols = parts
    return scipy.sparse.csc_matrix((data, indices, indptr), shape=(rows, cols))


def face_normals(V: ArrayLike, F: ArrayLike) -> FloatArray:
    """Unit normals of the faces: ``(p1 - p0) x (p2 - p0)`` normalised.

    V: (n, 3) float array of vertex positions. F: (m, 3) int array of triangles,
    counter-clockwise seen from outside. Returns an (m, 3) float array. A degenerate face
    (twice its area <= 8 eps (longest edge)**2: a repeated vertex or collinear corners) gets
    the zero vector. Equals ``igl.per_face_normals`` on non-degenerate faces.

    Raises InputError for bad (V, F).
    """
    return _geometry.face_normals(V, F)


@positional_options("weighting")
def vertex_normals(V: ArrayLike, F: ArrayLike, *, weighting: str = "angle") -> FloatArray:
    """Unit vertex normals: the weighted sum of the incident face normals, normalised (§1.2.4).

    V: (n, 3) float array. F: (m, 3) int array. weighting: ``"uniform"`` (each incident face
    once), ``"area"`` (by face area) or ``"angle"`` (by the corner angle; the default). Returns
    an (n, 3) float array equal to ``igl.per_vertex_normals`` with the matching
    ``PER_VERTEX_NORMALS_WEIGHTING_TYPE_*``. Degenerate faces contribute nothing; a vertex
    used by no face (or whose face normals cancel exactly) gets the zero vector, never NaN.

    Raises InputError for bad (V, F) or an unknown weighting.
    """
    return _geometry.vertex_normals(V, F, weighting)


def cotan_laplacian(V: ArrayLike, F: ArrayLike, *, intrinsic_delaunay: bool = False) -> scipy.sparse.csc_matrix:
    """Cotangent Laplacian (§3.0.2 cot-weights), libigl's sign: negative semi-definite.

    ``L[i, j] = (cot(alpha_ij) + cot(beta_ij)) / 2`` for every edge ij (one cotangent on a
    boundary edge), ``L[i, i] = -sum_j L[i, j]``. Symmetric, with linear precision: on a planar
    mesh ``L @ f`` vanishes at interior vertices for every linear function f.

    V: (n, 3) float array. F: (m, 3) int array. Returns an (n, n) ``scipy.sparse.csc_matrix``
    equal to ``igl.cotmatrix``. Every column stores its diagonal (0 for an unused vertex). The
    cotangents of a degenerate triangle (twice its area <= 8 eps (longest edge)**2) are set to
    zero instead of +-inf, so such a triangle contributes nothing.

    intrinsic_delaunay: the cot weights of the intrinsic Delaunay triangulation instead (§3.0.2
    "Delaunay cot-weights"; Bobenko & Springborn 2007): every edge with a negative weight
    (alpha + beta > pi) is flipped intrinsically, on edge lengths only, until the triangulation
    is locally Delaunay; no vertex moves, but an entry may join two vertices that share no mesh
    edge. A boundary edge has a single cotangent, negative where its opposite angle is obtuse, that
    no flip changes: such an edge is split intrinsically at the foot of that angle's altitude (two
    right triangles), and each inserted vertex is lumped back onto the edge's ends (its value
    their linear interpolant, its weights shared between them in the same proportions, the cross
    term that made the edge's weight negative dropped), so the matrix stays (n, n). Every
    off-diagonal entry is then >= 0, on interior and boundary edges alike (weights within 1e-12
    (1 + |cot alpha| + |cot beta|) below zero, co-circular quads, are set to 0); the matrix is
    symmetric, its rows sum to zero, it is negative semi-definite. Equal to
    ``igl.intrinsic_delaunay_cotmatrix`` to round-off where no boundary edge is split (libigl
    keeps the negative boundary weights; near a split edge the entries differ), and to the plain
    cotan Laplacian on a mesh that is already Delaunay with no obtuse angle opposite a boundary
    edge. Linear precision holds at every interior vertex. Needs an edge-manifold, consistently
    oriented mesh.

    Raises InputError for bad (V, F), or with intrinsic_delaunay for an edge with more than two
    faces or two faces that traverse an edge in the same direction.
    """
    return _csc(_geometry.cotan_laplacian(V, F, bool(intrinsic_delaunay)))


def uniform_laplacian(first: ArrayLike, second: ArrayLike | int | None = None, *, normalized: bool = False) -> scipy.sparse.csc_matrix:
    """Graph Laplacian with uniform weights (§3.0.2): ``L[i, j] = 1`` per edge, ``L[i, i] = -deg(i)``.

    Call as ``uniform_laplacian(F, n)`` (F: (m, 3) int array, n: the number of vertices,
    default ``F.max() + 1``) or as ``uniform_laplacian(V, F)`` like the other Laplacians (V:
    (n, 3) float array, validated together with F, only its length is used). With
    ``normalized=True`` each row is divided by the vertex degree: ``L[i, j] = 1/|N1(i)|``,
    ``L[i, i] = -1`` (the umbrella operator; not symmetric). Returns an (n, n)
    ``scipy.sparse.csc_matrix``; a vertex used by no face has a zero row and column.

    Raises InputError for an empty F, n < 1, an index of F outside ``[0, n)``, or bad V.
    """
    if second is None or np.isscalar(second) or (isinstance(second, np.ndarray) and second.ndim == 0):
        return _csc(_geometry.uniform_laplacian(first, second, bool(normalized)))  # (F, n): the core checks n
    V, F = first, second
    _core_checks.validate_mesh(V, F)
    return _csc(_geometry.uniform_laplacian(F, len(_arguments.real_array(V, "V", 3)), bool(normalized)))


def mean_value_laplacian(V: ArrayLike, F: ArrayLike) -> scipy.sparse.csc_matrix:
    """Mean-value Laplacian (§3.0.2 mean value weights; Floater 2003). Not symmetric.

    ``L[i, j] = (tan(alpha_ij / 2) + tan(beta_ij / 2)) / |p_j - p_i|``, where alpha_ij and
    beta_ij are the angles at vertex i in the two triangles sharing edge ij (one on a boundary
    edge), and ``L[i, i] = -sum_j L[i, j]``. The weights are positive for every triangle and
    have linear precision, but row i holds vertex i's weights, so ``L != L.T``.

    V: (n, 3) float array. F: (m, 3) int array. Returns an (n, n) ``scipy.sparse.csc_matrix``.
    Degenerate triangles and zero-length edges contribute nothing.

    Raises InputError for bad (V, F).
    """
    return _csc(_geometry.mean_value_laplacian(V, F))


@positional_options("kind")
def mass_matrix(V: ArrayLike, F: ArrayLike, *, kind: str = "voronoi") -> scipy.sparse.csc_matrix:
    """Lumped (diagonal) mass matrix, equal to ``igl.massmatrix``.

    kind: ``"voronoi"`` (default): mixed Voronoi areas (Meyer et al. 2003): the Voronoi cell
    inside non-obtuse triangles; an obtuse triangle gives half its area to the obtuse corner
    and a quarter to each other one (``igl.MASSMATRIX_TYPE_VORONOI``). ``"barycentric"``: a
    third of every incident triangle's area (``igl.MASSMATRIX_TYPE_BARYCENTRIC``).

    V: (n, 3) float array. F: (m, 3) int array. Returns an (n, n) diagonal
    ``scipy.sparse.csc_matrix`` whose diagonal sums to the surface area (0 for unused vertices).

    Raises InputError for bad (V, F) or an unknown kind.
    """
    return _csc(_geometry.mass_matrix(V, F, kind))


@positional_options("kind")
def vertex_areas(V: ArrayLike, F: ArrayLike, *, kind: str = "voronoi") -> FloatArray:
    """The diagonal of :func:`mass_matrix` as an (n,) float array (same ``kind`` options).

    Raises InputError for bad (V, F) or an unknown kind.
    """
    return _geometry.vertex_areas(V, F, kind)


def gaussian_curvature(V: ArrayLike, F: ArrayLike, *, pointwise: bool = False, boundary: str = "full_turn",
                       area: str = "voronoi") -> FloatArray:
    """Discrete Gaussian curvature as angle defect (§1.2.4: ``K = (2 pi - sum_i alpha_i) / A``).

    By default the integrated curvature ``2 pi - sum(theta)`` of the corner angles theta at each
    vertex, equal to ``igl.gaussian_curvature``; on a closed mesh ``sum(K) = 2 pi chi``
    (Gauss-Bonnet).

    boundary: ``"full_turn"`` (default, libigl's rule): ``2 pi - sum(theta)`` at boundary
    vertices too. ``"half_turn"``: ``pi - sum(theta)`` at boundary vertices (those on an edge of
    exactly one triangle), i.e. the boundary's discrete geodesic curvature is included, so
    ``sum(K) = 2 pi chi`` holds on meshes with boundary too.
    pointwise: divide by the vertex area of ``area`` (``"voronoi"`` mixed area by default, or
    ``"barycentric"``) to get curvature per unit area (0 where the area is 0).

    Units: the default (integrated) value is an angle in radians, dimensionless (the same on a
    scaled copy of the mesh); the pointwise value is per unit area, 1/length² (1/r² on a
    sphere of radius r). ``meshsmith curvature --kind gaussian`` writes the integrated value
    too, and the pointwise one with ``--pointwise``.

    V: (n, 3) float array. F: (m, 3) int array. Returns an (n,) float array. A vertex used by
    no face has angle sum 0: integrated value 2 pi (as libigl), pointwise value 0.

    Raises InputError for bad (V, F) or an unknown option.
    """
    return _geometry.gaussian_curvature(V, F, boundary, bool(pointwise), area)


def mean_curvature(V: ArrayLike, F: ArrayLike, *, area: str = "voronoi") -> MeanCurvature:
    """Mean curvature H and the mean-curvature normal Hn from the cotangent Laplacian (§1.2.4).

    ``Hn = -1/2 M^-1 L V`` with L = :func:`cotan_laplacian` and M = :func:`mass_matrix` of kind
    ``area``, since the Laplace-Beltrami operator of the positions is ``-2 H n``. H is ``|Hn|``
    signed by ``Hn . n`` with n the angle-weighted vertex normal: H > 0 on a sphere with
    outward normals (H = 1/r), and Hn then points outward.

    V: (n, 3) float array. F: (m, 3) int array. Returns a :class:`MeanCurvature` ``(H, Hn)``:
    (n,) and (n, 3) float arrays, per unit length (pointwise, not integrated). Vertices with zero area get 0. At boundary vertices ``L V`` holds a boundary term,
    so the values there do not estimate the surface's curvature.

    Raises InputError for bad (V, F) or an unknown area kind.
    """
    H, Hn = _geometry.mean_curvature(V, F, area)
    return MeanCurvature(H, Hn)


def principal_curvatures(V: ArrayLike, F: ArrayLike, *, method: str = "quadric_fit") -> PrincipalCurvatures:
    """Principal curvatures k1 >= k2 and their unit directions at every vertex (§1.2.1).

    method:

    * ``"quadric_fit"`` (default): a height function ``z = a x^2 + b xy + c y^2 + d x + e y``
      fitted by least squares, in the tangent frame of the angle-weighted vertex normal, to
      the vertex's 2-ring (grown to at most 4 rings until it holds 8 neighbours); k1, k2 and
      the directions are the eigenpairs of its shape operator. Converges as O(h^2) on spheres
      and tori, regular or not.
    * ``"shape_operator"``: per-face second fundamental forms fitted to the change of the
      vertex normals along the edges, averaged at each vertex with mixed-Voronoi corner
      weights (Rusinkiewicz 2004). O(h^2) on regular meshes, but it inherits the O(h) error
      of vertex normals on irregular ones (about 2% on subdivided icospheres at any level).
    * ``"mean_gaussian"``: ``k = H +- sqrt(max(H**2 - K, 0))`` from :func:`mean_curvature`
      and the pointwise :func:`gaussian_curvature` (Meyer et al. 2003), with the directions of
      ``"shape_operator"``; exact at umbilics (spheres), but the square root amplifies errors
      where k1 is close to k2.

    ``igl.principal_curvature`` fits quadrics over a neighbourhood of radius 5 (Panozzo et al.
    2010): smoother on noisy scans, but on coarse smooth meshes it errs by about 10% (a
    1280-face icosphere) and 5% (a 128x64 torus), where ``"quadric_fit"`` errs by about 2% and
    1%. The signs agree: positive where the surface bends away from its outward normal.

    V: (n, 3) float array. F: (m, 3) int array. Returns a :class:`PrincipalCurvatures`
    ``(k1, k2, d1, d2)``: (n,), (n,), (n, 3), (n, 3) float arrays, k1 and k2 per unit length; d1, d2 are unit vectors tangent to the vertex normal n, with
    d2 = n x d1. Vertices without a usable neighbourhood (unused, fewer than 5 neighbours,
    only degenerate faces) get zeros.

    Raises InputError for bad (V, F) or an unknown method.
    """
    k1, k2, d1, d2 = _geometry.principal_curvatures(V, F, method)
    return PrincipalCurvatures(k1, k2, d1, d2)


def laplacian_eigenpairs(V: ArrayLike, F: ArrayLike, k: int, *, mass: str = "voronoi",
                         progress: ProgressCallback = None) -> Eigenpairs:
    """The k smallest eigenpairs of ``-L u = lambda M u`` (the mesh's Laplace-Beltrami spectrum).

    L = :func:`cotan_laplacian`, M = :func:`mass_matrix` of kind ``mass``. Solved with Spectra's
    Lanczos iteration in shift-and-invert mode, the shifted matrix factorised once by CHOLMOD.
    On a unit sphere the eigenvalues approach l (l + 1) with multiplicity 2 l + 1.

    V: (n, 3) float array. F: (m, 3) int array. k: 1 <= k < n. progress: optional callable
    ``(fraction, stage) -> bool``; returning False raises :class:`meshsmith.Cancelled`.
    Returns an :class:`Eigenpairs` ``(values, vectors)``: (k,) ascending eigenvalues (the first ~0 on a connected
    mesh) and an (n, k) array of M-orthonormal eigenvectors (``U.T @ M @ U = I``), each signed
    so that its largest-magnitude entry is positive.

    Raises InputError for bad (V, F), k out of range, or a vertex with zero area (M must be
    positive definite: remove unreferenced vertices first); SolverError if the factorisation
    or the iteration fails.
    """
    values, vectors = _geometry.laplacian_eigenpairs(V, F, k, mass, progress)
    return Eigenpairs(values, vectors)
