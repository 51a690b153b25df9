"""`meshsmith clean` and `meshsmith repair`: a manifold, consistently oriented mesh, its holes
filled on request, and what it took (§2.4)."""
from __future__ import annotations

import argparse
import json
from typing import Any

import numpy as np

from .. import io, repair, topology
from ..repair.clean import CLEAN_COUNTS, CleanReport
from .common import MESH_SUFFIXES, ProgressBar, add_command, check_output, integer, number, read_mesh

#: The six orders of a triangle's corners: rotations, then reflections.
_CORNER_ORDERS = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [2, 1, 0], [1, 0, 2]])


def cleaned_attributes(mesh: io.MeshData, V2: np.ndarray, F2: np.ndarray, report: CleanReport) -> dict[str, Any]:
    """The input's attributes on the cleaned mesh, as write_mesh keywords: per-vertex colours (and
    per-vertex normals / UVs, whose index equals F) through report.vertex_map, face colours through
    report.face_map, per-corner normals and UVs through face_map with each output corner matched to
    its input corner (clean may reverse a face or renumber its corners: the order of the input
    corners whose positions match the output's, V_out == V_in[vertex_map])."""
    V, F = np.asarray(mesh.V), np.asarray(mesh.F)
    source = F[report.face_map]                              # (m', 3) input corners of each output face
    exponent = int(np.frexp(np.abs(V).max())[1]) if V.size else 0
    inside, outside = np.ldexp(V[source], -exponent), np.ldexp(V2[F2], -exponent)
    cost = ((outside[:, None, :, :] - inside[:, _CORNER_ORDERS, :]) ** 2).sum(axis=(2, 3))
    order = _CORNER_ORDERS[cost.argmin(axis=1)]             # output corner k = input corner order[f, k]
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


def command_repair(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    V, F = read_mesh(args.input)
    V1, F1, cleaned = repair.clean(V, F, needles_and_caps=args.needles_and_caps)
    lines = [f"clean: {line}" for line in cleaned.lines()]
    record: dict[str, object] = {"input": {"file": args.input, "vertices": len(V), "faces": len(F)},
                                 "clean": cleaned.counts()}
    if args.stitch is not None:
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
        V1, F1, removal = repair.remove_self_intersections(V1, F1, progress=ProgressBar())
        lines += [f"self-intersections: {line}" for line in removal.lines()]
        record["self_intersections"] = removal.counts()
    if args.fill_holes:
        V1, F1, filled = repair.fill_holes(V1, F1, max_hole_edges=args.max_hole, keep_border=args.keep_border,
                                           progress=ProgressBar())
        lines += [f"fill holes: {line}" for line in filled.lines()]
        record["fill_holes"] = {
            **filled.counts(),
            "patches": [{"loop": p.loop, "loop_edges": p.loop_edges, "faces": len(p.faces), "vertices": len(p.vertices),
                         "search": p.search, "max_dihedral_angle": p.max_dihedral_angle,
                         "edge_length_ratio": p.edge_length_ratio} for p in filled.patches],
            "unfilled": [{"loop": loop, "reason": reason} for loop, reason in filled.unfilled],
            "kept_borders": filled.kept_borders.tolist()}
    intersecting = repair.self_intersections(V1, F1) if len(F1) else np.zeros((0, 2), dtype=np.int64)
    loops = len(topology.boundary_loops(F1)) if len(F1) else 0
    record["output"] = {"file": args.output, "vertices": len(V1), "faces": len(F1), "boundary_loops": loops,
                        "manifold": bool(len(F1) and topology.is_manifold(F1)),
                        "self_intersecting_pairs": len(intersecting)}
    lines.append(f"output: {loops:,} boundary loops, {len(intersecting):,} self-intersecting face pairs")
    io.write_mesh(args.output, V1, F1)
    print(f"{args.input}: {len(V):,} vertices, {len(F):,} faces -> {args.output}: {len(V1):,} vertices, "
          f"{len(F1):,} faces")
    for line in lines:
        print(f"  {line}")
    if args.report:
        with open(args.report, "w") as stream:
            json.dump(record, stream, indent=2)
    return 0


def register_repair(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    command = add_command(
        commands, "repair", help="repair a mesh: clean, stitch cracks, fill holes; report what changed",
        description="Repair a triangle mesh (§2.4): clean it (as `meshsmith clean`, with --needles-and-caps "
                    "also collapsing needles and flipping caps), stitch boundary vertices and T-junctions "
                    "closer than --stitch, cut out self-intersecting faces and fill the holes this leaves "
                    "with --remove-self-intersections (repeated until none is left, at most 6 rounds), fill its holes with --fill-holes (Liepa: minimal-weight "
                    "triangulation, refinement, bi-Laplacian fairing; --max-hole N fills only loops of at "
                    "most N edges, --keep-border leaves open the rim of an open surface), then count what is "
                    "left: boundary loops and self-intersecting face pairs. Prints what was fixed; "
                    "--report writes it all as JSON, with each patch's largest dihedral angle and "
                    "edge-length ratio.",
        examples=["meshsmith repair mesh.off -o repaired.obj",
                  "meshsmith repair disk.obj -o closed.obj --fill-holes --max-hole 100 --report report.json",
                  "meshsmith repair mesh.off -o fixed.ply --remove-self-intersections --fill-holes"])
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
    command.add_argument("--report", metavar="FILE", help="write what was changed as JSON")
    command.set_defaults(run=command_repair)
