"""`meshsmith clean` and `meshsmith repair`: a manifold, consistently oriented mesh, its holes
filled on request, and what it took (§2.4)."""
from __future__ import annotations

import argparse
import json
from typing import Any, NamedTuple

import numpy as np

from .. import InputError, geometry, io, repair, topology
from ..repair.clean import CLEAN_COUNTS, CleanReport
from ..repair.zipper import barycentric
from .common import MESH_SUFFIXES, ProgressBar, Stages, UsageError, add_command, check_output, integer, number
from .io import refused_attribute

#: The six orders of a triangle's corners: rotations, then reflections.
_CORNER_ORDERS = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [2, 1, 0], [1, 0, 2]])


def _corner_orders(V_in: np.ndarray, corners_in: np.ndarray, V_out: np.ndarray, corners_out: np.ndarray) -> np.ndarray:
    """(k, 3) for k face pairs (corners_in[f] of V_in, corners_out[f] of V_out, the same triangle up
    to a renumbering of its corners or a reversal): output corner j is input corner order[f, j],
    the order whose positions match best (merged vertices moved slightly). Scaled by a power of two
    (exact), so any coordinate range works."""
    exponent = int(np.frexp(np.abs(V_in).max())[1]) if V_in.size else 0
    inside, outside = np.ldexp(V_in[corners_in], -exponent), np.ldexp(V_out[corners_out], -exponent)
    cost = ((outside[:, None, :, :] - inside[:, _CORNER_ORDERS, :]) ** 2).sum(axis=(2, 3))
    return _CORNER_ORDERS[cost.argmin(axis=1)]


def cleaned_attributes(mesh: io.MeshData, V2: np.ndarray, F2: np.ndarray, report: CleanReport) -> dict[str, Any]:
    """The input's attributes on the cleaned mesh, as write_mesh keywords: per-vertex colours (and
    per-vertex normals / UVs, whose index equals F) through report.vertex_map, face colours through
    report.face_map, per-corner normals and UVs through face_map with each output corner matched to
    its input corner (clean may reverse a face or renumber its corners: the order of the input
    corners whose positions match the output's, V_out == V_in[vertex_map])."""
    V, F = np.asarray(mesh.V), np.asarray(mesh.F)
    order = _corner_orders(V, F[report.face_map], V2, F2)   # output corner k = input corner order[f, k]
    rows = np.arange(len(F2))[:, None]
    kept: dict[str, Any] = {}
    if mesh.colors is not None:
        kept["colors"] = mesh.colors[report.vertex_map]
    if mesh.face_colors is not None:
        kept["face_colors"] = mesh.face_colors[report.face_map]
    for values, index, value_name, index_name in ((mesh.normals, mesh.F_normal, "normals", "F_normal"),
                                                  (mesh.UV, mesh.F_uv, "UV", "F_uv")):
        if values is None:
            continue
        index = np.asarray(index)
        if np.array_equal(index, F):  # per vertex: follows the vertices
            kept[value_name], kept[index_name] = values[report.vertex_map], F2
        else:                          # per corner: follows the corners
            kept[value_name], kept[index_name] = values, index[report.face_map][rows, order]
    return kept


class CarriedAttributes(NamedTuple):
    """:func:`carried_attributes`' result: the write_mesh keywords, and how many faces kept their
    values exactly, how many faces and vertices got interpolated ones."""

    attributes: dict[str, Any]
    kept_faces: int
    interpolated_faces: int
    interpolated_vertices: int


