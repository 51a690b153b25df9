"""`meshsmith triangulate|voronoi|crust|power`: planar tessellation and Voronoi filtering (§2.1)."""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .. import InputError, io, render, tessellation
from .common import (
    MESH_SUFFIXES,
    POINT_CLOUD_SUFFIXES,
    ProgressBar,
    add_command,
    check_output,
    integer,
    number,
    read_point_cloud,
)


def read_planar(path: str) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None, np.ndarray | None]:
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


#: Extensions read as planar input (a .poly file or x y text) by crust; mesh and point-cloud files are 3D.
PLANAR_SUFFIXES = (".poly", ".txt", ".xy", ".csv")


def _write_planar_mesh(path: str, V2: np.ndarray, F: np.ndarray) -> None:
    if path.lower().endswith(".png"):
        render.plot_planar(path, triangles=(V2, F), title=Path(path).stem)
    else:
        io.write_mesh(path, np.column_stack([V2, np.zeros(len(V2))]), F)


def command_triangulate(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES + (".png",), "-o")
    if args.picture:
        check_output(args.picture, (".png",), "--picture")
    P, segments, holes, _ = read_planar(args.input)
    # Without segments (a plain point set) the domain is the points' convex hull.
    V2, F, steiner = tessellation.refine(P, segments, holes, min_angle=args.min_angle,
                                         max_area=args.max_area, max_steiner_points=args.max_steiner_points,
                                         progress=ProgressBar())
    _write_planar_mesh(args.output, V2, F)
    if args.picture:
        render.plot_planar(args.picture, triangles=(V2, F), highlight=V2[len(P):],
                           title=f"{Path(args.input).name}: min angle {args.min_angle}°, {steiner} Steiner points")
    angles = tessellation.triangle_angles(V2, F)
    print(f"wrote {args.output}: {len(V2)} vertices ({steiner} Steiner points), {len(F)} triangles, "
          f"smallest angle {angles.min():.2f}°")
    return 0


def command_voronoi(args: argparse.Namespace) -> int:
    check_output(args.output, (".png",), "-o")
    P, _, _, _ = read_planar(args.input)
    diagram = tessellation.voronoi(P)
    render.plot_planar(args.output, polygons=diagram.cells, points=P,
                       title=f"Voronoi diagram of {len(P)} sites")
    print(f"wrote {args.output}: {len(diagram.vertices)} Voronoi vertices, {len(diagram.cells)} cells")
    return 0


def command_power(args: argparse.Namespace) -> int:
    check_output(args.output, (".png",), "-o")
    P, _, _, weights = read_planar(args.input)
    if weights is None:
        raise InputError(f"{args.input}: power diagrams need a weight per site: lines of 'x y w'")
    diagram = tessellation.power_diagram(P, weights)
    render.plot_planar(args.output, polygons=[cell for cell in diagram.cells if len(cell)], points=P,
                       highlight=P[diagram.hidden] if len(diagram.hidden) else None,
                       title=f"power diagram of {len(P)} sites ({len(diagram.hidden)} hidden)")
    print(f"wrote {args.output}: {len(P)} sites, {len(diagram.hidden)} with empty cells")
    return 0


def command_crust(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES + (".png",), "-o")
    suffix = Path(args.input).suffix.lower()
    if suffix in PLANAR_SUFFIXES or suffix not in POINT_CLOUD_SUFFIXES + MESH_SUFFIXES:
        P, _, _, _ = read_planar(args.input)
    else:
        P = read_point_cloud(args.input)
        if np.ptp(P[:, 2]) == 0.0:            # samples of a planar curve stored with z = 0
            P = P[:, :2]
    if P.shape[1] == 2:
        if not args.output.lower().endswith(".png"):
            raise InputError(f"output {args.output}: the 2D crust is a curve; write it as a .png picture")
        edges = tessellation.crust(P)
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


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    triangulate = add_command(
        commands, "triangulate", help="quality triangulation of a planar domain",
        description="Delaunay refinement (§2.1.1) of a planar straight-line graph (.poly: vertices, segments, "
                    "holes) or of a point set (x y lines): every angle >= --min-angle (guaranteed up to 20.7°, "
                    "in practice up to ~33°).",
        examples=["meshsmith triangulate domain.poly -o domain.obj",
                  "meshsmith triangulate domain.poly --min-angle 30 --max-area 0.01 -o fine.off --picture fine.png",
                  "meshsmith triangulate points.txt -o hull.png"])
    triangulate.add_argument("input", help=".poly file, or a text file of 'x y' lines")
    triangulate.add_argument("-o", "--output", required=True, help="mesh file (.obj, .ply, .off; z = 0) or .png")
    triangulate.add_argument("--min-angle", type=number(0, 35, open_low=True, open_high=True), default=20.7,
                             help="degrees, in (0, 35) (default 20.7)")
    triangulate.add_argument("--max-area", type=number(0, open_low=True), help="largest triangle area")
    triangulate.add_argument("--max-steiner-points", type=integer(0, 100_000_000), default=1_000_000,
                             metavar="N", help="stop with an error rather than insert more points (default 1000000)")
    triangulate.add_argument("--picture", help="also write a PNG of the triangulation (Steiner points in red)")
    triangulate.set_defaults(run=command_triangulate)

    voronoi = add_command(
        commands, "voronoi", help="Voronoi diagram of planar sites, as a picture",
        description="Voronoi cells (§2.1.1) of planar sites, clipped to their bounding box enlarged by 10%, "
                    "drawn as a PNG.",
        examples=["meshsmith voronoi points.txt -o cells.png", "meshsmith voronoi domain.poly -o cells.png"])
    voronoi.add_argument("input", help=".poly file, or a text file of 'x y' lines")
    voronoi.add_argument("-o", "--output", required=True, help="output PNG")
    voronoi.set_defaults(run=command_voronoi)

    crust = add_command(
        commands, "crust", help="reconstruct a curve (2D) or a surface (3D) from samples",
        description="Voronoi filtering (§2.1.3): the crust of 2D curve samples (drawn as a PNG), or the Cocone "
                    "crust of a 3D point cloud (written as a mesh or rendered as a PNG).",
        examples=["meshsmith crust circle.txt -o curve.png", "meshsmith crust points.xyz -o surface.ply",
                  "meshsmith crust points.xyz -o surface.png"])
    crust.add_argument("input", help="2D: .poly or 'x y' text; 3D: .xyz, .ply or a mesh file's vertices")
    crust.add_argument("-o", "--output", required=True, help="2D: a .png; 3D: a mesh file or a .png")
    crust.set_defaults(run=command_crust)

    power = add_command(
        commands, "power", help="power diagram of weighted planar sites, as a picture",
        description="Power diagram (§2.1.4) of weighted sites (lines of 'x y w', w a squared radius), drawn as "
                    "a PNG; hidden sites in red.",
        examples=["meshsmith power weighted.txt -o power.png"])
    power.add_argument("input", help="text file of 'x y w' lines")
    power.add_argument("-o", "--output", required=True, help="output PNG")
    power.set_defaults(run=command_power)
