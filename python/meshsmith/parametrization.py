"""Parametrization chapter (curriculum §5, §5.1): boundary maps, harmonic and Tutte maps,
stretch-minimizing maps, least-squares conformal maps, ABF and ABF++, and the shared pieces
(cutting a mesh to a disk, checking a map is bijective).

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); UV coordinates come back as
float64 (n, 2). Bad input raises :class:`meshsmith.InputError`.
"""
from __future__ import annotations

import numpy as np

from ._core import InputError
from ._core import parametrization as _core

__all__: list[str] = []

# ---------------------------------------------------------------------------------------------
# Boundary maps, harmonic maps, stretch-minimizing maps, LSCM, cut to disk, bijectivity (§5.1.1–2)
# ---------------------------------------------------------------------------------------------

from dataclasses import dataclass  # noqa: E402

__all__ += ["map_boundary", "harmonic", "StretchResult", "stretch_minimizing", "lscm", "default_lscm_pins",
            "lscm_spectral", "CutMesh", "cut_to_disk", "BijectivityReport", "check_bijectivity",
            "is_bijective", "PARAMETRIZATION_METHODS", "Parametrization", "parametrize"]


def map_boundary(V, F, shape: str = "circle", boundary=None) -> tuple[np.ndarray, np.ndarray]:
    """Map a boundary loop onto a convex polygon with arc-length spacing (§5, §5.1.1 step 1).

    V: (n, 3) float array, F: (m, 3) integer array.
    shape: "circle" (the unit circle, starting at (1, 0), counter-clockwise: exactly libigl's
        ``map_vertices_to_circle``) or "square" (the unit square [0, 1]^2 from (0, 0),
        counter-clockwise; the loop vertices nearest each quarter of the arc length are the corners).
    boundary: (b,) vertex indices of an ordered loop; default: the longest boundary loop of F,
        walked along the faces' orientation (so the map keeps triangles counter-clockwise).
    Returns (boundary_indices (b,) int64, boundary_uv (b, 2) float64).
    Raises InputError for a mesh that is not a clean, connected, oriented manifold with a boundary
    (a closed mesh: cut it with :func:`cut_to_disk`), or a bad loop.
    """
    return _core.map_boundary(V, F, shape, boundary)


def harmonic(V, F, boundary=None, boundary_uv=None, weights: str = "uniform", *,
             shape: str = "circle") -> np.ndarray:
    """Harmonic parametrization with a fixed boundary (§5.1.1): sum_j w_ij (u_j - u_i) = 0 inside.

    V: (n, 3) float array, F: (m, 3) integer array.
    boundary: (b,) fixed vertex indices; default: the longest boundary loop (the mesh must then be
        a topological disk). boundary_uv: (b, 2) their positions; default: `boundary` taken as an
        ordered loop mapped onto `shape` ("circle" or "square") by :func:`map_boundary`.
    weights: "uniform" (Tutte's embedding), "cotan" (the discrete harmonic map; the same as
        ``igl.harmonic(V, F, b, bc, 1)``) or "mean_value" (Floater). Uniform and mean-value
        weights are positive, so the map is bijective on a convex boundary; cotan may fold.
    Returns UV, (n, 2) float64.
    Raises InputError for bad input (non-disk without an explicit boundary, non-manifold,
    several components, isolated vertices, zero-area faces, bad boundary arrays); SolverError if
    the system is singular.
    """
    return _core.harmonic(V, F, boundary, boundary_uv, weights, shape)


@dataclass(frozen=True)
class StretchResult:
    """The result of :func:`stretch_minimizing`.

    uv: (n, 2) float64, the map of lowest stretch met; stretch: (k,) float64, Sander et al.'s
    scale-invariant L2 stretch (1 for an isometry up to scale) of the harmonic start (entry 0)
    and after every reweighting step; best_iteration: the index into `stretch` of `uv`.
    """

    uv: np.ndarray
    stretch: np.ndarray
    best_iteration: int


def stretch_minimizing(V, F, iterations: int = 10, *, weights: str = "mean_value", shape: str = "circle",
                       progress=None) -> StretchResult:
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
    return StretchResult(**_core.stretch_minimizing(V, F, iterations, weights, shape, progress))


