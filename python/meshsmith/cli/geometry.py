"""`meshsmith curvature`: per-vertex curvature as a picture or values (§1.2.4)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import InputError, geometry, render
from .common import UsageError, add_command, add_picture_size, check_output, read_mesh
from .render import add_colour_options, colour_range, describe_range

CURVATURE_KINDS = ("mean", "gaussian", "k1", "k2")


def curvature_field(kind: str, V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, str]:
    """Per-vertex curvature of the given kind (pointwise, i.e. per unit area) and its label."""
    if kind == "mean":
        return geometry.mean_curvature(V, F)[0], "mean curvature H"
    if kind == "gaussian":
        return geometry.gaussian_curvature(V, F, pointwise=True), "Gaussian curvature K"
    if kind in ("k1", "k2"):
        k1, k2, _, _ = geometry.principal_curvatures(V, F)
        return (k1, "max principal curvature k1") if kind == "k1" else (k2, "min principal curvature k2")
    raise InputError(f"unknown curvature kind '{kind}': use {', '.join(CURVATURE_KINDS)}")


def command_curvature(args) -> int:
    check_output(args.output, (".png", ".npy"), "-o")
    picture = Path(args.output).suffix.lower() == ".png"
    if not picture and (args.range is not None or args.cmap is not None):
        raise UsageError("--range and --cmap are for a .png picture; the .npy file holds the values")
    V, F = read_mesh(args.input)
    values, label = curvature_field(args.kind, V, F)
    if picture:
        cmap, (low, high) = colour_range(args, values)
        render.render(V, F, args.output, scalar=values, scalar_label=label, cmap=cmap, scalar_range=(low, high),
                      title=f"{Path(args.input).name}: {label}", size=(args.width, args.height), up=args.up)
        print(f"wrote {args.output}: {label}, median {np.median(values):.6g}, {describe_range(values, low, high)}")
    else:
        np.save(args.output, values)
        print(f"wrote {args.output}: {label}, median {np.median(values):.6g}, "
              f"range [{values.min():.6g}, {values.max():.6g}]")
    return 0


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    curvature = add_command(
        commands, "curvature", help="per-vertex curvature as a picture or values",
        description="Per-vertex curvature (§1.2.4): mean (cotan Laplacian), Gaussian (angle defect per "
                    "Voronoi area) or the principal curvatures k1 >= k2 (quadric fit). Writes a coloured "
                    "picture (.png) or the values (.npy).",
        examples=["meshsmith curvature mesh.off -o mean.png",
                  "meshsmith curvature mesh.off --kind gaussian -o gaussian.npy",
                  "meshsmith curvature mesh.off --kind k1 -o k1.png --range 0 2 --up z"])
    curvature.add_argument("input", help="mesh file (OBJ, OFF, PLY, STL)")
    curvature.add_argument("--kind", choices=CURVATURE_KINDS, default="mean", help="default: mean")
    curvature.add_argument("-o", "--output", required=True, help="out.png (a picture) or out.npy (the values)")
    add_colour_options(curvature)
    add_picture_size(curvature)
    curvature.set_defaults(run=command_curvature)
