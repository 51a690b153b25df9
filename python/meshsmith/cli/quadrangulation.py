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
                           "spectral": "Morse-Smale complex of a Laplacian eigenfunction, its cells coupled in one seamless map (§5.2.1)",
                           "dual-loops": "loops along a cross field, their arrangement's dual as a coarse quad layout "
                                         "(§5.3; up to 5 option sets tried in turn until the layout is complete)"}


def command_quadrangulate(args: argparse.Namespace) -> int:
    check_output(args.output, (".obj", ".off", ".ply"), "-o")
    if args.picture:
        check_output(args.picture, (".png",), "--picture")
    if args.faces is not None and args.edge_length is not None:
        raise UsageError("--faces and --edge-length are exclusive: give one")
    if args.refine is not None and args.method != "dual-loops":
        raise UsageError("--refine is for --method dual-loops only")
    for option in ("curvature_weight", "crease_weight", "conformal_scale"):
        if getattr(args, option) is not None and args.method != "miq":
            raise UsageError(f"--{option.replace('_', '-')} is for --method miq only")
    V, F = read_mesh(args.input)
    if args.method == "spectral":
        return _spectral(args, V, F)
    if args.method == "dual-loops":
        return _dual_loops(args, V, F)
    align = args.align or "curvature"
    weights = {option: getattr(args, option) for option in ("curvature_weight", "crease_weight", "conformal_scale")
               if getattr(args, option) is not None}                           # else quadrangulate's defaults
    start = time.perf_counter()
    result = quadrangulation.quadrangulate(V, F, target_faces=args.faces, target_edge_length=args.edge_length,
                                           align=align, sharp_angle=args.sharp_angle, progress=ProgressBar(),
                                           **weights)
    seconds = time.perf_counter() - start
    io.write_mesh(args.output, result.V, result.Q)
    report = result.report
    if args.picture:
        name = Path(args.input).name
        field = quadrangulation.cross_field(V, F, align=align, sharp_angle=args.sharp_angle, **weights)
        pictures = [quadrangulation.field_picture(V, F, field, size=PANEL,
                                                  title=f"{name}: cross field (before merging)"),
                    render.render(V, F, size=PANEL, uv=result.UV, checker_size=1.0, wireframe=False,
                                  title="the seamless map's unit grid"),
                    render.render(result.V, result.Q, size=PANEL, title=f"{report.quads} quads")]
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


#: (width, height) of each panel of --picture.
PANEL = (480, 420)