def lscm(V, F, pinned=None, pinned_uv=None) -> np.ndarray:
    """Least-squares conformal map with pinned vertices (§5.1.2; Lévy et al. 2002).

    Minimizes sum over triangles of A |grad v - R90 grad u|^2 (twice the conformal energy
    Dirichlet - signed area) with a free boundary. Equal to ``igl.lscm(V, F, pinned, pinned_uv)``.

    V: (n, 3) float array, F: (m, 3) integer array (connected, oriented manifold with a boundary).
    pinned: (p,) p >= 2 vertex indices; pinned_uv: (p, 2) their positions (not all equal).
    Default (both None; the mesh must then be a disk): the two boundary vertices farthest apart
    (a double sweep on the longest loop) at (0, 0) and (their 3D distance, 0) — see
    :func:`default_lscm_pins`.
    Returns UV, (n, 2) float64, triangles counter-clockwise. Raises InputError for bad input
    (closed: cut with :func:`cut_to_disk`; non-manifold, several components, isolated vertices,
    zero-area faces, bad pins); SolverError if the system is singular.
    """
    return _core.lscm(V, F, pinned, pinned_uv)


def default_lscm_pins(V, F) -> tuple[np.ndarray, np.ndarray]:
    """The pins :func:`lscm` uses when none are given: (indices (2,) int64, uv (2, 2) float64)."""
    return _core.default_lscm_pins(V, F)


def lscm_spectral(V, F) -> np.ndarray:
    """Spectral conformal parametrization: LSCM with a free boundary and no pins (Mullen et al. 2008).

    The generalized eigenvector x of Q x = lambda B x (Q: the LSCM/conformal energy matrix,
    B: lumped boundary lengths) with the smallest lambda once translations are removed, found
    with Spectra's shift-invert Lanczos. Centred at the origin, scaled to the surface's area,
    triangles counter-clockwise; unique up to a rotation.

    V: (n, 3) float array, F: (m, 3) integer array (connected, oriented manifold with a boundary).
    Returns UV, (n, 2) float64. Raises InputError as :func:`lscm`; SolverError if the
    eigensolver fails.
    """
    return _core.lscm_spectral(V, F)


@dataclass(frozen=True)
class CutMesh:
    """A mesh cut open into a topological disk (:func:`cut_to_disk`).

    V: (k, 3) float64 positions, V[i] == input V[vertex_origin[i]]; F: (m, 3) int64, face f is
    the input face f on the copies of its corners; vertex_origin: (k,) int64, the input vertex of
    each output vertex (the first n entries are 0..n-1; seam copies are appended);
    seam_edges: (c, 2) int64 input edges (i < j) cut open (empty for a disk).
    """

    V: np.ndarray
    F: np.ndarray
    vertex_origin: np.ndarray
    seam_edges: np.ndarray

    def __iter__(self):
        """Unpacks as ``V_cut, F_cut, seam = cut_to_disk(V, F)`` (seam: this object)."""
        return iter((self.V, self.F, self))


def cut_to_disk(V, F) -> CutMesh:
    """Cut a closed or higher-genus surface into one topological disk (§5.2.2 step 2).

    A breadth-first spanning tree of the triangles (across edges) is grown from face 0; the edges
    it never crosses, pruned of dangling branches, are the 2g handle loops plus the paths joining
    the boundary loops: the seam. A closed genus-0 mesh is cut along the shortest edge path
    between two far-apart vertices. A disk comes back unchanged.

    V: (n, 3) float array, F: (m, 3) integer array.
    Returns a :class:`CutMesh`; it unpacks as ``V_cut, F_cut, seam`` (``seam.seam_edges``,
    ``seam.vertex_origin``).
    Raises InputError for a mesh that is non-manifold, not oriented, has several components,
    isolated vertices or zero-area / repeated-index faces.
    """
    return CutMesh(**_core.cut_to_disk(V, F))


@dataclass(frozen=True)
class BijectivityReport:
    """The verdict of :func:`check_bijectivity`.

    bijective: bool; orientation: +1 (all triangles counter-clockwise), -1 (all clockwise) or 0;
    degenerate_faces: (k,) int64 faces with collinear UV corners; flipped_faces: (k,) int64 faces
    oriented against the majority; crossing_boundary_sides: (k, 2) int64 pairs of boundary sides
    (3 * face + corner, the side from corner to the next) whose UV segments intersect (at most 100).
    """

    bijective: bool
    orientation: int
    degenerate_faces: np.ndarray
    flipped_faces: np.ndarray
    crossing_boundary_sides: np.ndarray


def check_bijectivity(UV, F) -> BijectivityReport:
    """Check that the parametrization UV of F is one-to-one, and say why not.

    A disk map is bijective iff every UV triangle keeps one orientation (none flipped, none
    degenerate) and the boundary polygon is simple (no two boundary edges meet except
    consecutive ones at their shared vertex, without folding back). Exact orientation predicates
    decide every case; boundary edges are paired by a box-intersection sweep. With several
    boundary loops each must be simple and no two may meet.

    UV: (n, 2) float array, F: (m, 3) integer array. Returns a :class:`BijectivityReport`.
    Raises InputError for an empty F, an index outside UV or a NaN/Inf in UV.
    """
    return BijectivityReport(**_core.check_bijectivity(UV, F))


