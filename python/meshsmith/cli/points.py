"""`meshsmith normals`: point-cloud normals (§2.2)."""
from __future__ import annotations

from .. import io, points
from .common import ProgressBar


def command_normals(args) -> int:
    P, _ = io.read_points(args.input)
    progress = ProgressBar()
    N = points.estimate_normals(P, k=args.k, radius=args.radius, progress=progress)
    if args.orient:
        N = points.orient_normals(P, N, k=args.k, progress=progress)
    io.write_points(args.output, P, N)
    print(f"wrote {args.output}: {len(P)} points with {'oriented' if args.orient else 'unoriented'} normals")
    return 0


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    normals = commands.add_parser("normals", help="estimate (and orient) point-cloud normals",
                                  description="Estimate normals of a point cloud by PCA of each point's "
                                              "neighbourhood (§2.2); --orient makes them consistent by "
                                              "propagation along a minimum spanning tree (outward for closed shapes).")
    normals.add_argument("input", help="point cloud (XYZ or PLY; a mesh file gives its vertices)")
    normals.add_argument("-o", "--output", required=True, help="output XYZ or PLY with normals")
    normals.add_argument("--k", type=int, default=16, help="neighbours per point (default 16)")
    normals.add_argument("--radius", type=float, help="use all neighbours within this radius instead of k")
    normals.add_argument("--orient", action="store_true", help="orient the normals consistently")
    normals.set_defaults(run=command_normals)
