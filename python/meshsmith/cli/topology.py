"""`meshsmith info`: counts, topology, bounding box, area and volume."""
from __future__ import annotations

import argparse
import json

from .. import topology
from .common import add_command, read_faces


def command_info(args: argparse.Namespace) -> int:
    V, F = read_faces(args.file)  # quads and other polygons count as themselves
    summary = topology.info(V, F)
    if args.json:
        print(json.dumps(summary.as_dict(), indent=2))
    else:
        print(f"{args.file}")
        print(summary)
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    info = add_command(
        commands, "info", help="counts, topology, bounding box, area and volume of a mesh",
        description="Print counts, topology (components, boundary loops, genus, manifoldness, orientation), "
                    "bounding box, area and volume.",
        examples=["meshsmith info mesh.off", "meshsmith info mesh.off --json"])
    info.add_argument("file", help="mesh file (OBJ, OFF, PLY, STL)")
    info.add_argument("--json", action="store_true", help="print the figures as JSON")
    info.set_defaults(run=command_info)
