"""`meshsmith curvature`: per-vertex curvature as a picture or values (§1.2.4)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import InputError, geometry, render
from .common import read_mesh

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
    V, F = read_mesh(args.input)
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


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
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
