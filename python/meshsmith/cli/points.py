"""`meshsmith normals`: point-cloud normals (§2.2)."""
from __future__ import annotations

import argparse

from .. import io, points
from .common import (
    ProgressBar,
    add_command,
    check_output,
    integer,
    number,
    read_point_cloud,
)


def command_normals(args: argparse.Namespace) -> int:
    check_output(args.output, (".xyz", ".ply"), "-o")
    P = read_point_cloud(args.input)
    progress = ProgressBar()
    N = points.estimate_normals(P, k=args.k, radius=args.radius, progress=progress)
    if args.orient:
        N = points.orient_normals(P, N, k=args.k, progress=progress)
    io.write_points(args.output, P, N)
    print(f"wrote {args.output}: {len(P)} points with {'oriented' if args.orient else 'unoriented'} normals")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    normals = add_command(
        commands, "normals", help="estimate (and orient) point-cloud normals",
        description="Estimate normals of a point cloud by PCA of each point's neighbourhood (§2.2); --orient "
                    "makes them consistent by propagation along a minimum spanning tree (outward for closed "
                    "shapes). A mesh file (OBJ, OFF, STL) gives its vertices; its faces are ignored.",
        examples=["meshsmith normals points.xyz -o normals.xyz",
                  "meshsmith normals points.xyz -o oriented.ply --k 12 --orient",
                  "meshsmith normals mesh.off -o vertices.xyz --radius 0.3"])
    normals.add_argument("input", help="point cloud (XYZ or PLY; a mesh file (OBJ, OFF, STL) gives its vertices)")
    normals.add_argument("-o", "--output", required=True, help="output XYZ or PLY with normals")
    normals.add_argument("--k", type=integer(3, 10_000), default=16, help="neighbours per point, 3 to 10000 "
                         "(default 16)")
    normals.add_argument("--radius", type=number(0, open_low=True), help="use all neighbours within this radius instead of k")
    normals.add_argument("--orient", action="store_true", help="orient the normals consistently")
    normals.set_defaults(run=command_normals)