def _dual_loops(args: argparse.Namespace, V: np.ndarray, F: np.ndarray) -> int:
    """--method dual-loops: cross field, dual_loop_layout with its schedule of attempts; writes the layout's quads."""
    from .. import geometry
    area = geometry.surface_area(V, F)
    if args.edge_length is not None:
        spacing = args.edge_length
    elif args.faces is not None:
        spacing = float(np.sqrt(area / args.faces))      # a layout quad per spacing² of surface
    else:
        spacing = float(np.sqrt(area)) / 4                # dual_loop_layout's default
    start = time.perf_counter()
    field = quadrangulation.cross_field(V, F, align=args.align or "smooth", sharp_angle=args.sharp_angle)
    # dual_loop_layout's schedule of attempts (merged singularities, refinement, parallel crossings)
    # until one is complete; layout.theta is the field the returned attempt traced
    layout = quadrangulation.dual_loop_layout(V, F, field, spacing=spacing, refine=args.refine, progress=ProgressBar())
    seconds = time.perf_counter() - start
    io.write_mesh(args.output, layout.Vq, layout.Q)
    report = layout.report
    if args.picture:
        name = Path(args.input).name
        pictures = [quadrangulation.field_picture(layout.V_traced, layout.F_traced, layout.theta, size=PANEL,
                                                  title=f"{name}: {len(layout.singular_vertices)} singularities"),
                    quadrangulation.regions_picture(layout.V_traced, layout.F_traced, layout.region, size=PANEL,
                                                    marked=layout.Vq_vertex, title=f"{report.loops} loops, "
                                                    f"{report.regions} regions"),
                    render.render(layout.Vq, layout.Q, size=PANEL, title=f"{len(layout.Q)} layout quads")]
        render.save_png(np.concatenate(pictures, axis=1), args.picture)
    valence = np.bincount(np.bincount(layout.Q.ravel(), minlength=len(layout.Vq))) if len(layout.Q) else np.zeros(1, int)
    per_region = np.bincount(report.region_singularities) if report.regions else np.zeros(1, int)
    print(f"wrote {args.output}: {len(layout.Vq)} vertices, {len(layout.Q)} layout quads"
          + (" (complete)" if report.complete else " (incomplete: see below)"))
    for key, value in [
            ("loops / crossings", f"{report.loops} / {report.crossings} (spacing {report.spacing:.4g})"),
            ("singularities", f"{len(quadrangulation.singularities(V, F, field).vertices)} "
                              f"-> {len(layout.singular_vertices)} after merging "
                              f"(index sum {int(layout.singular_indices.sum())})"),
            ("regions by singularities", ", ".join(f"{k}: {c}" for k, c in enumerate(per_region.tolist()) if c)),
            ("layout valences", ", ".join(f"{k}: {c}" for k, c in enumerate(valence.tolist()) if c)),
            ("Euler characteristic", f"{report.euler_layout} (input {report.euler_input})"),
            ("attempts", f"{report.attempts} (this one: merge {report.merge:g} spacings, refine {report.refine}, "
                         + ("no parallel crossings" if np.isinf(report.parallel_crossing_penalty) else
                            f"parallel crossings at {report.parallel_crossing_penalty:g} x spacing") + ")"),
            ("time", f"{seconds:.2f} s")]:
        print(f"  {key:26s} {value}")
    if not report.complete:
        print(f"  incomplete: {report.failure}")
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
            ("map", "cells coupled by transition functions" if report.coupled else "each cell on its own"),
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
                  "meshsmith quadrangulate mesh.off -o quads.obj --faces 300 --method spectral",
                  "meshsmith quadrangulate mesh.off -o layout.obj --faces 60 --method dual-loops --picture layout.png"])
    parser.add_argument("input", help="triangle mesh file (.obj, .ply, .off, .stl): clean, connected, manifold")
    parser.add_argument("-o", "--output", required=True, help="output quad mesh (.obj, .off, .ply)")
    parser.add_argument("--faces", type=integer(1, 2 ** 24), metavar="N", help="about N quads")
    parser.add_argument("--edge-length", type=number(0, open_low=True), metavar="L", help="quad edge length L")
    parser.add_argument("--method", choices=list(QUADRANGULATION_METHODS), default="miq", help="default: miq")
    parser.add_argument("--align", choices=("curvature", "boundary", "smooth"), default=None,
                        help="what the cross field follows (default: curvature; smooth for dual-loops)")
    parser.add_argument("--sharp-angle", type=number(0, 180, open_low=True, open_high=True), metavar="DEG",
                        help="edges sharper than DEG degrees become quad edges")
    parser.add_argument("--curvature-weight", type=number(0, 1e6), default=None, metavar="W",
                        help="miq: the field's pull to the principal curvature directions (default 0.001)")
    parser.add_argument("--crease-weight", type=number(0, 1e6), default=None, metavar="W",
                        help="miq: the field's pull along edges where the surface folds (default 0, 0.2 with "
                             "--sharp-angle; 0.2 makes quads follow CAD creases without --sharp-angle)")
    parser.add_argument("--conformal-scale", type=number(0, 1), default=None, metavar="S",
                        help="miq: how far the quads' size follows the conformal factor of the field's flat "
                             "cone metric (default 1: squarer quads of varying size; 0: a uniform size; "
                             "maps holding --sharp-angle features use 0)")
    parser.add_argument("--refine", type=integer(0, 3), default=None, metavar="K",
                        help="dual-loops: split the mesh 1-to-4 K times before tracing, in every attempt (loops "
                             "between neighbouring singularities; default: the schedule's, 0 in the first and "
                             "last attempts, 1 in the others)")
    parser.add_argument("--picture", help="also write a PNG: the cross field with its singularities, the map's grid "
                                          "on the input (dual-loops: the loops' regions) and the quad mesh")
    parser.set_defaults(run=command_quadrangulate)
