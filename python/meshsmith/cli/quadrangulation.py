"""`meshsmith quadrangulate`: a triangle mesh to a pure quad mesh (§5.2.2)."""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from .. import io, quadrangulation, render
from .common import ProgressBar, UsageError, add_command, check_output, integer, number, read_mesh

#: --method values.
QUADRANGULATION_METHODS = {"miq": "cross field, mixed-integer parametrization (MIQ), quad extraction",
                           "spectral": "Morse-Smale complex of a Laplacian eigenfunction, harmonic maps of its cells (§5.2.1)"}


def command_quadrangulate(args: argparse.Namespace) -> int:
    check_output(args.output, (".obj", ".off", ".ply"), "-o")
    if args.picture:
        check_output(args.picture, (".png",), "--picture")
    if args.faces is not None and args.edge_length is not None:
        raise UsageError("--faces and --edge-length are exclusive: give one")
    V, F = read_mesh(args.input)
    if args.method == "spectral":
        return _spectral(args, V, F)
    start = time.perf_counter()
    result = quadrangulation.quadrangulate(V, F, target_faces=args.faces, target_edge_length=args.edge_length,
                                           align=args.align, sharp_angle=args.sharp_angle, progress=ProgressBar())
    seconds = time.perf_counter() - start
    io.write_mesh(args.output, result.V, result.Q)
    report = result.report
    if args.picture:
        name = Path(args.input).name
        pictures = [render.render(V, F, size=(480, 420), uv=result.UV, checker_size=1.0, wireframe=False,
                                  title=f"{name}: the seamless map's unit grid"),
                    render.render(result.V, result.Q, size=(480, 420), title=f"{report.quads} quads")]
        render.save_png(np.concatenate(pictures, axis=1), args.picture)
    extraction = report.extraction
    print(f"wrote {args.output}: {len(result.V)} vertices, {report.quads} quads"
          + ("" if extraction.complete else " (incomplete: see below)"))
    rows = [
        ("singularities", f"{len(report.singular_vertices)} (index sum {int(report.singular_indices.sum())})"),
        ("irregular vertices", str(report.irregular_vertices)),
        ("flipped triangles (miq)", f"{report.flipped_before} before repair, {report.flipped_after} after"),
        ("Euler characteristic", f"{extraction.euler_output} (input {extraction.euler_input})"),
        ("|angle - 90| mean / max", f"{report.mean_angle_deviation:.2f} / {report.max_angle_deviation:.2f} degrees"),
        ("min scaled Jacobian", f"{report.min_scaled_jacobian:.3f}"),
        ("squares left out", f"{extraction.squares_cut_by_boundary} cut by the boundary, "
                             f"{extraction.squares_inconsistent} inconsistent, "
                             f"{extraction.quads_non_manifold} non-manifold ({extraction.holes} holes)"),
        ("time", f"{seconds:.2f} s"),
    ]
    for key, value in rows:
        print(f"  {key:26s} {value}")
    return 0


def _spectral(args: argparse.Namespace, V: np.ndarray, F: np.ndarray) -> int:
    """--method spectral: spectral_quadrangulate, its cells and quality."""
    from .. import geometry
    faces = args.faces if args.edge_length is None else max(1, round(geometry.surface_area(V, F) / args.edge_length ** 2))
    start = time.perf_counter()
    result = quadrangulation.spectral_quadrangulate(V, F, target_faces=faces, progress=ProgressBar())
    seconds = time.perf_counter() - start
    io.write_mesh(args.output, result.V, result.Q)
    report = result.report
    if args.picture:
        render.render(result.V, result.Q, args.picture, size=(480, 420),
                      title=f"{report.quads} quads in {report.patches} Morse-Smale cells")
    print(f"wrote {args.output}: {len(result.V)} vertices, {report.quads} quads")
    for key, value in [
            ("Morse-Smale cells", f"{report.patches} (eigenvector {report.eigenvector}, "
                                  f"{report.refinements} refinement(s))"),
            ("maxima / saddles / minima", f"{report.maxima} / {report.saddles} / {report.minima}"),
            ("irregular vertices", str(report.irregular_vertices)),
            ("|angle - 90| mean / max", f"{report.mean_angle_deviation:.2f} / {report.max_angle_deviation:.2f} degrees"),
            ("min scaled Jacobian", f"{report.min_scaled_jacobian:.3f} ({report.inverted_quads} inverted)"),
            ("time", f"{seconds:.2f} s")]:
        print(f"  {key:26s} {value}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    parser = add_command(
        commands, "quadrangulate", help="remesh a triangle mesh into a pure quad mesh",
        description="Quadrangulation (§5.2.2): " + "; ".join(f"{name}: {what}" for name, what in
                                                             QUADRANGULATION_METHODS.items())
        + ". Prints the quads, singularities, angle quality and what was left out.",
        examples=["meshsmith quadrangulate mesh.off -o quads.obj --faces 400",
                  "meshsmith quadrangulate mesh.off -o quads.off --edge-length 0.15 --picture quads.png",
                  "meshsmith quadrangulate mesh.off -o quads.obj --faces 300 --method spectral"])
    parser.add_argument("input", help="triangle mesh file (.obj, .ply, .off, .stl): clean, connected, manifold")
    parser.add_argument("-o", "--output", required=True, help="output quad mesh (.obj, .off, .ply)")
    parser.add_argument("--faces", type=integer(1, 2 ** 24), metavar="N", help="about N quads")
    parser.add_argument("--edge-length", type=number(0, open_low=True), metavar="L", help="quad edge length L")
    parser.add_argument("--method", choices=list(QUADRANGULATION_METHODS), default="miq", help="default: miq")
    parser.add_argument("--align", choices=("curvature", "boundary", "smooth"), default="curvature",
                        help="what the cross field follows (default: curvature)")
    parser.add_argument("--sharp-angle", type=number(0, 180, open_low=True, open_high=True), metavar="DEG",
                        help="edges sharper than DEG degrees become quad edges")
    parser.add_argument("--picture", help="also write a PNG: the map's grid on the input and the quad mesh")
    parser.set_defaults(run=command_quadrangulate)
