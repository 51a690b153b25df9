"""Zippering (§2.4.1, after Turk and Levoy 1994): two registered, overlapping scans joined into one
manifold mesh by removing the overlapping triangles of one, clipping its new boundary against the
other's boundary and stitching the two boundaries together."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np

from .. import _arguments, topology
from .._core import InputError
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from ..geometry import SurfaceDistance, face_normals, vertex_normals
from ..points import KdTree
from .clean import clean
from .holes import fill_holes
from .intersections import remove_self_intersections, self_intersections
from .stitching import boundary_sides, stitch_boundaries
from .unreferenced import remove_unreferenced

__all__ = ["ZipperReport", "ZipperedMesh", "zipper"]


@dataclass(frozen=True)
class ZipperReport(Unpackable):
    """What :func:`zipper` did; unpacks as ``face_source, face_map``.

    face_source: (m,) int64, 0 for an output face from A, 1 from B, -1 for a face that closes a gap
    in the seam; face_map: (m,) int64, its row of FA or FB (a B face split at the seam gives
    several; -1 for a gap's face); removed_faces: B faces removed as
    overlapping A; snapped_vertices: B vertices of the cut moved onto A's boundary;
    inserted_vertices: A boundary vertices inserted into B's cut edges (the clipping);
    split_edges and merged_vertices: what :func:`stitch_boundaries` then did (A's boundary edges
    split at B's vertices, coincident vertices merged); removed_degenerate: faces a merge or the
    final :func:`clean` removed (slivers of the seam); dropped_fragments: pieces of B of at most
    8 faces left unconnected along the seam, removed; filled_gaps: holes of at most 8 edges left
    along the seam (every vertex on it), closed by :func:`fill_holes`; untangled_pairs: face pairs
    crossing each other that the seam made (a sliver of B folded over A's rim, a gap's patch), resolved
    by :func:`remove_self_intersections` on the seam's faces; boundary_loops_before: loops of A plus
    those of B; boundary_loops_after: loops of the output.
    """

    face_source: IndexArray
    face_map: IndexArray
    removed_faces: int
    snapped_vertices: int
    inserted_vertices: int
    split_edges: int
    merged_vertices: int
    removed_degenerate: int
    dropped_fragments: int
    filled_gaps: int
    untangled_pairs: int
    boundary_loops_before: int
    boundary_loops_after: int
    bridged_runs: int = 0
    bridge_faces: int = 0

    unpacks = ("face_source", "face_map")


class ZipperedMesh(NamedTuple):
    """The result of :func:`zipper`: ``V, F, report = zipper(VA, FA, VB, FB, tolerance=t)``."""

    V: FloatArray
    F: IndexArray
    report: ZipperReport


def barycentric(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    """(k, 3) barycentric coordinates of points P (k, 3) on triangles T (k, 3, 3) (points on the
    triangles, as closest points are), clamped to [0, 1] and summing to 1; a degenerate triangle
    gives its first corner."""
    e1, e2, d = T[:, 1] - T[:, 0], T[:, 2] - T[:, 0], P - T[:, 0]
    d11, d12, d22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    d1, d2 = (d * e1).sum(1), (d * e2).sum(1)
    det = d11 * d22 - d12 * d12
    ok = det > 0
    safe = np.where(ok, det, 1.0)
    u = np.where(ok, (d22 * d1 - d12 * d2) / safe, 0.0)
    v = np.where(ok, (d11 * d2 - d12 * d1) / safe, 0.0)
    weights = np.clip(np.column_stack([1 - u - v, u, v]), 0.0, 1.0)
    return weights / weights.sum(axis=1, keepdims=True)


def _on_boundary(V: FloatArray, F: IndexArray, face: IndexArray, point: FloatArray) -> np.ndarray:
    """(k,) bool: the closest point `point` (on face `face` of (V, F)) lies on a boundary edge of F."""
    side_is_boundary = np.zeros((len(F), 3), dtype=bool)        # side c runs from corner c to c + 1
    sides = boundary_sides(F)
    side_is_boundary[sides[:, 0], sides[:, 1]] = True
    vertex_is_boundary = np.zeros(len(V), dtype=bool)
    vertex_is_boundary[F[sides[:, 0], sides[:, 1]]] = True
    weights = barycentric(point, V[F[face]])
    on = np.zeros(len(face), dtype=bool)
    for c in range(3):        # on side c when the weight of the opposite corner (c + 2) vanishes
        on |= side_is_boundary[face, c] & (weights[:, (c + 2) % 3] < 1e-9)
        on |= vertex_is_boundary[F[face, c]] & (weights[:, c] > 1 - 1e-9)
    return on


def _closest_on_loops(P: FloatArray, VA: FloatArray, loops: list[IndexArray]) -> tuple[np.ndarray, ...]:
    """For each point of P (k, 3), the closest point of A's boundary loops: (loop (k,), parameter
    (k,) in [0, len(loop)) along it, distance (k,), point (k, 3)). The parameter's integer part is
    the segment from loop[j] to loop[j + 1], its fraction how far along; a point within a tenth of
    a segment of a corner is put on the corner (so no sliver is cut off next to it)."""
    which = np.concatenate([np.full(len(loop), i) for i, loop in enumerate(loops)])
    slot = np.concatenate([np.arange(len(loop)) for loop in loops])
    vertices = np.concatenate(loops)
    tree = KdTree(VA[vertices])
    neighbours = tree.query(min(8, len(vertices)), P).indices                     # (k, q)
    best = np.full(len(P), np.inf)
    loop_of, parameter = np.zeros(len(P), dtype=np.int64), np.zeros(len(P))
    point = np.zeros_like(P)
    sizes = np.array([len(loop) for loop in loops])
    for column in range(neighbours.shape[1]):
        n = neighbours[:, column]
        L, j = which[n], slot[n]
        for segment in (j, (j - 1) % sizes[L]):
            start = np.array([loops[l][s] for l, s in zip(L.tolist(), segment.tolist())], dtype=np.int64)
            end = np.array([loops[l][(s + 1) % sizes[l]] for l, s in zip(L.tolist(), segment.tolist())],
                           dtype=np.int64)
            a, b = VA[start], VA[end]
            direction = b - a
            length2 = np.einsum("ij,ij->i", direction, direction)
            t = np.clip(np.einsum("ij,ij->i", P - a, direction) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
            t = np.where(t < 0.1, 0.0, np.where(t > 0.9, 1.0, t))
            q = np.where(t[:, None] == 0.0, a, np.where(t[:, None] == 1.0, b, a + t[:, None] * direction))
            distance = np.linalg.norm(P - q, axis=1)
            better = distance < best
            best[better], loop_of[better] = distance[better], L[better]
            parameter[better] = ((segment + t) % sizes[L])[better]
            point[better] = q[better]
    return loop_of, parameter, best, point


#: The largest piece of B dropped, and the largest hole filled, where the seam did not close (edges).
SEAM_LEFTOVER = 8


def _close_seam(V: FloatArray, F: IndexArray, source: IndexArray, rows: IndexArray,
                seam_points: FloatArray) -> tuple[FloatArray, IndexArray, IndexArray, IndexArray, int, int]:
    """What a seam can leave behind where B's cut met A's rim badly: drop the components of at most
    SEAM_LEFTOVER faces, all from B, and fill the holes of at most SEAM_LEFTOVER edges whose vertices
    all lie on the seam (A's rim, B's snapped and inserted vertices). Returns (V, F, source, rows,
    dropped fragments, filled holes)."""
    components = topology.connected_components(F, len(V), connectivity="edge")
    sizes = np.bincount(components.face_labels, minlength=components.count)
    from_a = np.bincount(components.face_labels, weights=(source == 0), minlength=components.count)
    fragment = (sizes <= SEAM_LEFTOVER) & (from_a == 0) & (sizes < len(F))
    fragments = int(fragment.sum())
    if fragments:
        keep = ~fragment[components.face_labels]
        source, rows = source[keep], rows[keep]
        V, F, _ = remove_unreferenced(V, F[keep])
    _, seam_position = np.unique(np.vstack([seam_points, V]), axis=0, return_inverse=True)
    seam_position = seam_position.reshape(-1)
    on_seam = np.isin(seam_position[len(seam_points):], seam_position[:len(seam_points)])
    loops = topology.boundary_loops(F)
    gaps = [i for i, loop in enumerate(loops) if len(loop) <= SEAM_LEFTOVER and on_seam[loop].all()]
    if not gaps or not _fillable(F):
        return V, F, source, rows, fragments, 0
    V2, F2, filled = fill_holes(V, F, holes=gaps, refine=False, fair=False)
    added = len(F2) - len(F)
    return (V2, F2, np.concatenate([source, np.full(added, -1, dtype=np.int64)]),
            np.concatenate([rows, np.full(added, -1, dtype=np.int64)]), fragments, filled.filled)


def _unfolding_snaps(VB: FloatArray, FB: IndexArray, candidates: IndexArray, point: FloatArray,
                     close: np.ndarray) -> np.ndarray:
    """`close` (which candidates to move to `point`) without the moves that would turn a face of
    B over (its normal against the one it had): of such a face's moved corners the one moved
    farthest stays, until no face turns over (the gap it leaves is closed with the seam's)."""
    close = close.copy()
    moved = np.full(len(VB), -1, dtype=np.int64)
    for _ in range(16):
        moved[:] = -1
        moved[candidates[close]] = np.flatnonzero(close)
        touched = (moved[FB] >= 0).any(axis=1)
        if not touched.any():
            return close
        faces = FB[touched]
        P = VB[faces].copy()
        rows = moved[faces]
        P[rows >= 0] = point[rows[rows >= 0]]
        before = np.cross(VB[faces[:, 1]] - VB[faces[:, 0]], VB[faces[:, 2]] - VB[faces[:, 0]])
        after = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        turned = np.einsum("ij,ij->i", before, after) < 0
        if not turned.any():
            return close
        shift = np.where(rows >= 0, np.linalg.norm(P - VB[faces], axis=2), -1.0)[turned]
        undo = rows[turned][np.arange(int(turned.sum())), shift.argmax(axis=1)]
        close[undo] = False
    return close


def _clip_to_loops(VB: FloatArray, FB: IndexArray, face_map: IndexArray, VA: FloatArray, loops: list[IndexArray],
                   where: dict[int, tuple[int, float]]) -> tuple[FloatArray, IndexArray, IndexArray, int]:
    """Insert into each boundary edge of B whose two ends lie on the same loop of A (where: B vertex
    -> (loop, parameter)) copies of the loop vertices strictly between them (the shorter way
    round), splitting the edge's face into a fan; so B's cut follows A's boundary vertex by vertex.
    Returns (VB, FB, face_map, inserted vertices)."""
    inserted = 0
    for _ in range(8):                        # a face with two sides to split gets one per pass
        sides = boundary_sides(FB)
        new_vertices: list[np.ndarray] = []
        new_faces: list[list[int]] = []
        new_map: list[int] = []
        replaced = np.zeros(len(FB), dtype=bool)
        for f, c in sides.tolist():
            if replaced[f]:
                continue
            u, w, o = int(FB[f, c]), int(FB[f, (c + 1) % 3]), int(FB[f, (c + 2) % 3])
            if u not in where or w not in where or where[u][0] != where[w][0]:
                continue
            loop = loops[where[u][0]]
            n = len(loop)
            pu, pw = where[u][1], where[w][1]
            forward = (pw - pu) % n
            step, span = (1, forward) if forward <= n / 2 else (-1, n - forward)
            between = [k for k in (np.floor(pu) + step * np.arange(0, int(np.ceil(span)) + 2)).astype(int).tolist()
                       if 0 < step * (k - pu) < span]
            if not between or len(between) > 32:
                continue
            chain = [u]
            for k in between:
                where[len(VB) + len(new_vertices)] = (where[u][0], float(k % n))
                chain.append(len(VB) + len(new_vertices))
                new_vertices.append(VA[loop[k % n]])
            chain.append(w)
            new_faces += [[chain[i], chain[i + 1], o] for i in range(len(chain) - 1)]
            new_map += [int(face_map[f])] * (len(chain) - 1)
            replaced[f] = True
        if not new_faces:
            break
        inserted += len(new_vertices)
        VB = np.vstack([VB, np.asarray(new_vertices)])
        FB = np.vstack([FB[~replaced], np.asarray(new_faces, dtype=np.int64)])
        face_map = np.concatenate([face_map[~replaced], np.asarray(new_map, dtype=np.int64)])
    return VB, FB, face_map, inserted


#: Rounds of cutting out and refilling the seam's crossing faces (each one ring wider).
SEAM_ROUNDS = 2
#: The most crossing pairs the seam may have made for them to be untangled: more is not a seam's
#: few slivers but two scans that disagree along it (raw range scans: thousands), left as stitched.
SEAM_MAX_PAIRS = 1000


def _fillable(F: IndexArray) -> bool:
    """Whether :func:`fill_holes` takes F: edge-manifold and consistently oriented (where two
    raw scans' seam crossed itself it may be neither; the seam is then left as stitched)."""
    return bool(topology.is_manifold(F) and topology.is_oriented(F))


def _untangle_seam(V: FloatArray, F: IndexArray, source: IndexArray, rows: IndexArray, VA: FloatArray,
                   FA: IndexArray) -> tuple[FloatArray, IndexArray, IndexArray, IndexArray, int]:
    """Resolve the self-intersecting face pairs the seam made: :func:`remove_self_intersections`
    may cut out and refill only faces of B, the gaps' patches and A's faces that the stitching split
    (a corner not one of the input face's), so A's own faces, and any pair among them (the
    input's own), stay as they were. Returns (V, F, source, rows, pairs resolved)."""
    if not _fillable(F):
        return V, F, source, rows, 0
    removable = source != 0
    from_a = np.flatnonzero(source == 0)
    original = VA[FA[rows[from_a]]]                                               # (k, 3, 3)
    same = (V[F[from_a]][:, :, None, :] == original[:, None, :, :]).all(axis=3).any(axis=2).all(axis=1)
    removable[from_a[~same]] = True
    pairs = self_intersections(V, F)
    made = int(removable[pairs].any(axis=1).sum()) if len(pairs) else 0
    if not made or made > SEAM_MAX_PAIRS:
        return V, F, source, rows, 0
    try:
        V2, F2, removal = remove_self_intersections(V, F, faces=removable, max_rounds=SEAM_ROUNDS, refine=False,
                                                     fair=False)
    except InputError:
        # A round's fill met a non-manifold edge (raw scans whose seam crosses itself in many
        # places): the seam is left as stitched, its pairs for self_intersections to find.
        return V, F, source, rows, 0
    if not removal.initial_pairs:
        return V, F, source, rows, 0
    origin = removal.face_origin
    kept = origin >= 0
    source = np.where(kept, source[np.maximum(origin, 0)], -1)
    rows = np.where(kept, rows[np.maximum(origin, 0)], -1)
    return V2, F2, source, rows, removal.initial_pairs - removal.remaining_pairs


#: Bridge seam: B's cut vertices farther from A's boundary than this many of B's mean edges are not bridged.
BRIDGE_REACH = 3.0
#: Bridge seam: the largest angle between the normals of A and B where B is over A (Turk and Levoy's
#: test that two surfaces close together are the same surface, not the two sides of a thin part).
BRIDGE_NORMAL_ANGLE = 60.0


def _triangle_min_angles(V: FloatArray, T: IndexArray) -> FloatArray:
    """(t,) the smallest angle (radians) of each triangle of T; 0 for a degenerate one."""
    P = V[T]
    smallest = np.full(len(T), np.pi)
    for c in range(3):
        u, w = P[:, (c + 1) % 3] - P[:, c], P[:, (c + 2) % 3] - P[:, c]
        norms = np.linalg.norm(u, axis=1) * np.linalg.norm(w, axis=1)
        cosine = np.einsum("ij,ij->i", u, w) / np.where(norms > 0, norms, 1.0)
        smallest = np.minimum(smallest, np.where(norms > 0, np.arccos(np.clip(cosine, -1.0, 1.0)), 0.0))
    return smallest


def _flip_strip(V: FloatArray, T: IndexArray, F: IndexArray) -> IndexArray:
    """Lawson's flips inside the bridging strip T (edges two strip triangles share), each taken when
    it raises the pair's smallest angle, keeps both normals on the side they were, and makes no
    edge that F or T already has; until none is taken (at most 8 sweeps)."""
    T = T.copy()
    if not len(T):
        return T
    touching = np.zeros(max(int(F.max(initial=-1)), int(T.max())) + 1, dtype=bool)
    touching[T.ravel()] = True
    near = F[touching[F].any(axis=1)]
    existing = {(int(a), int(b)) for a, b in np.sort(np.vstack([near[:, [0, 1]], near[:, [1, 2]], near[:, [2, 0]]]),
                                                     axis=1).tolist()}
    for _ in range(8):
        side: dict[tuple[int, int], tuple[int, int]] = {}
        for f, (a, b, c) in enumerate(T.tolist()):
            for u, w in ((a, b), (b, c), (c, a)):
                side[(u, w)] = (f, {a, b, c}.difference((u, w)).pop())
        existing |= {(min(u, w), max(u, w)) for u, w in side}
        flipped = 0
        done = np.zeros(len(T), dtype=bool)
        for (u, w), (f, x) in list(side.items()):
            if (w, u) not in side or done[f]:
                continue
            g, y = side[(w, u)]
            if done[g] or x == y or (min(x, y), max(x, y)) in existing:
                continue
            old = np.array([[u, w, x], [w, u, y]])
            new = np.array([[x, u, y], [y, w, x]])
            n_old = np.cross(V[old[:, 1]] - V[old[:, 0]], V[old[:, 2]] - V[old[:, 0]]).sum(axis=0)
            n_new = np.cross(V[new[:, 1]] - V[new[:, 0]], V[new[:, 2]] - V[new[:, 0]])
            if (n_new @ n_old <= 0).any() or _triangle_min_angles(V, new).min() <= _triangle_min_angles(V, old).min():
                continue
            T[f], T[g] = new
            done[f] = done[g] = True
            existing.add((min(x, y), max(x, y)))
            flipped += 1
        if not flipped:
            break
    return T


def _bridge_runs(V: FloatArray, loops_a: list[IndexArray], loops_b: list[IndexArray],
                 reach: float) -> tuple[IndexArray, int]:
    """The triangles of a strip between B's cut and A's rim (Turk and Levoy's gap, bridged without
    moving a vertex): each run of consecutive vertices of a loop of B within ``reach`` of one loop
    of A, running against it (so the strip is oriented as both), is zipped to the chain of A's
    loop vertices between the closest points of its two ends, advancing at each step on the side
    whose new diagonal is shorter. A chain or run that would reuse a boundary edge already bridged
    is skipped (its gap stays open). Returns ((t, 3) int64 triangles, runs bridged)."""
    if not loops_a or not loops_b:
        return np.zeros((0, 3), dtype=np.int64), 0
    b_vertices = np.concatenate(loops_b)
    loop_of, parameter, distance, _ = _closest_on_loops(V[b_vertices], V, loops_a)
    triangles: list[tuple[int, int, int]] = []
    used_a: set[tuple[int, int]] = set()
    runs = 0
    start = 0
    for loop in loops_b:
        n = len(loop)
        near = distance[start:start + n] <= reach
        which, where = loop_of[start:start + n], parameter[start:start + n]
        start += n
        if not near.any():
            continue
        # Runs: maximal cyclic stretches of near vertices on one loop of A.
        same = near & np.roll(near, -1) & (which == np.roll(which, -1))     # edge i -> i + 1 joins a run
        if same.all():
            breaks = [int(np.argmax(where))]          # a whole loop: cut it where A's parameter wraps
        else:
            breaks = np.flatnonzero(~same).tolist()
        for r, first_break in enumerate(breaks):
            first = (first_break + 1) % n
            last = breaks[(r + 1) % len(breaks)]
            length = (last - first) % n + 1 if not same.all() else n
            run = [(first + t) % n for t in range(length)]
            if len(run) < 2 or not near[run[0]]:
                continue
            L = int(which[run[0]])
            chain_loop = loops_a[L]
            m = len(chain_loop)
            p = where[run]
            step = (p[:-1] - p[1:] + m / 2) % m - m / 2             # A's parameter should fall along the run
            if step.sum() <= 0.5:
                continue
            j0 = int(np.floor(p[0] + 0.5)) % m
            count = int(np.floor(step.sum() + 0.5)) + 1
            if count > m:
                continue
            Q = [int(chain_loop[(j0 - t) % m]) for t in range(count)]
            P = [int(loop[k]) for k in run]
            edges_a = [(Q[t + 1], Q[t]) for t in range(len(Q) - 1)]
            if any(e in used_a for e in edges_a):
                continue
            used_a.update(edges_a)
            i = j = 0
            while i < len(P) - 1 or j < len(Q) - 1:
                advance_p = j == len(Q) - 1 or (
                    i < len(P) - 1 and np.linalg.norm(V[P[i + 1]] - V[Q[j]]) <= np.linalg.norm(V[P[i]] - V[Q[j + 1]]))
                if advance_p:
                    triangles.append((P[i + 1], P[i], Q[j]))
                    i += 1
                else:
                    triangles.append((Q[j], Q[j + 1], P[i]))
                    j += 1
            runs += 1
    T = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    T = T[(T[:, 0] != T[:, 1]) & (T[:, 1] != T[:, 2]) & (T[:, 0] != T[:, 2])]
    return T, runs


#: Bridge seam: rounds of dropping the seam's faces that cross another face.
BRIDGE_DROP_ROUNDS = 6


def _drop_crossing_seam_faces(V: FloatArray, F: IndexArray, source: IndexArray,
                              rows: IndexArray) -> tuple[FloatArray, IndexArray, IndexArray, IndexArray, int]:
    """Where the bridged seam crosses a face (the strip through A's curled rim, a leftover of B
    through A), the crossing faces that are not A's (strip, patches, B) are dropped, leaving that
    stretch of the seam open: at most BRIDGE_DROP_ROUNDS rounds of :func:`self_intersections`,
    each followed by :func:`clean`. Returns (V, F, source, rows, pairs resolved)."""
    initial = None
    pairs = self_intersections(V, F)
    for _ in range(BRIDGE_DROP_ROUNDS):
        removable = source != 0
        chosen = pairs[removable[pairs].any(axis=1)] if len(pairs) else pairs
        if initial is None:
            initial = len(chosen)
        if not len(chosen):
            break
        drop = np.zeros(len(F), dtype=bool)
        drop[chosen.ravel()] = True
        drop &= removable
        V, F, cleaned = clean(V, F[~drop])
        source, rows = source[~drop][cleaned.face_map], rows[~drop][cleaned.face_map]
        pairs = self_intersections(V, F)
    left = int(((source != 0)[pairs].any(axis=1)).sum()) if len(pairs) else 0
    return V, F, source, rows, (initial or 0) - left


def _zipper_bridged(Va: FloatArray, Fa: IndexArray, Vb: FloatArray, Fb: IndexArray, loops_a: list[IndexArray],
                    loops_before: int, surface: SurfaceDistance, covered: Callable[..., np.ndarray],
                    tolerance: float, progress: ProgressCallback) -> ZipperedMesh:
    """:func:`zipper` with ``seam="bridge"``: B's faces over A whose normals agree with A's are
    removed, and those with a corner within max(tolerance, half of B's mean edge) of A (its rim
    included), so that B's cut keeps a gap from A; the gap is bridged by :func:`_bridge_runs`,
    then cleaned, its leftovers closed and its crossings untangled as for ``seam="clip"``."""
    normals = vertex_normals(Vb, Fb)
    overlap = covered(Vb[Fb].mean(axis=1), face_normals(Vb, Fb)) | covered(Vb, normals)[Fb].any(axis=1)
    spacing = float(np.linalg.norm(Vb[Fb] - Vb[np.roll(Fb, -1, axis=1)], axis=2).mean())
    closest = surface.closest_points(Vb)
    facing = np.einsum("ij,ij->i", face_normals(Va, Fa)[closest.face], normals) >= np.cos(np.radians(BRIDGE_NORMAL_ANGLE))
    near = (closest.distance <= max(tolerance, 0.5 * spacing)) & facing
    overlap |= near[Fb].any(axis=1)
    removed = int(overlap.sum())
    face_map_b = np.flatnonzero(~overlap).astype(np.int64)
    Vb1, Fb1, _ = remove_unreferenced(Vb, Fb[~overlap])

    _arguments.report(progress, 0.5, "zipper: bridging")
    V = np.vstack([Va, Vb1])
    F = np.vstack([Fa, Fb1 + len(Va)])
    loops_b = topology.boundary_loops(Fb1 + len(Va)) if len(Fb1) else []
    strip, runs = _bridge_runs(V, loops_a, loops_b, BRIDGE_REACH * spacing)
    strip = _flip_strip(V, strip, F)
    F = np.vstack([F, strip])
    source = np.concatenate([np.zeros(len(Fa), dtype=np.int64), np.ones(len(Fb1), dtype=np.int64),
                             np.full(len(strip), -1, dtype=np.int64)])
    rows = np.concatenate([np.arange(len(Fa), dtype=np.int64), face_map_b, np.full(len(strip), -1, dtype=np.int64)])
    faces_before_clean = len(F)
    V, F, cleaned = clean(V, F)
    source, rows = source[cleaned.face_map], rows[cleaned.face_map]
    degenerate = faces_before_clean - len(F)

    _arguments.report(progress, 0.85, "zipper: closing the seam")
    fragments = gaps = untangled = 0
    if len(F) and len(loops_a) and len(Fb1):
        seam_points = np.vstack([Va[np.concatenate(loops_a)]] + [Vb1[loop] for loop in
                                                                   topology.boundary_loops(Fb1)])
        V, F, source, rows, fragments, gaps = _close_seam(V, F, source, rows, seam_points)
        _arguments.report(progress, 0.9, "zipper: untangling the seam")
        V, F, source, rows, untangled = _drop_crossing_seam_faces(V, F, source, rows)
    _arguments.report(progress, 1.0, "zipper: done")
    report = ZipperReport(face_source=source, face_map=rows, removed_faces=removed, snapped_vertices=0,
                          inserted_vertices=0, split_edges=0, merged_vertices=0, removed_degenerate=degenerate,
                          dropped_fragments=fragments, filled_gaps=gaps, untangled_pairs=untangled,
                          boundary_loops_before=loops_before,
                          boundary_loops_after=len(topology.boundary_loops(F)) if len(F) else 0,
                          bridged_runs=runs, bridge_faces=int((source == -1).sum()))
    return ZipperedMesh(V, F, report)


@_arguments.real_options
def zipper(VA: ArrayLike, FA: ArrayLike, VB: ArrayLike, FB: ArrayLike, *, tolerance: float,
           seam: str = "clip", progress: ProgressCallback = None) -> ZipperedMesh:
    """Join two registered, overlapping scans into one manifold mesh (§2.4.1, after Turk and Levoy 1994).

    1. Overlap: a point is over A when it lies within ``tolerance`` of A's surface (exact
       point-to-triangle distance, :class:`SurfaceDistance`) at a closest point that is not on A's
       boundary (points beyond A's rim have their closest point on it). A triangle of B is removed
       when its centroid or one of its corners is over A, so what is left of B ends at A's rim,
       with a gap of at most one of B's triangles.
    2. Clipping: each vertex of B's new boundary (the cut) is moved onto the closest point of A's
       boundary (onto a corner of it when within a tenth of a segment), if that is within
       ``tolerance`` plus 1.5 times its longest edge; each edge of the cut whose ends landed on one
       loop of A then gets the loop's vertices between them, so the cut follows A's boundary
       vertex by vertex.
    3. Joining: :func:`stitch_boundaries` with a tolerance of a millionth of A's mean boundary edge
       splits A's boundary edges at the cut's vertices and merges the coincident vertices; then
       :func:`clean` removes the slivers and degenerate faces this leaves and orients the result.
       Where B's cut met A's rim badly (a sharp turn of the rim), a piece of B of at most 8 faces
       may be left unconnected, and a hole of a few edges open: such pieces are dropped and such
       holes (every vertex on the seam) filled, and both counted.
    4. Untangling: where the seam left faces crossing each other (a sliver of B folded over A's
       rim faces, nearly coplanar with them), :func:`remove_self_intersections` cuts out and
       refills the seam's faces of every such pair — faces of B, the gaps' patches, A's faces
       split at the seam — never A's own faces, so pairs that were in A are left as they were
       (at most SEAM_ROUNDS = 2 rounds, each hole closed by Liepa's triangulation of its loop
       alone, no vertex added; what is left is for :func:`self_intersections` to find). More
       than SEAM_MAX_PAIRS = 1000 such pairs are not untangled (two scans disagreeing all along
       the seam, not a few slivers).
       It runs where the stitched mesh is manifold and oriented, and the seam is left as
       stitched where it fails (a fill meeting a non-manifold edge: two raw range scans).
    A's triangles are all kept (those along its rim split at B's vertices, and such a split face
    refilled where it crossed B); where the two scans do not overlap, their boundaries stay open.

    ``seam="bridge"`` (for raw range scans, whose rims are ragged and whose surfaces interleave by
    scanner noise in the overlap; ``"clip"`` is the default above): B's faces over A are removed
    only where their normals agree with A's within BRIDGE_NORMAL_ANGLE = 60° (Turk and Levoy's
    test, so the two sides of a thin part are not taken for one), and also every face of B with a
    corner within max(tolerance, half of B's mean edge) of A, rim included, so that B's cut keeps a
    gap from A instead of being snapped onto it; each run of B's cut within BRIDGE_REACH = 3 mean
    edges of one loop of A, running against it, is joined to that loop's vertices by a strip of
    triangles (no vertex moved or added; :func:`_flip_strip` raises its smallest angles), and the
    strip faces, patches and B faces that still cross another face are dropped (that stretch of
    the seam left open; untangled_pairs counts them). A's faces are all kept unchanged.
    bun000 + bun045 (40k + 40k vertices): 23 s at load 11-19, manifold, oriented, no crossing pair
    (at most BRIDGE_DROP_ROUNDS = 6 rounds of dropping).

    VA, VB: (n, 3) float arrays; FA, FB: (m, 3) integer arrays, each a manifold, consistently
    oriented surface (as :func:`clean` returns it) with the same orientation (outward for a
    closed object); tolerance > 0, in the units of V: the largest distance between the two
    registered surfaces where they overlap (noise plus registration error), well below the size of
    the overlap. Returns a :class:`ZipperedMesh` ``(V, F, report)``: V float64, F int64, manifold
    where the overlap's rim was met by B's triangles, with a :class:`ZipperReport`. Raises
    InputError for bad input or tolerance; Cancelled from ``progress``.
    Time O((m_A + m_B) log m_A) plus the boundary's length.
    """
    tolerance = float(tolerance)
    if not (np.isfinite(tolerance) and tolerance > 0):
        raise InputError(f"tolerance = {tolerance!r}: expected a finite number > 0")
    if not isinstance(seam, str) or seam not in ("clip", "bridge"):
        raise InputError(f"seam = {seam!r}: expected 'clip' or 'bridge'")
    progress = _arguments.progress(progress)
    Va, Fa, _ = remove_unreferenced(VA, FA)
    Vb, Fb, _ = remove_unreferenced(VB, FB)
    loops_a, loops_b = topology.boundary_loops(Fa), topology.boundary_loops(Fb)
    loops_before = len(loops_a) + len(loops_b)

    _arguments.report(progress, 0.0, "zipper: overlap")
    surface = SurfaceDistance(Va, Fa)
    normals_a = face_normals(Va, Fa)

    def covered(points: FloatArray, normals: FloatArray | None = None) -> np.ndarray:
        """Within tolerance of A, at a closest point not on A's boundary (so over A, not beyond it);
        with ``normals``, also facing as A's closest face does (within BRIDGE_NORMAL_ANGLE)."""
        closest = surface.closest_points(points)
        inside = closest.distance <= tolerance
        if len(loops_a):
            inside &= ~_on_boundary(Va, Fa, closest.face, closest.point)
        if normals is not None:
            inside &= np.einsum("ij,ij->i", normals_a[closest.face], normals) >= np.cos(np.radians(BRIDGE_NORMAL_ANGLE))
        return inside

    if seam == "bridge" and len(Fb):
        return _zipper_bridged(Va, Fa, Vb, Fb, loops_a, loops_before, surface, covered, tolerance, progress)
    overlap = covered(Vb[Fb].mean(axis=1)) | covered(Vb)[Fb].any(axis=1)
    removed = int(overlap.sum())
    Fb1, face_map_b = Fb[~overlap], np.flatnonzero(~overlap).astype(np.int64)

    _arguments.report(progress, 0.4, "zipper: clipping")
    snapped = inserted = 0
    Vb1 = Vb.copy()
    on_seam = np.zeros(len(Vb), dtype=bool)
    if len(Fb1) and len(loops_a) and removed:
        cut = np.zeros(len(Vb), dtype=bool)
        sides = boundary_sides(Fb1)
        cut[Fb1[sides[:, 0], sides[:, 1]]] = True
        touched = np.zeros(len(Vb), dtype=bool)
        touched[Fb[overlap].ravel()] = True
        cut &= touched
        candidates = np.flatnonzero(cut)
        if len(candidates):
            edges = np.linalg.norm(Vb[Fb1] - Vb[np.roll(Fb1, -1, axis=1)], axis=2)   # (m, 3): side c's length
            longest = np.zeros(len(Vb))
            np.maximum.at(longest, Fb1.ravel(), edges.ravel())
            np.maximum.at(longest, np.roll(Fb1, -1, axis=1).ravel(), edges.ravel())
            loop, parameter, distance, point = _closest_on_loops(Vb[candidates], Va, loops_a)
            close = distance <= tolerance + 1.5 * longest[candidates]
            close = _unfolding_snaps(Vb, Fb1, candidates, point, close)
            Vb1[candidates[close]] = point[close]
            snapped = int(close.sum())
            where = {int(v): (int(l), float(p)) for v, l, p in
                     zip(candidates[close].tolist(), loop[close].tolist(), parameter[close].tolist())}
            # A face with all three corners on A's rim and its centroid over A is folded onto A's rim faces.
            on_rim = np.zeros(len(Vb), dtype=bool)
            on_rim[candidates[close]] = True
            flat = on_rim[Fb1].all(axis=1)
            flat[flat] = covered(Vb1[Fb1[flat]].mean(axis=1))
            removed += int(flat.sum())
            Fb1, face_map_b = Fb1[~flat], face_map_b[~flat]
            Vb1, Fb1, face_map_b, inserted = _clip_to_loops(Vb1, Fb1, face_map_b, Va, loops_a, where)
            on_seam = np.zeros(len(Vb1), dtype=bool)
            on_seam[list(where)] = True
            on_seam[candidates] = True          # an unsnapped cut vertex may bound a gap too

    _arguments.report(progress, 0.7, "zipper: stitching")
    V = np.vstack([Va, Vb1])
    F = np.vstack([Fa, Fb1 + len(Va)]) if len(Fb1) else Fa
    source = np.concatenate([np.zeros(len(Fa), dtype=np.int64), np.ones(len(Fb1), dtype=np.int64)])
    rows = np.concatenate([np.arange(len(Fa), dtype=np.int64), face_map_b])
    split_edges = merged = 0
    if len(loops_a) and len(Fb1):
        sides = boundary_sides(Fa)
        lengths = np.linalg.norm(Va[Fa[sides[:, 0], sides[:, 1]]] - Va[Fa[sides[:, 0], (sides[:, 1] + 1) % 3]], axis=1)
        stitched = stitch_boundaries(V, F, tolerance=1e-6 * float(lengths.mean()))
        V, F = stitched.V, stitched.F
        source, rows = source[stitched.face_map], rows[stitched.face_map]
        split_edges, merged = stitched.split_edges, stitched.merged_vertices
        degenerate = stitched.removed_faces
    else:
        degenerate = 0
    faces_before_clean = len(F)
    V, F, cleaned = clean(V, F)
    source, rows = source[cleaned.face_map], rows[cleaned.face_map]
    degenerate += faces_before_clean - len(F)

    _arguments.report(progress, 0.85, "zipper: closing the seam")
    fragments = gaps = 0
    if len(F) and len(loops_a) and len(Fb1):
        seam_points = np.vstack([Va[np.concatenate(loops_a)], Vb1[np.flatnonzero(on_seam)]])
        V, F, source, rows, fragments, gaps = _close_seam(V, F, source, rows, seam_points)
    untangled = 0
    if len(F) and len(loops_a) and len(Fb1):
        _arguments.report(progress, 0.9, "zipper: untangling the seam")
        V, F, source, rows, untangled = _untangle_seam(V, F, source, rows, Va, Fa)
    _arguments.report(progress, 1.0, "zipper: done")
    loops_after = len(topology.boundary_loops(F)) if len(F) else 0
    report = ZipperReport(face_source=source, face_map=rows, removed_faces=removed, snapped_vertices=snapped,
                          inserted_vertices=inserted, split_edges=split_edges, merged_vertices=merged,
                          removed_degenerate=degenerate, dropped_fragments=fragments, filled_gaps=gaps,
                          untangled_pairs=untangled,
                          boundary_loops_before=loops_before,
                          boundary_loops_after=loops_after)
    return ZipperedMesh(V, F, report)
