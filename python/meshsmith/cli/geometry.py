"""`meshsmith curvature`: per-vertex curvature as a picture or values (§1.2.4)."""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .. import InputError, geometry, render
from .common import ProgressBar, Stages, UsageError, add_command, add_picture_size, check_output, read_mesh
from .render import add_colour_options, colour_range, describe_range

CURVATURE_KINDS = ("mean", "gaussian", "k1", "k2")


def curvature_field(kind: str, V: np.ndarray, F: np.ndarray, *, pointwise: bool = False) -> tuple[np.ndarray, str]:
    """Per-vertex curvature of the given kind, the same quantity as the API's default, and its label.

    mean, k1, k2: per unit length (1/r on a sphere of radius r), as :func:`geometry.mean_curvature`
    and :func:`geometry.principal_curvatures`. gaussian: the integrated angle defect in radians, as
    :func:`geometry.gaussian_curvature`; with ``pointwise`` divided by the Voronoi area (1/length²).
    """
    if pointwise and kind != "gaussian":
        raise InputError(f"--pointwise applies to --kind gaussian only: {kind} is per unit length already")
    if kind == "mean":
        return geometry.mean_curvature(V, F).H, "mean curvature H (1/length)"
    if kind == "gaussian":
        if pointwise:
            return geometry.gaussian_curvature(V, F, pointwise=True), "Gaussian curvature K (1/length²)"
        return geometry.gaussian_curvature(V, F), "integrated Gaussian curvature (angle defect, radians)"
    if kind in ("k1", "k2"):
        k1, k2, _, _ = geometry.principal_curvatures(V, F)
        return (k1, "max principal curvature k1") if kind == "k1" else (k2, "min principal curvature k2")
    raise InputError(f"unknown curvature kind '{kind}': use {', '.join(CURVATURE_KINDS)}")


def command_curvature(args: argparse.Namespace) -> int:
    check_output(args.output, (".png", ".npy"), "-o")
    picture = Path(args.output).suffix.lower() == ".png"
    if not picture and (args.range is not None or args.cmap is not None):
        raise UsageError("--range and --cmap are for a .png picture; the .npy file holds the values")
    if args.pointwise and args.kind != "gaussian":
        raise UsageError(f"--pointwise applies to --kind gaussian only: {args.kind} is per unit length already")
    stages = Stages(ProgressBar(), ["reading", f"{args.kind} curvature", "rendering" if picture else "writing"])
    stages.start("reading")
    V, F = read_mesh(args.input)
    stages.start(f"{args.kind} curvature")
    values, label = curvature_field(args.kind, V, F, pointwise=args.pointwise)
    stages.start(stages.names[-1])
    if picture:
        cmap, (low, high) = colour_range(args, values)
        render.render(V, F, args.output, scalar=values, scalar_label=label, cmap=cmap, scalar_range=(low, high),
                      title=f"{Path(args.input).name}: {label}", size=(args.width, args.height), up=args.up)
        stages.done()
        print(f"wrote {args.output}: {label}, median {np.median(values):.6g}, {describe_range(values, low, high)}")
    else:
        np.save(args.output, values)
        stages.done()
        print(f"wrote {args.output}: {label}, median {np.median(values):.6g}, "
              f"range [{values.min():.6g}, {values.max():.6g}]")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    curvature = add_command(
        commands, "curvature", help="per-vertex curvature as a picture or values",
        description="Per-vertex curvature (§1.2.4), the same values as the Python API's defaults: mean "
                    "(cotan Laplacian, 1/length), Gaussian (the integrated angle defect 2π − Σθ in radians, as "
                    "geometry.gaussian_curvature; --pointwise divides it by the Voronoi area: 1/length²) or "
                    "the principal curvatures k1 >= k2 (quadric fit, 1/length). Writes a coloured picture "
                    "(.png) or the values (.npy).",
        examples=["meshsmith curvature mesh.off -o mean.png",
                  "meshsmith curvature mesh.off --kind gaussian -o gaussian.npy",
                  "meshsmith curvature mesh.off --kind gaussian --pointwise -o gaussian.png",
                  "meshsmith curvature mesh.off --kind k1 -o k1.png --range 0 2 --up z"])
    curvature.add_argument("input", help="mesh file (OBJ, OFF, PLY, STL)")
    curvature.add_argument("--kind", choices=CURVATURE_KINDS, default="mean", help="default: mean")
    curvature.add_argument("--pointwise", action="store_true",
                           help="gaussian only: curvature per unit area (1/length²) instead of the "
                                "integrated angle defect (radians)")
    curvature.add_argument("-o", "--output", required=True, help="out.png (a picture) or out.npy (the values)")
    add_colour_options(curvature)
    add_picture_size(curvature)
    curvature.set_defaults(run=command_curvature)