def carried_attributes(source: io.MeshData, V2: np.ndarray, F2: np.ndarray) -> CarriedAttributes:
    """The attributes of a triangle mesh `source` carried onto (V2, F2), a mesh a repair step made
    from it (stitching, hole filling, cutting out self-intersections, a volumetric remesh).

    A face of F2 whose three corner positions are those of a source face keeps that face's values
    exactly (corners matched as in :func:`cleaned_attributes`), and a vertex at a source vertex's
    position keeps its per-vertex values. Every other face and vertex (a hole patch, a face split
    at a T-junction, every face of a remesh) gets values interpolated at the closest point of the
    source surface (barycentric in that source face; a corner looks from slightly inside its own
    face, so it reads the source face on its side of a UV seam): colours and UVs blend their
    neighbours', normals are blended and renormalized, a face colour is its centroid's nearest
    source face's. Returns a :class:`CarriedAttributes`."""
    V, F = np.asarray(source.V, dtype=np.float64), np.asarray(source.F)
    V2, F2 = np.asarray(V2, dtype=np.float64), np.asarray(F2)
    _, position = np.unique(np.vstack([V, V2]), axis=0, return_inverse=True)
    position = position.reshape(-1)
    here, there = position[:len(V)], position[len(V):]
    vertex_of_position = np.full(position.max() + 1, -1, dtype=np.int64)
    vertex_of_position[here[::-1]] = np.arange(len(V))[::-1]          # the first source vertex there
    vertex_source = vertex_of_position[there]                            # (n2,) or -1
    face_key = {tuple(key): f for f, key in enumerate(np.sort(here[F], axis=1).tolist())}
    face_source = np.array([face_key.get(tuple(key), -1) for key in np.sort(there[F2], axis=1).tolist()],
                           dtype=np.int64).reshape(-1)
    kept_faces, new_faces = np.flatnonzero(face_source >= 0), np.flatnonzero(face_source < 0)
    new_vertices = np.flatnonzero(vertex_source < 0)
    order = _corner_orders(V, F[face_source[kept_faces]], V2, F2[kept_faces])
    tree = geometry.SurfaceDistance(V, F) if len(new_faces) or len(new_vertices) else None

    def interpolate(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(source face (k,), barycentric weights (k, 3)) at the closest points of `points`."""
        if tree is None or not len(points):
            return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
        closest = tree.closest_points(points)
        return closest.face, barycentric(closest.point, V[F[closest.face]])

    vertex_face, vertex_weights = interpolate(V2[new_vertices])
    corners = F2[new_faces]                                               # (k, 3) output corners of new faces
    centroids = V2[corners].mean(axis=1)
    looks = V2[corners] + 1e-6 * (centroids[:, None, :] - V2[corners])  # from slightly inside the face
    corner_face, corner_weights = interpolate(looks.reshape(-1, 3))

    def per_vertex(values: np.ndarray, unit: bool) -> np.ndarray:
        out = np.empty((len(V2), values.shape[1]))
        known = vertex_source >= 0
        out[known] = values[vertex_source[known]]
        if len(new_vertices):
            blended = np.einsum("kj,kjc->kc", vertex_weights, values[F[vertex_face]])
            out[new_vertices] = _unit_rows(blended) if unit else blended
        return out

    attributes: dict[str, Any] = {}
    if source.colors is not None:
        attributes["colors"] = np.clip(per_vertex(np.asarray(source.colors, dtype=np.float64), False), 0.0, 1.0)
    if source.face_colors is not None:
        colours = np.asarray(source.face_colors, dtype=np.float64)
        face_colours = np.empty((len(F2), colours.shape[1]))
        face_colours[kept_faces] = colours[face_source[kept_faces]]
        if len(new_faces):
            face_colours[new_faces] = colours[tree.closest_points(centroids).face] if tree else 0.0
        attributes["face_colors"] = face_colours
    for values, index, value_name, index_name in ((source.normals, source.F_normal, "normals", "F_normal"),
                                                  (source.UV, source.F_uv, "UV", "F_uv")):
        if values is None:
            continue
        values, index = np.asarray(values, dtype=np.float64), np.asarray(index)
        unit = value_name == "normals"
        if np.array_equal(index, F):                                       # per vertex
            attributes[value_name], attributes[index_name] = per_vertex(values, unit), F2
            continue
        out_index = np.empty_like(F2)
        out_index[kept_faces] = index[face_source[kept_faces]][np.arange(len(kept_faces))[:, None], order]
        table = [values]
        if len(new_faces):
            source_corners = index[corner_face]                            # (3k, 3) value rows, -1 where none
            has = (source_corners >= 0).all(axis=1)
            blended = np.einsum("kj,kjc->kc", corner_weights[has], values[source_corners[has]])
            rows = np.full(len(source_corners), -1, dtype=np.int64)
            rows[has] = len(values) + np.arange(int(has.sum()))
            out_index[new_faces] = rows.reshape(-1, 3)
            table.append(_unit_rows(blended) if unit else blended)
        attributes[value_name], attributes[index_name] = np.vstack(table), out_index
    return CarriedAttributes(attributes, len(kept_faces), len(new_faces), len(new_vertices))


def _unit_rows(vectors: np.ndarray) -> np.ndarray:
    length = np.linalg.norm(vectors, axis=1, keepdims=True)
    return vectors / np.where(length > 0, length, 1.0)


def command_clean(args: argparse.Namespace) -> int:
    mesh = io.read_mesh(args.input, return_attributes=True)  # triangulated: F is an (m, 3) array
    V, F = mesh.V, np.asarray(mesh.F)
    V2, F2, report = repair.clean(V, F, merge_tolerance=None if args.no_merge else args.merge_tolerance,
                                  remove_degenerate=not args.keep_degenerate,
                                  split_non_manifold=not args.no_split, orient=not args.no_orient,
                                  min_component_faces=args.min_component_faces)
    attributes = cleaned_attributes(mesh, V2, F2, report)
    io.write_mesh(args.output, V2, F2, **attributes)
    names = [name for name in ("normals", "UV", "colors", "face_colors") if name in attributes]
    print(f"{args.input}: {len(V):,} vertices, {len(F):,} faces -> {args.output}: {len(V2):,} vertices, "
          f"{len(F2):,} faces" + (f", with {', '.join(names)}" if names else ""))
    width = max(len(words) for words in CLEAN_COUNTS.values())
    for name, count in report.counts().items():
        print(f"  {CLEAN_COUNTS[name]:<{width}}  {count:,}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    clean = add_command(
        commands, "clean", help="clean a mesh: merge, remove degenerate faces, split non-manifold, orient",
        description="Clean a triangle mesh (§2.4): merge coincident vertices (or those within "
                    "--merge-tolerance), remove faces with a repeated vertex, of zero area or duplicated, "
                    "split non-manifold vertices and edges, remove components smaller than "
                    "--min-component-faces, orient every component consistently (closed ones outward) and "
                    "remove unreferenced vertices. Prints one line per kind of change, with its count.",
        examples=["meshsmith clean mesh.off -o clean.obj",
                  "meshsmith clean mesh.off -o merged.ply --merge-tolerance 1e-6 --min-component-faces 10"])
    clean.add_argument("input", help="mesh file (.obj, .ply, .off, .stl)")
    clean.add_argument("-o", "--output", required=True, help="cleaned mesh file (format from the extension)")
    merging = clean.add_mutually_exclusive_group()
    merging.add_argument("--merge-tolerance", type=float, default=0.0, metavar="D",
                         help="merge vertices at distance <= D, transitively (default 0: exactly coincident ones)")
    merging.add_argument("--no-merge", action="store_true", help="merge no vertices")
    clean.add_argument("--min-component-faces", type=int, default=0, metavar="N",
                       help="remove connected components with fewer than N faces (default 0: keep all)")
    clean.add_argument("--keep-degenerate", action="store_true",
                       help="keep faces with a repeated vertex, of zero area or duplicated")
    clean.add_argument("--no-split", action="store_true", help="leave non-manifold vertices and edges as they are")
    clean.add_argument("--no-orient", action="store_true", help="leave the faces' orientation as it is")
    clean.set_defaults(run=command_clean)
    register_repair(commands)


#: The attribute names of write_mesh's keywords, with the index array that goes with each.
_ATTRIBUTE_INDEX = {"normals": "F_normal", "UV": "F_uv", "colors": None, "face_colors": None}


def _write_keeping_what_fits(path: str, V: np.ndarray, F: np.ndarray,
                             attributes: dict[str, Any]) -> tuple[list[str], dict[str, str]]:
    """Write the mesh with every attribute the format can hold: (names written, {name dropped: why})."""
    attributes = dict(attributes)
    dropped: dict[str, str] = {}
    while True:
        try:
            io.write_mesh(path, V, F, **attributes)
            return [name for name in _ATTRIBUTE_INDEX if name in attributes], dropped
        except InputError as error:
            name = refused_attribute(error)
            if name is None or name not in attributes:
                raise
            dropped[name] = str(error).split(": ", 1)[-1]
            attributes.pop(name)
            attributes.pop(_ATTRIBUTE_INDEX[name] or "", None)


def command_repair(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    if args.volumetric is not None and (args.fill_holes or args.stitch is not None or args.remove_self_intersections):
        raise UsageError("--volumetric rebuilds the whole surface closed: it replaces --fill-holes, --stitch and "
                         "--remove-self-intersections, give one or the other")
    if args.rho is not None and args.volumetric is None:
        raise UsageError("--rho is the gap width that --volumetric closes; give --volumetric EPS too")
    for flag, given in (("--max-hole", args.max_hole is not None), ("--keep-border", args.keep_border)):
        if given and not args.fill_holes:
            raise UsageError(f"{flag} chooses the holes --fill-holes fills; give --fill-holes too")
    steps = ["reading", "cleaning"] + (["stitching"] if args.stitch is not None else []) \
        + (["self-intersections"] if args.remove_self_intersections else []) \
        + (["filling holes"] if args.fill_holes else []) + (["volumetric"] if args.volumetric is not None else []) \
        + ["checking", "writing"]
    stages = Stages(ProgressBar(), steps)
    stages.start("reading")
    mesh = io.read_mesh(args.input, return_attributes=True)   # triangulated: F is an (m, 3) array
    V, F = mesh.V, np.asarray(mesh.F)
    stages.start("cleaning")
    V1, F1, cleaned = repair.clean(V, F, needles_and_caps=args.needles_and_caps)
    cleaned_mesh = io.MeshData(V1, F1, **cleaned_attributes(mesh, V1, F1, cleaned))
    lines = [f"clean: {line}" for line in cleaned.lines()]
    record: dict[str, object] = {"input": {"file": args.input, "vertices": len(V), "faces": len(F),
                                           "attributes": mesh.attributes},
                                 "clean": cleaned.counts()}
    if args.stitch is not None:
        stages.start("stitching")
        stitched = repair.stitch_boundaries(V1, F1, tolerance=args.stitch)
        V1, F1, again = repair.clean(stitched.V, stitched.F)
        counts = {"split_edges": stitched.split_edges, "inserted_vertices": stitched.inserted_vertices,
                  "merged_vertices": stitched.merged_vertices, "removed_faces": stitched.removed_faces,
                  "boundary_edges_before": stitched.boundary_edges_before,
                  "boundary_edges_after": stitched.boundary_edges_after}
        record["stitch"] = {**counts, "clean_after": again.counts()}
        lines.append(f"stitch: {stitched.merged_vertices:,} boundary vertices merged, {stitched.inserted_vertices:,} "
                     f"T-junctions inserted; boundary edges {stitched.boundary_edges_before:,} -> "
                     f"{stitched.boundary_edges_after:,}")
    if args.remove_self_intersections:
        stages.start("self-intersections")
        V1, F1, removal = repair.remove_self_intersections(V1, F1, progress=stages.part())
        lines += [f"self-intersections: {line}" for line in removal.lines()]
        record["self_intersections"] = removal.counts()
    if args.fill_holes:
        stages.start("filling holes")
        V1, F1, filled = repair.fill_holes(V1, F1, max_hole_edges=args.max_hole, keep_border=args.keep_border,
                                           progress=stages.part())
        lines += [f"fill holes: {line}" for line in filled.lines()]
        record["fill_holes"] = {
            **filled.counts(),
            "patches": [{"loop": p.loop, "loop_edges": p.loop_edges, "faces": len(p.faces), "vertices": len(p.vertices),
                         "search": p.search, "max_dihedral_angle": p.max_dihedral_angle,
                         "edge_length_ratio": p.edge_length_ratio} for p in filled.patches],
            "unfilled": [{"loop": loop, "reason": reason} for loop, reason in filled.unfilled],
            "kept_borders": filled.kept_borders.tolist()}
    if args.volumetric is not None:
        stages.start("volumetric")
        if not len(F1):
            raise InputError(f"{args.input}: no face is left after cleaning: nothing to rebuild")
        V1, F1, rebuilt = repair.volumetric_repair(V1, F1, epsilon=args.volumetric, rho=args.rho or 0.0,
                                                   progress=stages.part())
        record["volumetric"] = {"epsilon": args.volumetric, "rho": args.rho or 0.0, "shape": list(rebuilt.shape),
                                "cell_size": rebuilt.cell_size, "stored_cells": rebuilt.stored_cells,
                                "occupied_cells": rebuilt.occupied_cells,
                                "inside_cells": rebuilt.inside_cells, "closing_cells": rebuilt.closing_cells,
                                "manifold_cells": rebuilt.manifold_cells, "sharp_vertices": rebuilt.sharp_vertices,
                                "unconstrained_vertices": rebuilt.unconstrained_vertices,
                                "untangled_vertices": rebuilt.untangled_vertices, "fine_faces": rebuilt.fine_faces,
                                "faces": len(F1)}
        nx, ny, nz = rebuilt.shape
        lines.append(f"volumetric: rebuilt on a {nx} x {ny} x {nz} grid of cell {rebuilt.cell_size:.6g} "
                     f"(epsilon {args.volumetric:g}, rho {args.rho or 0.0:g}; {rebuilt.stored_cells:,} cells stored, "
                     f"near the surface); {rebuilt.closing_cells:,} cells closed "
                     f"by rho, {rebuilt.sharp_vertices:,} vertices on sharp features, "
                     f"{rebuilt.unconstrained_vertices:,} over holes and gaps; {len(F1):,} faces "
                     f"({rebuilt.fine_faces:,} before flat regions were merged)")
    stages.start("checking")
    intersecting = repair.self_intersections(V1, F1) if len(F1) else np.zeros((0, 2), dtype=np.int64)
    loops = len(topology.boundary_loops(F1)) if len(F1) else 0
    closed = bool(len(F1) and loops == 0)
    record["output"] = {"file": args.output, "vertices": len(V1), "faces": len(F1), "boundary_loops": loops,
                        "manifold": bool(len(F1) and topology.is_manifold(F1)),
                        "self_intersecting_pairs": len(intersecting)}
    if closed:
        record["output"]["volume"] = geometry.volume(V1, F1)  # type: ignore[index]
    lines.append(f"output: {loops:,} boundary loops, {len(intersecting):,} self-intersecting face pairs")
    stages.start("writing")
    carried = carried_attributes(cleaned_mesh, V1, F1) if mesh.attributes and len(F1) else None
    written, dropped = _write_keeping_what_fits(args.output, V1, F1, carried.attributes if carried else {})
    if mesh.attributes:
        lines += _attribute_lines(mesh.attributes, carried, written, dropped, volumetric=args.volumetric is not None)
        record["attributes"] = {
            "input": mesh.attributes, "written": written, "dropped": dropped,
            "kept_faces": carried.kept_faces if carried else 0,
            "interpolated_faces": carried.interpolated_faces if carried else 0,
            "interpolated_vertices": carried.interpolated_vertices if carried else 0}
    stages.done()
    print(f"{args.input}: {len(V):,} vertices, {len(F):,} faces -> {args.output}: {len(V1):,} vertices, "
          f"{len(F1):,} faces")
    for line in lines:
        print(f"  {line}")
    if args.report:
        with open(args.report, "w") as stream:
            json.dump(record, stream, indent=2)
    return 0


def _attribute_lines(present: list[str], carried: CarriedAttributes | None, written: list[str],
                     dropped: dict[str, str], *, volumetric: bool) -> list[str]:
    """The report's lines about the input's attributes: kept, interpolated where, dropped and why."""
    lines = []
    if written and carried is not None:
        new = (f"interpolated from the nearest input surface on {carried.interpolated_faces:,} new faces and "
               f"{carried.interpolated_vertices:,} new vertices"
               + (" (the volumetric remesh makes every face new)" if volumetric else ""))
        if not carried.kept_faces:
            lines.append(f"attributes: {', '.join(written)} {new}")
        else:
            lines.append(f"attributes: {', '.join(written)} kept exactly on {carried.kept_faces:,} faces"
                         + (f", {new}" if carried.interpolated_faces or carried.interpolated_vertices else ""))
    for name, reason in dropped.items():
        lines.append(f"attributes: {name} dropped: {reason}")
    if carried is None:
        lines.append(f"attributes: {', '.join(present)} dropped: no face is left")
    return lines


def register_repair(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    command = add_command(
        commands, "repair", help="repair a mesh: clean, stitch cracks, fill holes; report what changed",
        description="Repair a triangle mesh (§2.4): clean it (as `meshsmith clean`, with --needles-and-caps "
                    "also collapsing needles and flipping caps), stitch boundary vertices and T-junctions "
                    "closer than --stitch, cut out self-intersecting faces and fill the holes this leaves "
                    "with --remove-self-intersections (repeated until none is left, at most 6 rounds), fill its holes with --fill-holes (Liepa: minimal-weight "
                    "triangulation, refinement, bi-Laplacian fairing; --max-hole N fills only loops of at "
                    "most N edges, --keep-border leaves open the rim of an open surface), then count what is "
                    "left: boundary loops and self-intersecting face pairs. --volumetric EPS instead "
                    "rebuilds the whole surface closed and manifold on voxels of diagonal EPS (closing "
                    "gaps up to about 2 x --rho). The input's normals, UVs and colours are kept where "
                    "its faces survive and interpolated on new faces; one the output format cannot hold "
                    "is dropped and named. Prints what was fixed; --report writes it all as JSON, with "
                    "each patch's largest dihedral angle and edge-length ratio.",
        examples=["meshsmith repair mesh.off -o repaired.obj",
                  "meshsmith repair disk.obj -o closed.obj --fill-holes --max-hole 100 --report report.json",
                  "meshsmith repair mesh.off -o fixed.ply --remove-self-intersections --fill-holes",
                  "meshsmith repair disk.obj -o solid.ply --volumetric 0.05 --rho 0.1 --report report.json"])
    command.add_argument("input", help="mesh file (.obj, .ply, .off, .stl)")
    command.add_argument("-o", "--output", required=True, help="repaired mesh file (format from the extension)")
    command.add_argument("--fill-holes", action="store_true", help="fill the holes (every boundary loop by default)")
    command.add_argument("--max-hole", type=integer(3), default=None, metavar="N",
                         help="with --fill-holes: fill only holes of at most N edges")
    command.add_argument("--keep-border", action="store_true",
                         help="with --fill-holes: leave open each component's longest loop when it is at least "
                              "twice as long as each other (a scan's rim)")
    command.add_argument("--stitch", type=number(0.0, open_low=True), default=None, metavar="D",
                         help="stitch boundary vertices and T-junctions closer than D")
    command.add_argument("--remove-self-intersections", action="store_true",
                         help="cut out the self-intersecting faces and fill the holes this leaves, until none is left")
    command.add_argument("--needles-and-caps", action="store_true",
                         help="collapse needles and flip caps while cleaning")
    command.add_argument("--volumetric", type=number(0.0, open_low=True), default=None, metavar="EPS",
                         help="rebuild the surface closed and manifold on a voxel grid of cell diagonal EPS "
                              "(volumetric repair, §2.4.2): every hole, gap, self-intersection and overlap "
                              "goes; instead of --fill-holes, --stitch and --remove-self-intersections")
    command.add_argument("--rho", type=number(0.0), default=None, metavar="R",
                         help="with --volumetric: also close gaps and holes up to about 2R wide (default 0)")
    command.add_argument("--report", metavar="FILE", help="write what was changed as JSON")
    command.set_defaults(run=command_repair)
