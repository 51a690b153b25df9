"""`meshsmith clean`: a manifold, consistently oriented mesh, and what it took (§2.4)."""
from __future__ import annotations

import argparse

from .. import io, repair
from ..repair.clean import CLEAN_COUNTS
from .common import add_command, read_mesh


def command_clean(args: argparse.Namespace) -> int:
    V, F = read_mesh(args.input)
    V2, F2, report = repair.clean(V, F, merge_tolerance=None if args.no_merge else args.merge_tolerance,
                                  remove_degenerate=not args.keep_degenerate,
                                  split_non_manifold=not args.no_split, orient=not args.no_orient,
                                  min_component_faces=args.min_component_faces)
    io.write_mesh(args.output, V2, F2)
    print(f"{args.input}: {len(V):,} vertices, {len(F):,} faces -> {args.output}: {len(V2):,} vertices, "
          f"{len(F2):,} faces")
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
