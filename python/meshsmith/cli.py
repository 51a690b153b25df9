"""The `meshsmith` command line: one subcommand per task, mirroring the chapters.

    meshsmith info FILE
    meshsmith convert IN OUT [--binary | --ascii]
    meshsmith render IN -o out.png [--scalar x|y|z|valence|FILE.npy] [--wireframe] [--views ...]
    meshsmith curvature IN --kind mean|gaussian|k1|k2 -o out.png|out.npy
    meshsmith normals IN.xyz -o OUT.xyz [--k 16] [--orient]
    meshsmith triangulate IN.poly --min-angle 30 [--max-area A] -o OUT.obj [--picture P.png]
    meshsmith voronoi IN -o cells.png;  meshsmith power IN -o cells.png;  meshsmith crust IN -o OUT
    meshsmith decimate IN -o OUT (--faces N | --ratio r | --error eps) [--method qem|cluster] [--progressive OUT.pm]
    meshsmith lod IN.pm --faces N -o OUT
    meshsmith parametrize IN --method tutte|harmonic|stretch|lscm|abf|abf++ -o OUT.obj [--picture P.png]
    meshsmith demo [--out DIR] [--input FILE]

Every command has --help. Bad input prints one line `meshsmith: error: ...` on stderr and exits
with status 1 (status 2 for a malformed command line, as argparse does).
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from . import InputError, SolverError, Cancelled


class ProgressBar:
    """A progress callback `(fraction, stage) -> True` that draws a bar on stderr.

    Draws only when stderr is a terminal (or `force`), so logs and pipes stay clean.
    """

    def __init__(self, width: int = 30, force: bool = False, stream=None):
        self.stream = stream or sys.stderr
        self.enabled = force or self.stream.isatty()
        self.width, self.start, self.last_stage = width, time.perf_counter(), None

    def __call__(self, fraction: float, stage: str) -> bool:
        if self.enabled:
            filled = int(round(fraction * self.width))
            elapsed = time.perf_counter() - self.start
            self.stream.write(f"\r{stage:<24.24} [{'#' * filled}{'.' * (self.width - filled)}] "
                              f"{100 * fraction:5.1f}%  {elapsed:6.1f}s")
            if fraction >= 1.0:
                self.stream.write("\n")
            self.stream.flush()
        return True


def _read_mesh(path: str):
    from . import io
    return io.read_mesh(path)


def command_info(args) -> int:
    from . import topology
    V, F = _read_mesh(args.file)
    summary = topology.info(V, F)
    if args.json:
        print(json.dumps(summary.as_dict(), indent=2))
    else:
        print(f"{args.file}")
        print(summary)
    return 0


def command_convert(args) -> int:
    from . import io
    V, F = io.read_mesh(args.input)
    options = {}
    if args.binary or args.ascii:
        options["binary"] = bool(args.binary)
    io.write_mesh(args.output, V, F, **options)
    print(f"wrote {args.output}: {len(V)} vertices, {len(F)} faces")
    return 0


def scalar_field(name: str, V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, str]:
    """A per-vertex scalar for `--scalar`: a coordinate, the valence, or values from a .npy file."""
    if name in ("x", "y", "z"):
        return V[:, "xyz".index(name)].copy(), f"{name} coordinate"
    if name == "valence":
        return np.bincount(np.asarray(F).ravel(), minlength=len(V)).astype(float), "vertex valence"
    path = Path(name)
    if path.suffix == ".npy":
        if not path.is_file():
            raise InputError(f"scalar file {name} does not exist")
        values = np.load(path, allow_pickle=False)
        if values.ndim != 1 or len(values) != len(V):
            raise InputError(f"scalar file {name} holds shape {values.shape}: expected ({len(V)},), one value per vertex")
        return values.astype(float), path.stem
    raise InputError(f"unknown scalar '{name}': use x, y, z, valence or a .npy file of per-vertex values")


def command_render(args) -> int:
    from . import render
    V, F = _read_mesh(args.input)
    options = dict(size=(args.width, args.height), wireframe=args.wireframe, flat=args.flat)
    if args.scalar:
        options["scalar"], options["scalar_label"] = scalar_field(args.scalar, V, F)
        options["cmap"] = args.cmap
    if args.views:
        options["views"] = args.views.split(",")
    render.render(V, F, args.output, title=args.title or Path(args.input).name, **options)
    print(f"wrote {args.output}")
    return 0


CURVATURE_KINDS = ("mean", "gaussian", "k1", "k2")


def curvature_field(kind: str, V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, str]:
    """Per-vertex curvature of the given kind (pointwise, i.e. per unit area) and its label."""
    from . import geometry
    if kind == "mean":
        return geometry.mean_curvature(V, F)[0], "mean curvature H"
    if kind == "gaussian":
        return geometry.gaussian_curvature(V, F, pointwise=True), "Gaussian curvature K"
    if kind in ("k1", "k2"):
        k1, k2, _, _ = geometry.principal_curvatures(V, F)
        return (k1, "max principal curvature k1") if kind == "k1" else (k2, "min principal curvature k2")
    raise InputError(f"unknown curvature kind '{kind}': use {', '.join(CURVATURE_KINDS)}")


def command_curvature(args) -> int:
    from . import render
    V, F = _read_mesh(args.input)
    values, label = curvature_field(args.kind, V, F)
    output = Path(args.output)
    if output.suffix.lower() == ".npy":
        np.save(output, values)
    elif output.suffix.lower() == ".png":
        render.render(V, F, output, scalar=values, scalar_label=label, cmap="coolwarm",
                      title=f"{Path(args.input).name}: {label}", size=(args.width, args.height))
    else:
        raise InputError(f"output {args.output} must end in .png (a picture) or .npy (the values)")
    print(f"wrote {args.output}: {label}, median {np.median(values):.6g}, "
          f"range [{values.min():.6g}, {values.max():.6g}]")
    return 0


def command_normals(args) -> int:
    from . import io, points
    P, _ = io.read_points(args.input)
    progress = ProgressBar()
    N = points.estimate_normals(P, k=args.k, radius=args.radius, progress=progress)
    if args.orient:
        N = points.orient_normals(P, N, k=args.k, progress=progress)
    io.write_points(args.output, P, N)
    print(f"wrote {args.output}: {len(P)} points with {'oriented' if args.orient else 'unoriented'} normals")
    return 0


def read_planar(path: str):
    """Planar input of the tessellation commands: a Triangle ``.poly`` file (vertices, segments,
    holes), or a text file of ``x y`` or ``x y w`` lines (w: a weight, used by ``power``).
    Returns (P (n, 2), segments or None, holes or None, weights or None)."""
    from . import io
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
    from . import io, render
    if path.lower().endswith(".png"):
        render.plot_planar(path, triangles=(V2, F), title=Path(path).stem)
    else:
        io.write_mesh(path, np.column_stack([V2, np.zeros(len(V2))]), F)


def command_triangulate(args) -> int:
    from . import render, tessellation
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
    from . import render, tessellation
    P, _, _, _ = read_planar(args.input)
    diagram = tessellation.voronoi(P)
    render.plot_planar(args.output, polygons=diagram.cells, points=P,
                       title=f"Voronoi diagram of {len(P)} sites")
    print(f"wrote {args.output}: {len(diagram.vertices)} Voronoi vertices, {len(diagram.cells)} cells")
    return 0


def command_power(args) -> int:
    from . import render, tessellation
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
    from . import io, render, tessellation
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


def _relative_hausdorff(V0, F0, V1, F1) -> tuple[float, float]:
    """Symmetric Hausdorff distance between two meshes and its ratio to the bounding-box diagonal."""
    from . import geometry
    distance = float(geometry.hausdorff_distance(V1, F1, V0, F0))
    diagonal = float(np.linalg.norm(V0.max(axis=0) - V0.min(axis=0)))
    return distance, (distance / diagonal if diagonal > 0 else 0.0)


def command_decimate(args) -> int:
    from . import decimation, io
    V, F = io.read_mesh(args.input)
    progress = ProgressBar()
    if args.method == "cluster":
        if args.progressive:
            raise InputError("--progressive needs --method qem: clustering records no collapses")
        if args.faces is not None:
            options = dict(target_vertices=max(3, args.faces // 2))   # a closed mesh has ~2 faces per vertex
        elif args.ratio is not None:
            if not 0 < args.ratio <= 1:
                raise InputError(f"--ratio must be in (0, 1], got {args.ratio}")
            options = dict(target_vertices=max(3, int(round(args.ratio * len(np.unique(F))))))
        else:
            if not args.error > 0:
                raise InputError(f"--error must be > 0, got {args.error}")
            options = dict(cell_size=args.error / np.sqrt(3.0))     # a vertex moves at most a cell diagonal
        result = decimation.cluster(V, F, progress=progress, **options)
        V2, F2 = result.V, result.F
        note = f", cell size {result.cell_size:.6g}, {'manifold' if result.is_manifold else 'NOT manifold'}"
    else:
        stop = dict(target_faces=args.faces, ratio=args.ratio, max_error=args.error)
        stop = {key: value for key, value in stop.items() if value is not None}
        if args.progressive:
            pm = decimation.progressive_mesh(V, F, progress=progress, **stop)
            pm.save(args.progressive)
            pm.set_level(0)
            V2, F2 = pm.mesh()
            note = f"; progressive mesh {args.progressive}: {pm.n_splits} vertex splits back to the input"
        else:
            V2, F2 = decimation.decimate(V, F, progress=progress, **stop)
            note = ""
    if len(F2) == 0:
        raise InputError(f"{args.method}: no triangle is left; ask for more faces or a smaller error")
    io.write_mesh(args.output, V2, F2)
    distance, relative = _relative_hausdorff(V, F, V2, F2)
    print(f"wrote {args.output}: {len(F)} -> {len(F2)} faces ({len(V2)} vertices){note}")
    print(f"Hausdorff distance {distance:.6g} ({100 * relative:.4g}% of the bounding-box diagonal)")
    return 0


def command_lod(args) -> int:
    from . import decimation, io
    pm = decimation.ProgressiveMesh.load(args.input)
    V, F = pm.at(args.faces)
    io.write_mesh(args.output, V, F)
    low, high = pm.face_range
    print(f"wrote {args.output}: level {pm.level} of {pm.n_splits}, {len(F)} faces ({len(V)} vertices; "
          f"this progressive mesh spans {low}..{high} faces)")

def parametrization_picture(path, result, title: str) -> None:
    """One PNG: the UV layout (coloured by angle distortion) beside the surface under a checkerboard."""
    from . import render
    corners = result.uv[result.F]  # per corner, so seams cut by cut_to_disk show in the texture
    V, F = (result.cut.V, result.F) if result.cut is not None else (result.V, result.F)
    layout = render.render_uv_layout(result.uv, result.F, size=(640, 640), scalar=result.distortion.vertex_conformal,
                                     scalar_range=(1.0, 2.0), scalar_label="angle distortion σ1/σ2",
                                     title=f"UV layout ({result.method})")
    checker = float(np.ptp(result.uv, axis=0).max()) / 24
    surface = render.render(V, F, uv=corners, checker_size=checker, size=(640, 640), title=title)
    render.save_png(np.concatenate([layout, surface], axis=1), path)


def command_parametrize(args) -> int:
    from . import io, parametrization
    if not args.output.lower().endswith(".obj"):
        raise InputError(f"output {args.output}: texture coordinates are written as OBJ 'vt' lines; use a .obj file")
    V, F = _read_mesh(args.input)
    result = parametrization.parametrize(V, F, args.method, progress=ProgressBar())
    # Positions stay those of the input; texture coordinates are per cut vertex (seams included).
    io.write_mesh(args.output, V, F, UV=result.uv, F_uv=result.F)
    if args.picture:
        parametrization_picture(args.picture, result, f"{Path(args.input).name}: checkerboard through UV")
    print(f"wrote {args.output}: {len(V)} vertices, {len(F)} faces, {len(result.uv)} texture coordinates"
          + (f" (cut along {len(result.cut.seam_edges)} seam edges)" if result.cut is not None else ""))
    for key, value in result.summary().items():
        print(f"  {key:40s} {value:.4f}" if isinstance(value, float) else f"  {key:40s} {value}")
    return 0


def command_demo(args) -> int:
    from . import demo
    report = demo.run_demo(Path(args.out), input_path=args.input, progress=ProgressBar())
    print(f"demo report: {report}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="meshsmith", description="Geometry processing: the classic curriculum.")
    parser.add_argument("--version", action="version", version=f"meshsmith {_version()}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)

    info = commands.add_parser("info", help="counts, topology, bounding box, area and volume of a mesh",
                               description="Print counts, topology (components, boundary loops, genus, "
                                           "manifoldness, orientation), bounding box, area and volume.")
    info.add_argument("file", help="mesh file (OBJ, OFF, PLY, STL)")
    info.add_argument("--json", action="store_true", help="print the figures as JSON")
    info.set_defaults(run=command_info)

    convert = commands.add_parser("convert", help="convert between mesh formats",
                                  description="Read a mesh and write it in the format given by OUT's extension.")
    convert.add_argument("input")
    convert.add_argument("output")
    encoding = convert.add_mutually_exclusive_group()
    encoding.add_argument("--binary", action="store_true", help="binary PLY/STL/OFF")
    encoding.add_argument("--ascii", action="store_true", help="ASCII PLY/STL/OFF")
    convert.set_defaults(run=command_convert)

    render = commands.add_parser("render", help="render a mesh to a PNG picture",
                                 description="Render a shaded picture of a mesh, optionally coloured by a scalar.")
    render.add_argument("input")
    render.add_argument("-o", "--output", required=True, help="output PNG")
    render.add_argument("--scalar", help="colour by x, y, z, valence, or a .npy file of per-vertex values")
    render.add_argument("--cmap", default="viridis", help="colormap for --scalar (viridis, magma, coolwarm)")
    render.add_argument("--wireframe", action="store_true", help="draw the edges")
    render.add_argument("--flat", action="store_true", help="flat shading (one normal per face)")
    render.add_argument("--views", help="comma-separated views, e.g. front,left,top,three-quarter")
    render.add_argument("--width", type=int, default=800)
    render.add_argument("--height", type=int, default=600)
    render.add_argument("--title", help="title drawn on the picture (default: the file name)")
    render.set_defaults(run=command_render)

    curvature = commands.add_parser("curvature", help="per-vertex curvature as a picture or values",
                                    description="Per-vertex curvature (§1.2.4): mean (cotan Laplacian), "
                                                "Gaussian (angle defect per Voronoi area) or the principal "
                                                "curvatures k1 >= k2 (quadric fit). Writes a coloured picture "
                                                "(.png) or the values (.npy).")
    curvature.add_argument("input")
    curvature.add_argument("--kind", choices=CURVATURE_KINDS, default="mean")
    curvature.add_argument("-o", "--output", required=True, help="out.png or out.npy")
    curvature.add_argument("--width", type=int, default=800)
    curvature.add_argument("--height", type=int, default=600)
    curvature.set_defaults(run=command_curvature)

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

    decimate = commands.add_parser("decimate", help="reduce the number of triangles (QEM or clustering)",
                                   description="Decimate a mesh (§4.1-4.3): greedy QEM edge collapses (default) or "
                                               "vertex clustering on a grid; prints the faces before and after "
                                               "and the Hausdorff distance to the input.")
    decimate.add_argument("input", help="mesh file (OBJ, OFF, PLY, STL)")
    decimate.add_argument("-o", "--output", required=True, help="decimated mesh file")
    stop = decimate.add_mutually_exclusive_group(required=True)
    stop.add_argument("--faces", type=int, help="target number of faces (cluster: about half as many vertices)")
    stop.add_argument("--ratio", type=float, help="target fraction of the faces (cluster: of the vertices), in (0, 1]")
    stop.add_argument("--error", type=float,
                      help="qem: the largest quadric error of a collapse (length^2, see decimation.decimate); "
                           "cluster: the largest distance a vertex moves (cell diagonal)")
    decimate.add_argument("--method", choices=("qem", "cluster"), default="qem", help="default: qem")
    decimate.add_argument("--progressive", metavar="OUT.pm",
                          help="also write the progressive mesh from OUTPUT (its base) back to INPUT (qem only)")
    decimate.set_defaults(run=command_decimate)

    lod = commands.add_parser("lod", help="extract a level of detail from a progressive mesh",
                              description="Read a progressive mesh (.pm, written by `meshsmith decimate "
                                          "--progressive`) and write its finest level with at most N faces.")
    lod.add_argument("input", help="progressive mesh file (.pm)")
    lod.add_argument("--faces", type=int, required=True, help="at most this many faces")
    lod.add_argument("-o", "--output", required=True, help="output mesh file")
    lod.set_defaults(run=command_lod)
    from .parametrization import PARAMETRIZATION_METHODS
    parametrize = commands.add_parser(
        "parametrize", help="flatten a mesh: write texture coordinates (OBJ vt)",
        description="Parametrization (§5.1): " + "; ".join(f"{name}: {what}" for name, what in
                                                           PARAMETRIZATION_METHODS.items())
        + ". A mesh that is not a disk is cut with a spanning-tree cut graph first. Prints the distortion.")
    parametrize.add_argument("input", help="mesh file (.obj, .ply, .off, .stl)")
    parametrize.add_argument("--method", choices=list(PARAMETRIZATION_METHODS), default="lscm",
                             help="default: lscm")
    parametrize.add_argument("-o", "--output", required=True, help="output .obj with vt texture coordinates")
    parametrize.add_argument("--picture", help="also write a PNG: the UV layout and the surface under a checkerboard")
    parametrize.set_defaults(run=command_parametrize)

    demo = commands.add_parser("demo", help="run the whole pipeline and write an HTML report",
                               description="Run every stage of meshsmith on a built-in shape (or --input) "
                                           "and write outputs and an HTML report with pictures.")
    demo.add_argument("--out", default="meshsmith-demo", help="output folder (default: meshsmith-demo)")
    demo.add_argument("--input", help="mesh file to use instead of the built-in shape")
    demo.set_defaults(run=command_demo)
    return parser


def _version() -> str:
    from . import __version__
    return __version__


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except (InputError, SolverError, OSError) as error:
        message = str(error).splitlines()[0] if str(error) else type(error).__name__
        print(f"meshsmith: error: {message}", file=sys.stderr)
        return 1
    except (Cancelled, KeyboardInterrupt):
        print("meshsmith: cancelled", file=sys.stderr)
        return 130
