"""`meshsmith triangulate|voronoi|crust|power`: planar tessellation and Voronoi filtering (§2.1)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import InputError, io, render, tessellation
from .common import ProgressBar


def read_planar(path: str):
    """Planar input of the tessellation commands: a Triangle ``.poly`` file (vertices, segments,
    holes), or a text file of ``x y`` or ``x y w`` lines (w: a weight, used by ``power``).
    Returns (P (n, 2), segments or None, holes or None, weights or None)."""
    if path.lower().endswith(".poly"):
        P, segments, holes = io.read_poly(path)
        return P, segments, holes, None
    if not Path(path).is_file():
        raise InputError(f"{path} does not exist")
    try:
        table = np.loadtxt(path, ndmin=2, comments="#")
    except ValueError as error:
        raise InputError(f"{path}: not a table of numbers ({error})") from None
    if table.shape[1] not in (2, 3) or len(table) == 0:
        raise InputError(f"{path}: expected lines of 'x y' or 'x y w', found {table.shape[1]} columns")
    if not np.isfinite(table).all():
        raise InputError(f"{path}: holds NaN or Inf")
    return table[:, :2], None, None, (table[:, 2] if table.shape[1] == 3 else None)


def _write_planar_mesh(path: str, V2: np.ndarray, F: np.ndarray) -> None:
    if path.lower().endswith(".png"):
        render.plot_planar(path, triangles=(V2, F), title=Path(path).stem)
    else:
        io.write_mesh(path, np.column_stack([V2, np.zeros(len(V2))]), F)


def command_triangulate(args) -> int:
    P, segments, holes, _ = read_planar(args.input)
    # Without segments (a plain point set) the domain is the points' convex hull.
    V2, F, steiner = tessellation.refine(P, segments, holes, min_angle=args.min_angle,
                                         max_area=args.max_area, progress=ProgressBar())
    _write_planar_mesh(args.output, V2, F)
    if args.picture:
        render.plot_planar(args.picture, triangles=(V2, F), highlight=V2[len(P):],
                           title=f"{Path(args.input).name}: min angle {args.min_angle}°, {steiner} Steiner points")
    angles = tessellation.triangle_angles(V2, F)
    print(f"wrote {args.output}: {len(V2)} vertices ({steiner} Steiner points), {len(F)} triangles, "
          f"smallest angle {angles.min():.2f}°")
    return 0


def command_voronoi(args) -> int:
    P, _, _, _ = read_planar(args.input)
    diagram = tessellation.voronoi(P)
    render.plot_planar(args.output, polygons=diagram.cells, points=P,
                       title=f"Voronoi diagram of {len(P)} sites")
    print(f"wrote {args.output}: {len(diagram.vertices)} Voronoi vertices, {len(diagram.cells)} cells")
    return 0


def command_power(args) -> int:
    P, _, _, weights = read_planar(args.input)
    if weights is None:
        raise InputError(f"{args.input}: power diagrams need a weight per site: lines of 'x y w'")
    diagram = tessellation.power_diagram(P, weights)
    render.plot_planar(args.output, polygons=[cell for cell in diagram.cells if len(cell)], points=P,
                       highlight=P[diagram.hidden] if len(diagram.hidden) else None,
                       title=f"power diagram of {len(P)} sites ({len(diagram.hidden)} hidden)")
    print(f"wrote {args.output}: {len(P)} sites, {len(diagram.hidden)} with empty cells")
    return 0


def command_crust(args) -> int:
    suffix = Path(args.input).suffix.lower()
    if suffix in (".poly", ".txt", ".xy", ".csv") or (suffix not in (".xyz", ".ply", ".obj", ".off", ".stl")):
        P, _, _, _ = read_planar(args.input)
    else:
        P, _ = io.read_points(args.input) if suffix in (".xyz", ".ply") else (io.read_mesh(args.input)[0], None)
        if np.ptp(P[:, 2]) == 0.0:            # samples of a planar curve stored with z = 0
            P = P[:, :2]
    if P.shape[1] == 2:
        edges = tessellation.crust(P)
        if not args.output.lower().endswith(".png"):
            raise InputError(f"output {args.output}: the 2D crust is a curve; write it as a .png picture")
        render.plot_planar(args.output, segments=(P, edges), points=P,
                           title=f"crust of {len(P)} samples: {len(edges)} edges")
        print(f"wrote {args.output}: {len(edges)} curve edges through {len(P)} samples")
        return 0
    V, F = tessellation.crust_3d(P, progress=ProgressBar())
    if args.output.lower().endswith(".png"):
        render.render(V, F, args.output, title=f"Cocone crust of {len(P)} points")
    else:
        io.write_mesh(args.output, V, F)
    print(f"wrote {args.output}: {len(F)} triangles over {len(V)} points")
    return 0


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    triangulate = commands.add_parser("triangulate", help="quality triangulation of a planar domain",
                                      description="Delaunay refinement (§2.1.1) of a planar straight-line "
                                                  "graph (.poly: vertices, segments, holes) or of a point set "
                                                  "(x y lines): every angle >= --min-angle (guaranteed up to 20.7°, "
                                                  "in practice up to ~33°).")
    triangulate.add_argument("input", help=".poly file, or a text file of 'x y' lines")
    triangulate.add_argument("-o", "--output", required=True, help="mesh file (.obj, .ply, .off; z = 0) or .png")
    triangulate.add_argument("--min-angle", type=float, default=20.7, help="degrees (default 20.7)")
    triangulate.add_argument("--max-area", type=float, help="largest triangle area")
    triangulate.add_argument("--picture", help="also write a PNG of the triangulation (Steiner points in red)")
    triangulate.set_defaults(run=command_triangulate)

    voronoi = commands.add_parser("voronoi", help="Voronoi diagram of planar sites, as a picture",
                                  description="Voronoi cells (§2.1.1) of planar sites, clipped to their "
                                              "bounding box enlarged by 10%%, drawn as a PNG.")
    voronoi.add_argument("input", help=".poly file, or a text file of 'x y' lines")
    voronoi.add_argument("-o", "--output", required=True, help="output PNG")
    voronoi.set_defaults(run=command_voronoi)

    crust = commands.add_parser("crust", help="reconstruct a curve (2D) or a surface (3D) from samples",
                                description="Voronoi filtering (§2.1.3): the crust of 2D curve samples "
                                            "(drawn as a PNG), or the Cocone crust of a 3D point cloud "
                                            "(written as a mesh or rendered as a PNG).")
    crust.add_argument("input", help="2D: .poly or 'x y' text; 3D: .xyz, .ply or a mesh file's vertices")
    crust.add_argument("-o", "--output", required=True, help="2D: a .png; 3D: a mesh file or a .png")
    crust.set_defaults(run=command_crust)

    power = commands.add_parser("power", help="power diagram of weighted planar sites, as a picture",
                                description="Power diagram (§2.1.4) of weighted sites (lines of 'x y w', "
                                            "w a squared radius), drawn as a PNG; hidden sites in red.")
    power.add_argument("input", help="text file of 'x y w' lines")
    power.add_argument("-o", "--output", required=True, help="output PNG")
    power.set_defaults(run=command_power)