def is_bijective(UV, F) -> bool:
    """True when the parametrization UV of F is one-to-one (see :func:`check_bijectivity`)."""
    return check_bijectivity(UV, F).bijective



#: The methods :func:`parametrize` knows, with what each one computes.
PARAMETRIZATION_METHODS = {
    "tutte": "Tutte's embedding: harmonic map with uniform weights on a circle (§5.1.1)",
    "harmonic": "harmonic map with cotangent weights on a circle (§5.1.1)",
    "stretch": "stretch-minimizing map from the mean-value harmonic map (§5.1.1)",
    "lscm": "least-squares conformal map with two far-apart pins (§5.1.2)",
    "abf": "angle-based flattening (§5.1.3)",
    "abf++": "ABF++, the reduced-system Newton solver of ABF (§5.1.3)",
}


@dataclass(frozen=True)
class Parametrization:
    """A parametrization made by :func:`parametrize`, with its quality.

    V, F: the mesh the texture coordinates belong to (the input, or the input cut to a disk);
    uv: (k, 2) float64, one row per vertex of V; cut: the :class:`CutMesh` when the input had to
    be cut, else None (then V, F are the input); method: the method's name; distortion: the
    :class:`meshsmith.geometry.TriangleDistortion` of the map; bijective: :func:`is_bijective`.
    """

    V: np.ndarray
    F: np.ndarray
    uv: np.ndarray
    cut: CutMesh | None
    method: str
    distortion: object
    bijective: bool

    def summary(self) -> dict[str, object]:
        """Area-weighted mean angle distortion (sigma1/sigma2), mean area distortion
        (max(a, 1/a) of the map scaled to the surface's area), Sander's normalized L2 stretch,
        flipped triangles and bijectivity, as a dict of plain numbers."""
        d = self.distortion
        weights = d.surface_areas
        scale = weights.sum() / np.abs(d.parameter_areas).sum()
        area = d.area / scale  # 3D area / UV area with the UV scaled to the surface's area
        finite = np.isfinite(d.conformal) & (weights > 0)
        return {"method": self.method,
                "angle distortion (mean sigma1/sigma2)": float(np.average(d.conformal[finite], weights=weights[finite])),
                "area distortion (mean max(a, 1/a))": float(np.average(np.maximum(area, 1 / area)[finite],
                                                                        weights=weights[finite])),
                "stretch (Sander L2, 1 = isometry)": float(d.normalized_global_stretch_l2),
                "flipped triangles": int(len(d.flipped_faces)),
                "bijective": bool(self.bijective),
                "seam edges": 0 if self.cut is None else int(len(self.cut.seam_edges))}


def parametrize(V, F, method: str = "lscm", *, progress=None) -> Parametrization:
    """Parametrize any clean manifold mesh with one of :data:`PARAMETRIZATION_METHODS`.

    A mesh that is not a topological disk (closed, higher genus, several holes) is first cut
    with :func:`cut_to_disk`. "abf" / "abf++" use :func:`abf` when it is available.
    V: (n, 3) float array, F: (m, 3) integer array; progress: optional callback (stretch only).
    Returns a :class:`Parametrization`. Raises InputError for an unknown method or bad input
    (see :func:`cut_to_disk`), and when ABF is asked for but not available.
    """
    from . import geometry, topology
    if method not in PARAMETRIZATION_METHODS:
        raise InputError(f"unknown parametrization method {method!r}: expected one of "
                         + ", ".join(PARAMETRIZATION_METHODS))
    info = topology.info(V, F)
    cut = None
    if not (info.n_boundary_loops == 1 and info.euler_characteristic == 1):
        cut = cut_to_disk(V, F)
        V, F = cut.V, cut.F
    if method == "tutte":
        uv = harmonic(V, F, weights="uniform")
    elif method == "harmonic":
        uv = harmonic(V, F, weights="cotan")
    elif method == "stretch":
        uv = stretch_minimizing(V, F, progress=progress).uv
    elif method == "lscm":
        uv = lscm(V, F)
    else:
        flatten = globals().get("abf")
        if flatten is None:
            raise InputError(f"method {method!r} needs meshsmith.parametrization.abf, which this build "
                             "does not have")
        result = flatten(V, F, method=method)
        uv = np.asarray(getattr(result, "uv", result))
    return Parametrization(np.asarray(V), np.asarray(F), uv, cut, method,
                           geometry.triangle_distortion(V, F, uv), is_bijective(uv, F))


# ---------------------------------------------------------------------------------------------
# ABF and ABF++ (§5.1.3)
# ---------------------------------------------------------------------------------------------

