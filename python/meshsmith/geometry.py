"""Geometry chapter (§1.2, §3.0.2): measures and discrete differential geometry of triangle meshes.

Areas and volume; face and vertex normals; uniform, cotangent and mean-value Laplacians; mass
matrices; Gaussian, mean and principal curvatures; Laplacian eigenpairs; per-triangle distortion of a parametrization; exact point-to-surface
distances, Hausdorff and mean surface distance. (Discrete curves are
in :mod:`meshsmith.curves`.)

Conventions follow libigl so results compare one to one: the Laplacians are
``L_ii = -sum_j L_ij`` (the cotangent Laplacian is negative semi-definite), sparse matrices come
back as ``scipy.sparse.csc_matrix`` with sorted indices, and curvature is positive where the
surface bends away from its outward normal (a sphere of radius r has H = 1/r, K = 1/r**2).

Every function validates its input in the C++ core and raises :class:`meshsmith.InputError`
(a ``ValueError``) for a wrong shape or dtype, NaN/Inf coordinates, an index outside
``[0, n)``, an empty array or an unknown option. Degenerate (zero-area) triangles never
produce NaN: their normals are zero and their cotangents are set to zero, so they contribute
nothing.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse

from ._core import InputError
from ._core import core as _core_checks
from ._core import geometry as _geometry

__all__ = [
    "face_areas",
    "surface_area",
    "volume",
    "face_normals",
    "vertex_normals",
    "cotan_laplacian",
    "uniform_laplacian",
    "mean_value_laplacian",
    "mass_matrix",
    "vertex_areas",
    "gaussian_curvature",
    "mean_curvature",
    "principal_curvatures",
    "laplacian_eigenpairs",
    "TriangleDistortion",
    "triangle_distortion",
    "SurfaceDistance",
    "hausdorff_distance",
    "mean_surface_distance",
]


def face_areas(V, F) -> np.ndarray:
    """Area of each triangle, ``|(v1 - v0) x (v2 - v0)| / 2`` (libigl's ``doublearea / 2``).

    V: (n, 3) float array of positions, F: (m, 3) integer array of triangles.
    Returns an (m,) float64 array (0 for degenerate faces).
    Raises InputError for bad input (empty, out-of-range index, NaN/Inf).
    """
    return _geometry.face_areas(V, F)


def surface_area(V, F) -> float:
    """Total area of the triangles of (V, F), summed in a fixed order (deterministic).

    Raises InputError as :func:`face_areas`.
    """
    return float(_geometry.surface_area(V, F))


def volume(V, F) -> float:
    """Signed volume enclosed by a closed surface (divergence theorem).

    Sum over faces of ``v0 . (v1 x v2) / 6``: positive when the faces are counter-clockwise seen
    from outside (outward normals), negative when inward. For an open or inconsistently oriented
    mesh the value depends on the origin and is not a volume.
    V: (n, 3) float array, F: (m, 3) integer array. Raises InputError as :func:`face_areas`.
    """
    return float(_geometry.volume(V, F))

def _csc(parts) -> scipy.sparse.csc_matrix:
    data, indices, indptr, rows, cols = parts
    return scipy.sparse.csc_matrix((data, indices, indptr), shape=(rows, cols))


def face_normals(V, F) -> np.ndarray:
    """Unit normals of the faces: ``(p1 - p0) x (p2 - p0)`` normalised.

    V: (n, 3) float array of vertex positions. F: (m, 3) int array of triangles,
    counter-clockwise seen from outside. Returns an (m, 3) float array. A degenerate face
    (twice its area <= 8 eps (longest edge)**2: a repeated vertex or collinear corners) gets
    the zero vector. Equals ``igl.per_face_normals`` on non-degenerate faces.

    Raises InputError for bad (V, F).
    """
    return _geometry.face_normals(V, F)


def vertex_normals(V, F, weighting: str = "angle") -> np.ndarray:
    """Unit vertex normals: the weighted sum of the incident face normals, normalised (§1.2.4).

    V: (n, 3) float array. F: (m, 3) int array. weighting: ``"uniform"`` (each incident face
    once), ``"area"`` (by face area) or ``"angle"`` (by the corner angle; the default). Returns
    an (n, 3) float array equal to ``igl.per_vertex_normals`` with the matching
    ``PER_VERTEX_NORMALS_WEIGHTING_TYPE_*``. Degenerate faces contribute nothing; a vertex
    used by no face (or whose face normals cancel exactly) gets the zero vector, never NaN.

    Raises InputError for bad (V, F) or an unknown weighting.
    """
    return _geometry.vertex_normals(V, F, weighting)


def cotan_laplacian(V, F) -> scipy.sparse.csc_matrix:
    """Cotangent Laplacian (§3.0.2 cot-weights), libigl's sign: negative semi-definite.

    ``L[i, j] = (cot(alpha_ij) + cot(beta_ij)) / 2`` for every edge ij (one cotangent on a
    boundary edge), ``L[i, i] = -sum_j L[i, j]``. Symmetric, with linear precision: on a planar
    mesh ``L @ f`` vanishes at interior vertices for every linear function f.

    V: (n, 3) float array. F: (m, 3) int array. Returns an (n, n) ``scipy.sparse.csc_matrix``
    equal to ``igl.cotmatrix``. Every column stores its diagonal (0 for an unused vertex). The
    cotangents of a degenerate triangle (twice its area <= 8 eps (longest edge)**2) are set to
    zero instead of +-inf, so such a triangle contributes nothing.

    Raises InputError for bad (V, F).
    """
    return _csc(_geometry.cotan_laplacian(V, F))


def uniform_laplacian(first, second=None, *, normalized: bool = False) -> scipy.sparse.csc_matrix:
    """Graph Laplacian with uniform weights (§3.0.2): ``L[i, j] = 1`` per edge, ``L[i, i] = -deg(i)``.

    Call as ``uniform_laplacian(F, n)`` (F: (m, 3) int array, n: the number of vertices,
    default ``F.max() + 1``) or as ``uniform_laplacian(V, F)`` like the other Laplacians (V:
    (n, 3) float array, validated together with F, only its length is used). With
    ``normalized=True`` each row is divided by the vertex degree: ``L[i, j] = 1/|N1(i)|``,
    ``L[i, i] = -1`` (the umbrella operator; not symmetric). Returns an (n, n)
    ``scipy.sparse.csc_matrix``; a vertex used by no face has a zero row and column.

    Raises InputError for an empty F, n < 1, an index of F outside ``[0, n)``, or bad V.
    """
    if second is not None and np.ndim(second) == 2:  # (V, F)
        V, F = first, second
        _core_checks.validate_mesh(V, F)
        n = len(V)
    else:
        F, n = first, second
        if n is None:
            faces = np.asarray(F)
            n = int(faces.max()) + 1 if faces.size and np.issubdtype(faces.dtype, np.integer) else 1
    return _csc(_geometry.uniform_laplacian(F, int(n), bool(normalized)))


def mean_value_laplacian(V, F) -> scipy.sparse.csc_matrix:
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


def mass_matrix(V, F, kind: str = "voronoi") -> scipy.sparse.csc_matrix:
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


def vertex_areas(V, F, kind: str = "voronoi") -> np.ndarray:
    """The diagonal of :func:`mass_matrix` as an (n,) float array (same ``kind`` options).

    Raises InputError for bad (V, F) or an unknown kind.
    """
    return _geometry.vertex_areas(V, F, kind)


def gaussian_curvature(V, F, *, pointwise: bool = False, boundary: str = "full_turn",
                       area: str = "voronoi") -> np.ndarray:
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

    V: (n, 3) float array. F: (m, 3) int array. Returns an (n,) float array. A vertex used by
    no face has angle sum 0: integrated value 2 pi (as libigl), pointwise value 0.

    Raises InputError for bad (V, F) or an unknown option.
    """
    return _geometry.gaussian_curvature(V, F, boundary, bool(pointwise), area)


def mean_curvature(V, F, *, area: str = "voronoi") -> tuple[np.ndarray, np.ndarray]:
    """Mean curvature H and the mean-curvature normal Hn from the cotangent Laplacian (§1.2.4).

    ``Hn = -1/2 M^-1 L V`` with L = :func:`cotan_laplacian` and M = :func:`mass_matrix` of kind
    ``area``, since the Laplace-Beltrami operator of the positions is ``-2 H n``. H is ``|Hn|``
    signed by ``Hn . n`` with n the angle-weighted vertex normal: H > 0 on a sphere with
    outward normals (H = 1/r), and Hn then points outward.

    V: (n, 3) float array. F: (m, 3) int array. Returns ``(H, Hn)``: (n,) and (n, 3) float
    arrays. Vertices with zero area get 0. At boundary vertices ``L V`` holds a boundary term,
    so the values there do not estimate the surface's curvature.

    Raises InputError for bad (V, F) or an unknown area kind.
    """
    H, Hn = _geometry.mean_curvature(V, F, area)
    return H, Hn


def principal_curvatures(V, F, *, method: str = "quadric_fit"
                         ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
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

    V: (n, 3) float array. F: (m, 3) int array. Returns ``(k1, k2, d1, d2)``: (n,), (n,),
    (n, 3), (n, 3) float arrays; d1, d2 are unit vectors tangent to the vertex normal n, with
    d2 = n x d1. Vertices without a usable neighbourhood (unused, fewer than 5 neighbours,
    only degenerate faces) get zeros.

    Raises InputError for bad (V, F) or an unknown method.
    """
    k1, k2, d1, d2 = _geometry.principal_curvatures(V, F, method)
    return k1, k2, d1, d2


def laplacian_eigenpairs(V, F, k: int, *, mass: str = "voronoi", progress=None
                         ) -> tuple[np.ndarray, np.ndarray]:
    """The k smallest eigenpairs of ``-L u = lambda M u`` (the mesh's Laplace-Beltrami spectrum).

    L = :func:`cotan_laplacian`, M = :func:`mass_matrix` of kind ``mass``. Solved with Spectra's
    Lanczos iteration in shift-and-invert mode, the shifted matrix factorised once by CHOLMOD.
    On a unit sphere the eigenvalues approach l (l + 1) with multiplicity 2 l + 1.

    V: (n, 3) float array. F: (m, 3) int array. k: 1 <= k < n. progress: optional callable
    ``(fraction, stage) -> bool``; returning False raises :class:`meshsmith.Cancelled`.
    Returns ``(values, vectors)``: (k,) ascending eigenvalues (the first ~0 on a connected
    mesh) and an (n, k) array of M-orthonormal eigenvectors (``U.T @ M @ U = I``), each signed
    so that its largest-magnitude entry is positive.

    Raises InputError for bad (V, F), k out of range, or a vertex with zero area (M must be
    positive definite: remove unreferenced vertices first); SolverError if the factorisation
    or the iteration fails.
    """
    return _geometry.laplacian_eigenpairs(V, F, int(k), mass, progress)

@dataclass(frozen=True)
class TriangleDistortion:
    """Distortion of the map from each parameter (UV) triangle onto its 3D triangle.

    m = number of faces, n = number of vertices. Every measure is 1 for an isometry.

    Per face:
      jacobians (m, 2, 2): J of the affine map UV -> 3D triangle, in the orthonormal frame
        (x, y) of the 3D triangle (x along v1 - v0, y = n x x), so det J < 0 iff the UV triangle
        is clockwise.
      singular_values (m, 2): sigma1 >= sigma2 >= 0 of J (J^T J is the first fundamental form).
      isometric (m,): symmetric Dirichlet energy normalised to 1 at isometries,
        (s1^2 + s2^2 + s1^-2 + s2^-2) / 4.
      conformal (m,): s1 / s2 (1 for a conformal map).
      area (m,): s1 * s2 = 3D area / UV area (1 for an equiareal map).
      stretch_l2 (m,): sqrt((s1^2 + s2^2) / 2), Sander et al.'s L2 stretch (§5's s_Delta).
      stretch_linf (m,): s1, Sander et al.'s L-infinity stretch.
      flipped (m,) bool: det J < 0 (UV triangle orientation reversed).
      surface_areas (m,): 3D triangle areas (the averaging weights).
      parameter_areas (m,): signed UV triangle areas (negative when flipped).
    Per vertex (n,), area-weighted averages over the incident faces (weights = 3D areas, §5
    s_{p_i}): vertex_isometric, vertex_conformal, vertex_area, vertex_stretch_l2,
    vertex_stretch_linf. NaN for a vertex with no incident face of positive 3D area.
    Global:
      global_stretch_l2: sqrt(sum A s^2 / sum A) (1 for an isometry).
      normalized_global_stretch_l2: global_stretch_l2 * sqrt(sum |UV area| / sum A), invariant
        to a uniform scale of UV (1 for an isometry up to scale).
      global_stretch_linf: max s1.
      (The three global values are NaN only when no face has positive 3D area.)
    Index lists (int64, ascending): flipped_faces; degenerate_parameter_faces (UV area exactly 0
    with positive 3D area: J, sigma and every measure are +inf there, and so are the averages
    touching them); degenerate_surface_faces (3D area 0: sigma2 = 0, conformal and isometric
    +inf, area 0; weight 0, so left out of every average; never flipped).
    """

    jacobians: np.ndarray
    singular_values: np.ndarray
    isometric: np.ndarray
    conformal: np.ndarray
    area: np.ndarray
    stretch_l2: np.ndarray
    stretch_linf: np.ndarray
    flipped: np.ndarray
    surface_areas: np.ndarray
    parameter_areas: np.ndarray
    vertex_isometric: np.ndarray
    vertex_conformal: np.ndarray
    vertex_area: np.ndarray
    vertex_stretch_l2: np.ndarray
    vertex_stretch_linf: np.ndarray
    global_stretch_l2: float
    normalized_global_stretch_l2: float
    global_stretch_linf: float
    flipped_faces: np.ndarray
    degenerate_parameter_faces: np.ndarray
    degenerate_surface_faces: np.ndarray


def triangle_distortion(V, F, UV) -> TriangleDistortion:
    """Distortion of the parametrization UV of the mesh (V, F), per triangle and per vertex.

    The map of each triangle goes from its UV triangle to its 3D triangle (§5: the Jacobian of
    that affine map, its singular values sigma1 >= sigma2 and the isometric / conformal /
    equiareal measures; §1.2.2: J^T J is the first fundamental form).

    V: (n, 3) float array of surface positions. F: (m, 3) integer array of triangles.
    UV: (n, 2) float array of parameter positions, one per vertex.
    Returns a :class:`TriangleDistortion` (see its docstring for every field and for how
    degenerate UV triangles (+inf, listed) and degenerate 3D triangles (weight 0) are reported).
    Raises InputError for a bad mesh (empty, NaN/Inf, index out of range), UV of the wrong shape,
    UV with a NaN/Inf, or UV with a number of rows other than n.
    """
    return TriangleDistortion(**_geometry.triangle_distortion(V, F, UV))


class SurfaceDistance:
    """Exact point-to-surface distances to a triangle mesh, with an AABB tree built once.

    ``SurfaceDistance(V, F, leaf_size=4)``: V (n, 3) float array, F (m, 3) integer array (both
    copied); the tree splits the triangles at the median centroid along the longest axis, down
    to ``leaf_size`` triangles per leaf. Build once, then query many times; queries run in
    parallel and give the same result for any thread count.
    Raises InputError for a bad mesh (empty, NaN/Inf, index out of range) or leaf_size < 1.
    """

    def __init__(self, V, F, leaf_size: int = 4):
        self._tree = _geometry.SurfaceDistance(V, F, leaf_size)

    @property
    def face_count(self) -> int:
        """Number of triangles in the tree."""
        return int(self._tree.face_count)

    def closest_points(self, Q, progress=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Closest surface point of each query point.

        Q: (k, 3) float array (k may be 0). progress: optional ``(fraction, stage) -> bool``.
        Returns ``(distance, face, point)``: (k,) float64 Euclidean distances, (k,) int64 index
        of a nearest face (the first found when several are equally near, e.g. at a shared
        vertex), (k, 3) float64 closest points. Same distances as libigl's
        ``point_mesh_squared_distance`` (which returns squared ones); where a query is equally
        near to several surface points (inside a convex corner, on a medial axis) the face and
        point may be another of them.
        Raises InputError for Q of the wrong shape or with a NaN/Inf.
        """
        return self._tree.closest_points(Q, progress)

    def distances(self, Q, progress=None) -> np.ndarray:
        """(k,) float64 distances from the rows of Q (k, 3) to the surface; as closest_points."""
        return self._tree.distances(Q, progress)


def _sampling(sampled: bool, samples_per_face: int) -> int:
    if not sampled:
        return 0
    if isinstance(samples_per_face, bool) or not isinstance(samples_per_face, (int, np.integer)) \
            or samples_per_face < 1:
        raise InputError(f"samples_per_face must be an integer >= 1, got {samples_per_face!r}")
    return int(samples_per_face)


def hausdorff_distance(VA, FA, VB, FB, *, sampled: bool = False, samples_per_face: int = 16,
                       seed: int = 0, one_sided: bool = False, progress=None):
    """Symmetric Hausdorff distance between the surfaces (VA, FA) and (VB, FB).

    Each one-sided distance is the maximum, over sample points of one surface, of the exact
    distance to the other surface (closest point on its triangles, AABB tree):

    - ``sampled=False`` (default): the samples are the vertices, so the result is
      ``max(max_a d(a, B), max_b d(b, A))`` over the vertex rows, exactly what libigl's
      ``hausdorff`` computes (a lower bound of the true Hausdorff distance).
    - ``sampled=True``: the vertices plus ``samples_per_face`` points per face, uniform in each
      triangle from a hash of (seed, face, sample): a tighter (larger) lower bound that tends to
      the true Hausdorff distance as samples_per_face grows. Deterministic for a given seed.
      m * samples_per_face may be at most 2^27 per mesh (a bound on memory).

    VA, VB: (n, 3) float arrays; FA, FB: (m, 3) integer arrays.
    Returns the distance (float), or with ``one_sided=True`` the tuple
    ``(symmetric, a_to_b, b_to_a)``. Raises InputError for a bad mesh (the message names VA, FA,
    VB or FB for a wrong shape or dtype, "mesh A" or "mesh B" for bad values) or
    samples_per_face < 1 with sampled=True.
    """
    result = _geometry.hausdorff_distance(VA, FA, VB, FB, _sampling(sampled, samples_per_face),
                                          int(seed) % 2**64, progress)
    return tuple(float(x) for x in result) if one_sided else float(result[0])


def mean_surface_distance(VA, FA, VB, FB, *, sampled: bool = False, samples_per_face: int = 16,
                          seed: int = 0, one_sided: bool = False, progress=None):
    """Mean distance between the surfaces (VA, FA) and (VB, FB), area-weighted.

    The one-sided value a_to_b approximates ``(1/|A|) * integral over A of d(x, B)``:

    - ``sampled=False`` (default): the vertices of A weighted by their lumped (barycentric)
      area ``sum of A_f / 3`` over the incident faces (unreferenced vertices weigh 0);
    - ``sampled=True``: ``samples_per_face`` points per face of A, uniform in the triangle
      (hash of seed, face, sample), each weighted by ``A_f / samples_per_face`` (the vertices
      are then not used): a Monte-Carlo estimate of the integral.

    The symmetric value is ``(|A| a_to_b + |B| b_to_a) / (|A| + |B|)``, the mean over both
    surfaces together. Returns that float, or with ``one_sided=True`` the tuple
    ``(symmetric, a_to_b, b_to_a)``. Raises InputError as :func:`hausdorff_distance`, and when a
    surface has zero total area.
    """
    result = _geometry.mean_surface_distance(VA, FA, VB, FB, _sampling(sampled, samples_per_face),
                                             int(seed) % 2**64, progress)
    return tuple(float(x) for x in result) if one_sided else float(result[0])
