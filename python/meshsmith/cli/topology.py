"""`meshsmith info`: counts, topology, bounding box, area and volume, and the defects found."""
from __future__ import annotations

import argparse
import json

import numpy as np

from .. import io, repair, topology
from ..repair.defects import DEFECT_COUNTS, INTERSECTION_FACE_LIMIT
from .common import ProgressBar, Stages, add_command, read_faces


def command_info(args: argparse.Namespace) -> int:
    stages = Stages(ProgressBar(), ["reading", "topology", "defects"])
    stages.start("reading")
    V, F = read_faces(args.file)  # quads and other polygons count as themselves
    stages.start("topology")
    summary = topology.info(V, F)
    if isinstance(F, io.Polygons) or F.shape[1] > 3:
        triangles = (F if isinstance(F, io.Polygons) else io.Polygons.from_array(F)).fan_triangles()[0]
    else:
        triangles = F
    stages.start("defects")
    defects = repair.find_defects(V, triangles, intersections=True if args.intersections else None,
                                  progress=stages.part())
    stages.done()
    if args.json:
        print(json.dumps({**summary.as_dict(), "defects": defects.counts()}, indent=2))
        return 0
    print(f"{args.file}")
    print(summary)
    polygons = " (on the polygons' fan triangles)" if triangles is not F else ""
    if not defects.has_defects():
        print(f"defects{polygons}: none found")
        return 0
    print(f"defects{polygons}:")
    width = max(len(words) for words in DEFECT_COUNTS.values())
    for name, value in defects.counts().items():
        if value is None:
            print(f"  {DEFECT_COUNTS[name]:<{width}}  not looked for ({len(np.asarray(triangles)):,} faces > "
                  f"{INTERSECTION_FACE_LIMIT:,}: use --intersections)")
        elif value:
            print(f"  {DEFECT_COUNTS[name]:<{width}}  {value:,}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    info = add_command(
        commands, "info", help="counts, topology, bounding box, area and volume of a mesh, and its defects",
        description="Print counts, topology (components, boundary loops, genus, manifoldness, orientation), "
                    "bounding box, area and volume, then the defects found (§2.4): boundary loops, "
                    "non-manifold edges and vertices, degenerate, zero-area and duplicate faces, unreferenced "
                    "vertices, flipped components and self-intersecting face pairs (looked for up to "
                    f"{INTERSECTION_FACE_LIMIT:,} faces, or always with --intersections). `meshsmith repair` "
                    "fixes them.",
        examples=["meshsmith info mesh.off", "meshsmith info mesh.off --json",
                  "meshsmith info mesh.off --intersections"])
    info.add_argument("file", help="mesh file (OBJ, OFF, PLY, STL)")
    info.add_argument("--json", action="store_true", help="print the figures as JSON (the defects under \"defects\")")
    info.add_argument("--intersections", action="store_true",
                      help=f"look for self-intersections whatever the size (by default up to "
                           f"{INTERSECTION_FACE_LIMIT:,} faces)")
    info.set_defaults(run=command_info)