__all__ += ["AbfResult", "abf", "uv_from_angles"]

from dataclasses import dataclass as _dataclass  # noqa: E402  (kept within this section)


@_dataclass(frozen=True)
class AbfResult:
    """Result of :func:`abf` (m = number of faces, n = number of vertices).

    uv (n, 2) float: the flattened vertex positions; every triangle is counter-clockwise
      (positive signed area) when the map is bijective.
    angles (m, 3) float: the optimized angles (radians), column k at corner k (vertex F[f, k]).
    optimal_angles (m, 3) float: the target angles beta (the 3D angles, rescaled to sum 2 pi
      around interior vertices, clamped to [minimum_angle, pi - minimum_angle]).
    iterations: Newton iterations taken (0 when beta already satisfies every condition).
    residual: final constraint residual, the infinity-norm over |sum of a triangle's angles - pi|,
      |sum of the angles around an interior vertex - 2 pi| and |sum log sin(next angles) -
      sum log sin(previous angles)| around an interior vertex (the wheel condition).
    residual_history (iterations + 1,) float: the residual before the first step, then after each.
    """

    uv: np.ndarray
    angles: np.ndarray
    optimal_angles: np.ndarray
    iterations: int
    residual: float
    residual_history: np.ndarray


def abf(V, F, method: str = "abf++", *, max_iterations: int = 30, tolerance: float = 1e-8,
        minimum_angle: float = 1e-4, progress=None) -> AbfResult:
    """Angle-based flattening of a disk-topology mesh (§5.1.3; Sheffer & de Sturler 2001, ABF;
    Sheffer, Lévy, Mogilnitskaya & Bogart 2005, ABF++).

    Minimizes sum (alpha - beta)^2 / beta^2 over the angles alpha of the flat mesh, subject to
    triangle sums pi, interior-vertex sums 2 pi and the wheel (sine-product) condition at every
    interior vertex, by Newton's method on the Lagrangian from alpha = beta; then lays the
    angles out in the plane by the least-squares sine-law system (:func:`uv_from_angles`),
    pinning the two boundary vertices farthest apart (the first at the origin), scaled so that
    the UV area equals the surface area (a developable surface comes out isometric).

    V: (n, 3) float array. F: (m, 3) int array: one connected, manifold, oriented component with
    one boundary loop, every vertex used, no zero-area face (needles are fine: their beta are
    clamped to minimum_angle).
    method: "abf++" solves each Newton step through the reduced system of ABF++ (CHOLMOD on a
    2 x #interior-vertices SPD matrix); "abf" solves the full KKT system by sparse LU (the same
    iterates, much slower: for comparison). max_iterations bounds the Newton iterations;
    tolerance is on the constraint residual (infinity-norm, see :class:`AbfResult`).
    minimum_angle (radians, in (0, pi/6)) clamps beta. progress: optional callable
    ``(fraction, stage) -> bool`` called once per Newton iteration (stage
    "ABF++ Newton iteration k, residual r"), throttled to one call per 50 ms; returning False
    raises :class:`meshsmith.Cancelled`.

    Returns an :class:`AbfResult`. Raises InputError for a closed mesh (cut it first with
    ``parametrization.cut_to_disk``), several boundary loops or components, a non-manifold or
    non-oriented mesh, an unused vertex, a face repeating a vertex or of zero area, or bad
    options; SolverError
    if the residual is still above tolerance after max_iterations (the message gives it).
    """
    result = _core.abf(V, F, method, int(max_iterations), float(tolerance), float(minimum_angle), progress)
    return AbfResult(**result)


def uv_from_angles(F, angles, *, n_vertices: int | None = None, pinned=None, pinned_uv=None) -> np.ndarray:
    """Planar layout of triangles with prescribed angles (the last step of ABF++, §5.1.3).

    For every face the sine law and the angle at one corner give a linear equation between
    its three UV positions; the 2m equations are solved in the least-squares sense with two
    pinned vertices. Angles satisfying ABF's conditions are reproduced exactly.

    F: (m, 3) int array. angles: (m, 3) float array in (0, pi), column k at corner k.
    n_vertices: number of vertices (default: max index + 1; every vertex must be used).
    pinned: two vertex indices (default: F[0, 0] and F[0, 1]); pinned_uv: (2, 2) their
    positions (default (0, 0) and (1, 0)).
    Returns (n_vertices, 2) float UV. Raises InputError for bad shapes, an angle outside
    (0, pi), bad pins or an unused vertex; SolverError if the faces are not edge-connected.
    """
    pinned = None if pinned is None else np.reshape(np.asarray(pinned), (1, -1))
    return _core.uv_from_angles(F, angles, -1 if n_vertices is None else int(n_vertices), pinned, pinned_uv)
