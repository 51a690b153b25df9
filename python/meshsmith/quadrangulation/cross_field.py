"""Cross fields (4-RoSy) on triangle meshes and their singularities (§5.2.2 step 1); C++
src/quadrangulation/cross_field.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Union

import numpy as np

from .. import _arguments
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from .._core import InputError
from ..repair.unreferenced import ReferencedMesh, on_referenced_vertices

__all__ = ["CrossField", "Singularities", "cross_field", "field_angles", "singularities", "FieldLike"]


@dataclass(frozen=True)
class CrossField(Unpackable):
    """A cross field (:func:`cross_field`); unpacks as ``theta, directions``.

    theta: (m,) float64 angle of each face's cross against its reference edge F[f,0] → F[f,1],
    in [0, π/2) (the cross is the four directions theta + k·π/2); directions: (m, 3) float64 unit
    vectors at angle theta in the face planes; edges: (e, 2) int64 unique edges (i < j);
    edge_faces: (e, 2) int64 the faces on each side, the first one's side running i → j (−1 on a
    boundary); connection: (e,) float64 parallel-transport angle κ from the first face's frame
    to the second's; period_jumps: (e,) int64 p with θ_g − θ_f − κ − p·π/2 in [−π/4, π/4);
    constrained_faces: faces held by a hard constraint; energy: the angle energy E of theta
    (:func:`cross_field`; None for a field from :func:`merge_singularities`, which does not
    know the alignment terms to evaluate it with); initial_energy: E of the power-4 field before
    rounding (equal to energy for ``rounding="none"``; None as energy); changed_jumps: interior edges whose period jump the rounding changed
    (compared in one gauge: the power-4 angles combed along the rounding's spanning forest).
    """

    unpacks = ("theta", "directions")
    theta: FloatArray
    directions: FloatArray
    edges: IndexArray
    edge_faces: IndexArray
    connection: FloatArray
    period_jumps: IndexArray
    constrained_faces: int
    energy: float | None = None
    initial_energy: float | None = None
    changed_jumps: int = 0


@dataclass(frozen=True)
class Singularities(Unpackable):
    """Singular vertices of a cross field (:func:`singularities`); unpacks as ``vertices, indices``.

    vertices: (k,) int64 input vertex indices, increasing; indices: (k,) int64 their indices in
    quarter turns (+1 at a valence-3 corner of a quad mesh, −1 at a valence-5 vertex).
    """

    vertices: IndexArray
    indices: IndexArray


#: A cross field argument: a :class:`CrossField`, (m,) angles or (m, 3) direction vectors.
FieldLike = Union[CrossField, ArrayLike]


@_arguments.real_options
def cross_field(V: ArrayLike, F: ArrayLike, *, align: str = "curvature", constraints: object = None,
                sharp_angle: float | None = None, curvature_weight: float = 1e-3, crease_weight: float = 0.2,
                rounding: str = "none", progress: ProgressCallback = None) -> CrossField:
    """A smooth cross field on a triangle mesh (§5.2.2 step 1; Bommes et al. 2009, in the
    power-4 representation of Knöppel et al. 2013).

    The power-4 complex numbers z_f = exp(4iθ_f) minimize Σ_edges w |z_g − exp(4iκ) z_f|²
    (κ the parallel transport between the two faces' frames) — a sparse Hermitian system solved
    by CHOLMOD, or its smallest eigenvector when nothing constrains the field.

    V: (n, 3) float array, F: (m, 3) integer array.
    align: ``"curvature"`` — principal curvature directions where the surface is anisotropic
    (a soft term of weight ``curvature_weight`` against the smoothness term; the default 1e-3 keeps
    noisy principal directions from adding singularities: at 1e-2 bumpy-cube had 104 instead of
    56) and the boundary (hard); where no face is
    anisotropic (a sphere) the smoothest field — and, with ``crease_weight`` (default 0.2), along
    the edges where the surface folds: each interior edge pulls its two faces' crosses towards its
    direction with weight crease_weight · w_e · (1 − cos β), β its dihedral angle (the extrinsic
    misfit of a cross bent across the fold, as in Instant Meshes); a face's pulls count where they
    agree (summed as power-4 numbers, at least 0.02 before the weight), so smooth parts and
    isotropic tessellations (an icosphere keeps its 8 cones) are left to smoothness while CAD
    creases are followed (fandisk: 97% of the faces at edges folding more than 40° within 5° of
    the edge, 79% with crease_weight=0); ``"boundary"`` — the boundary (hard), smooth
    inside; ``"smooth"`` — the smoothest field, boundary ignored.
    constraints: None or a pair ``(faces, directions)``: (k,) face indices and (k, 3) vectors,
    one direction of each listed face's cross (projected into the face plane; hard).
    sharp_angle: None, or degrees: interior edges whose dihedral angle exceeds it are features
    and their two faces follow the edge (hard).
    rounding: how the period jumps are settled, measured by the angle energy
    E = Σ_e w (θ_f + κ + π/2·p − θ_g)² + Σ_f μ_f (θ_f − θ*_f + π/2·q_f)² (p, q integers; μ_f the
    curvature term's weight, both terms the power-4 ones' second-order expansion ÷ 16):
    ``"none"`` — the power-4 field as solved (the default); ``"resolve"`` — its jumps kept, the
    free angles re-solved to minimize E (one real sparse solve); ``"greedy"`` — greedy
    mixed-integer rounding of the jumps (Bommes et al. 2009, as CoMISo): the jumps of a dual
    spanning forest rooted at the hard faces fixed (the gauge), the others started as reals from
    the power-4 field, rounded (all those within 0.1 of an integer at once, then the closest one
    at a time, each followed by a few Gauss–Seidel sweeps of the angles around it), and the
    angles solved with every jump fixed; when that E is above ``"resolve"``'s, the ``"resolve"``
    field is returned. Neither raises E above the power-4 field's; hard constraints stay exact.
    Returns a :class:`CrossField` (unpacks as ``theta, directions``).
    Raises InputError for a negative or non-finite curvature_weight or crease_weight, for
    non-manifold, unoriented or multi-component input, zero-area or
    repeated-index faces (clean it first: :func:`meshsmith.repair.clean`, ``meshsmith clean``),
    a constraint face out of range, a NaN or zero constraint direction, or an unknown align or
    rounding.
    """
    if not isinstance(rounding, str):  # (the binding names the choices; a non-string would be a TypeError)
        raise InputError(f"rounding = {rounding!r}: expected 'none', 'resolve' or 'greedy'")
    mesh = on_referenced_vertices(V, F)
    faces: object = None
    directions: object = None
    if constraints is not None:
        if not isinstance(constraints, (tuple, list)) or len(constraints) != 2:
            raise InputError("cross_field: constraints must be a pair (faces, directions)")
        faces, directions = constraints
    angle = 0.0
    if sharp_angle is not None:
        angle = float(sharp_angle)
        if not 0 < angle < 180:
            raise InputError(f"cross_field: sharp_angle must be in (0, 180) degrees, got {sharp_angle}")
    out = _core.cross_field(mesh.V, mesh.F, align=align, sharp_angle=angle, constraint_faces=faces,
                            constraint_directions=directions, curvature_weight=curvature_weight,
                            crease_weight=crease_weight,
                            rounding=rounding, progress=progress)
    edges = mesh.vertex_map[out["edges"]] if mesh.removed else out["edges"]
    return CrossField(theta=out["theta"], directions=out["directions"], edges=edges,
                      edge_faces=out["edge_faces"], connection=out["connection"],
                      period_jumps=out["period_jumps"], constrained_faces=int(out["constrained_faces"]),
                      energy=float(out["energy"]), initial_energy=float(out["initial_energy"]),
                      changed_jumps=int(out["changed_jumps"]))


def field_angles(V: ArrayLike, F: ArrayLike, field: FieldLike) -> FloatArray:
    """The per-face angles θ (m,) of a cross field given as a :class:`CrossField`, (m,) angles
    (returned as float64) or (m, 3) direction vectors (measured in each face's frame: against
    the reference edge F[f,0] → F[f,1], counter-clockwise about the face normal).
    Raises InputError for a field of the wrong size, with NaN/Inf, or a direction normal to its face."""
    if isinstance(field, CrossField):
        field = field.theta
    if _arguments.numbers(field, "field").ndim == 1:
        theta = _arguments.finite(_arguments.real_array(field, "field"), "field")
        n_faces = len(_arguments.index_array(F, "F", 3))
        if len(theta) != n_faces:
            raise InputError(f"field has {len(theta)} angles but the mesh has {n_faces} faces")
        return theta
    mesh = on_referenced_vertices(V, F)
    return _core.field_angles(mesh.V, mesh.F, _arguments.real_array(field, "field", 3))


def singularities(V: ArrayLike, F: ArrayLike, field: FieldLike) -> Singularities:
    """The singular vertices of a cross field and their indices in quarter turns (§5.2.2).

    The index of a vertex is its angle defect plus the field's rotation against parallel
    transport around it, in quarter turns; on a closed mesh the indices sum to 4χ exactly
    (Poincaré–Hopf: +8 on a sphere, 0 on a torus), and on a mesh with boundary too when the
    field follows the boundary. field: a :class:`CrossField`, (m,) angles or (m, 3) directions.
    Returns a :class:`Singularities` (unpacks as ``vertices, indices``).
    Raises InputError as :func:`cross_field` and for a field with NaN or the wrong size.
    """
    theta = field_angles(V, F, field)
    mesh = on_referenced_vertices(V, F)
    vertices, indices = _core.singularities(mesh.V, mesh.F, theta)
    if mesh.removed:
        vertices = mesh.vertex_map[vertices]
    return Singularities(vertices=np.asarray(vertices, dtype=np.int64), indices=np.asarray(indices, dtype=np.int64))


@_arguments.real_options
def merge_singularities(V: ArrayLike, F: ArrayLike, field: CrossField, distance: float, *,
                        fixed_faces: ArrayLike | None = None, passes: int = 3) -> CrossField:
    """The cross field with its singularities closer than `distance` cancelled or moved apart
    (§5.2.2 step 1; the "too close for the quad size" case: MIQ rounds both of such a pair to the
    same or neighbouring integer points and folds the triangles between them).

    Interior pairs are taken closest first (geodesic along interior edges): a +k and a −l cancel
    (their indices add up at one of them); of two with the same sign, the one of smaller vertex
    index moves to the vertex within `distance` of it farthest from the other (two cones of one
    sign may not share an integer point). An index moves from vertex a to b
    by changing the period jumps along the shortest edge path a → b by its quarter turns; then
    the angles of the faces within 2·distance of the moved singularities are re-solved with those
    jumps fixed, minimizing Σ_e w_e (θ_g − θ_f − κ_e − p_e·π/2)² (w_e as in :func:`cross_field`),
    the other faces and `fixed_faces` (the hard constraints) held. This is repeated up to
    `passes` times (the re-solve can leave a pair where a vertex's angle defect needs it). A
    pair whose cancellation the re-solve cannot honour (a residual beyond π/4 there) comes back
    as it was: the indices are always read off the angles, so Poincaré–Hopf holds exactly.

    Measured (curvature-aligned fields at 3,000 quads, distance = 1–1.5 quad edges): pmp-bunny
    67 → 58 singularities and MIQ's flips left 7 → 0; rocker-arm 40 → 30 and 7 → 0 at 1.5.

    V: (n, 3), F: (m, 3); field: a :class:`CrossField` of (V, F); distance: input units (> 0).
    Returns a new :class:`CrossField` (the same one when nothing is merged; its
    ``constrained_faces`` is the input's). Raises InputError for a distance that is not > 0,
    passes outside [1, 100] or a field of the wrong size.
    """
    if not isinstance(field, CrossField):
        raise InputError("merge_singularities: field must be a CrossField (from cross_field)")
    distance = float(distance)
    if not (np.isfinite(distance) and distance > 0):
        raise InputError(f"merge_singularities: distance must be a finite number > 0, got {distance}")
    passes = _arguments.integer(passes, "passes", 1, 100)
    fixed = None if fixed_faces is None else _arguments.index_array(fixed_faces, "fixed_faces")
    mesh = on_referenced_vertices(V, F)
    computed = None
    for _ in range(passes):
        merged, computed = _merge_pass(mesh, field, distance, fixed, computed)
        if merged is field:
            break
        field = merged
    return field


def _merge_pass(mesh: ReferencedMesh, field: CrossField, distance: float, fixed_faces: np.ndarray | None,
                computed: dict[str, Any] | None) -> tuple[CrossField, dict[str, Any]]:
    """One pass of :func:`merge_singularities` on the referenced mesh: the field (itself when
    nothing moves) and its field_edges (`computed`: the field's, from the pass before, or None)."""
    import scipy.sparse
    import scipy.sparse.csgraph

    dijkstra: Any = scipy.sparse.csgraph.dijkstra  # (scipy-stubs' overloads miss limit= with indices=)

    P, T = np.asarray(mesh.V, dtype=np.float64), np.asarray(mesh.F, dtype=np.int64)
    if len(field.theta) != len(T):
        raise InputError(f"merge_singularities: the field has {len(field.theta)} faces but the mesh has {len(T)}")
    n, m = len(P), len(T)
    theta = np.asarray(field.theta, dtype=np.float64)
    if computed is None:  # (the field's own arrays are on the input's numbering)
        computed = _core.field_edges(P, T, theta)
    edges = np.asarray(computed["edges"], dtype=np.int64)
    edge_faces = np.asarray(computed["edge_faces"], dtype=np.int64)
    connection = np.asarray(computed["connection"], dtype=np.float64)
    interior = edge_faces[:, 1] >= 0
    # the unreduced jumps (field.period_jumps are mod 4: the angle energy needs the whole turns)
    g = np.where(interior, edge_faces[:, 1], edge_faces[:, 0])
    jumps = np.round((theta[g] - theta[edge_faces[:, 0]] - connection) / (np.pi / 2)).astype(np.int64)
    if "singular_vertices" in computed:  # from the pass before
        vertices, indices = computed["singular_vertices"], computed["singular_indices"]
    else:
        vertices, indices = _core.singularities(P, T, theta)
    index = np.zeros(n, dtype=np.int64)
    index[np.asarray(vertices, dtype=np.int64)] = indices
    boundary_vertex = np.zeros(n, dtype=bool)
    boundary_vertex[edges[~interior].ravel()] = True
    candidates = np.array([v for v in vertices if not boundary_vertex[v]], dtype=np.int64)
    if len(candidates) < 2:
        return field, computed
    length = np.linalg.norm(P[edges[:, 1]] - P[edges[:, 0]], axis=1)
    e_in = np.nonzero(interior)[0]
    graph = scipy.sparse.coo_matrix((length[e_in], (edges[e_in, 0], edges[e_in, 1])), shape=(n, n)).tocsr()
    dist, predecessors = dijkstra(graph, directed=False, indices=candidates, limit=distance,
                                                       return_predecessors=True)
    edge_row = _edge_rows(edges, n)
    row_of = {int(v): r for r, v in enumerate(candidates)}
    pairs = sorted((dist[r, b], int(a), int(b)) for r, a in enumerate(candidates) for b in candidates
                   if b != a and np.isfinite(dist[r, b]))
    moved: list[int] = []

    def move(a: int, b: int, row: np.ndarray) -> None:
        """Moves a's index to b along the shortest path (predecessor row `row` of a search from a)."""
        _carry_index(jumps, edge_row, row, a, b, int(index[a]))
        index[b] += index[a]
        index[a] = 0
        moved.extend([a, b])

    for _, a, b in pairs:
        ia, ib = int(index[a]), int(index[b])
        if ia == 0 or ib == 0:
            continue
        if ia * ib < 0:  # a ±1 pair: cancel
            move(a, b, predecessors[row_of[a]])
        elif a < b:  # same sign: move a to the vertex within `distance` of a farthest from b
            around, row = dijkstra(graph, directed=False, indices=a, limit=distance,
                                                       return_predecessors=True)
            from_b = dijkstra(graph, directed=False, indices=b, limit=3 * distance)
            reach = np.isfinite(around) & np.isfinite(from_b) & (index == 0) & ~boundary_vertex
            if reach.any():
                move(a, int(np.argmax(np.where(reach, from_b, -np.inf))), row)
    if not moved:
        return field, computed
    # Re-solve the angles near the moved singularities with the jumps fixed.
    near = dijkstra(graph, directed=False, indices=np.unique(moved), limit=2 * distance,
                                         min_only=True)
    free: np.ndarray = np.asarray(np.isfinite(near)[T].any(axis=1), dtype=bool)
    if fixed_faces is not None:
        if len(fixed_faces) and (fixed_faces.min() < 0 or fixed_faces.max() >= m):
            raise InputError(f"merge_singularities: fixed_faces must be face indices in [0, {m})")
        free[fixed_faces] = False
    if field.constrained_faces:  # the boundary is held when the field follows it
        free[edge_faces[~interior, 0]] = False
    resolved = _core.resolve_angles(P, T, theta, jumps, ~free)
    solved = np.asarray(resolved["theta"], dtype=np.float64)  # in [0, π/2)
    edges_out = dict(computed, **resolved)  # the same edges, the solved field's jumps and singularities
    p0, p1, p2 = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    e1 = (p1 - p0) / np.linalg.norm(p1 - p0, axis=1, keepdims=True)
    normal = np.cross(p1 - p0, p2 - p0)
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    directions = np.cos(solved)[:, None] * e1 + np.sin(solved)[:, None] * np.cross(normal, e1)
    return CrossField(theta=solved, directions=directions, edges=mesh.vertex_map[edges] if mesh.removed else edges,
                      edge_faces=edge_faces, connection=connection, period_jumps=np.asarray(edges_out["period_jumps"], dtype=np.int64),
                      constrained_faces=field.constrained_faces), edges_out


def _edge_rows(edges: np.ndarray, n: int) -> Callable[[int, int], int]:
    """The row of edge (x, y) in `edges` ((e, 2) int64, each row i < j, n vertices), by binary
    search on the sorted keys i·n + j (a dict of every edge took 9.8 s of a 90 s pmp-bunny run at
    load 20; the paths that use it touch a few dozen edges)."""
    keys = edges[:, 0] * n + edges[:, 1]
    key_order = np.argsort(keys)
    sorted_keys = keys[key_order]

    def edge_row(x: int, y: int) -> int:
        return int(key_order[np.searchsorted(sorted_keys, min(x, y) * n + max(x, y))])
    return edge_row


def _carry_index(jumps: np.ndarray, edge_row: Callable[[int, int], int], predecessors: np.ndarray,
                source: int, target: int, quarter_turns: int) -> None:
    """Moves a singularity index of `quarter_turns` from vertex `source` to `target` by changing
    the period `jumps` (per edge of :func:`_edge_rows`, in place) along the shortest path, given by
    `predecessors` (the predecessor row of a search from source): each step x → y carries the
    index onward (I_x −= i, I_y += i), and p_e += 1 moves one unit from j to i (i < j)."""
    y = target
    while y != source:
        x = int(predecessors[y])
        e = edge_row(x, y)
        jumps[e] += quarter_turns if x > y else -quarter_turns
        y = x
