"""`meshsmith parametrize`: texture coordinates (§5.1)."""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .. import InputError, io, parametrization, render
from ..parametrization import PARAMETRIZATION_METHODS
from .common import ProgressBar, add_command, check_output, read_mesh


def command_parametrize(args: argparse.Namespace) -> int:
    if not args.output.lower().endswith(".obj"):
        raise InputError(f"output {args.output}: texture coordinates are written as OBJ 'vt' lines; use a .obj file")
    check_output(args.output, (".obj",), "-o")
    if args.picture:
        check_output(args.picture, (".png",), "--picture")
    V, F = read_mesh(args.input)
    result = parametrization.parametrize(V, F, method=args.method, progress=ProgressBar())
    # Positions stay those of the input; texture coordinates are per cut vertex (seams included),
    # written for the cut vertices some face uses (unreferenced input vertices have none).
    used, F_uv = np.unique(result.F, return_inverse=True)
    io.write_mesh(args.output, V, F, UV=result.uv[used], F_uv=F_uv.reshape(-1, 3))
    if args.picture:
        render.parametrization_picture(result, args.picture, f"{Path(args.input).name}: checkerboard through UV")
    print(f"wrote {args.output}: {len(V)} vertices, {len(F)} faces, {len(used)} texture coordinates"
          + (f" (cut along {len(result.cut.seam_edges)} seam edges)" if result.cut is not None else ""))
    for key, value in result.summary().items():
        print(f"  {key:40s} {value:.4f}" if isinstance(value, float) else f"  {key:40s} {value}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    parametrize = add_command(
        commands, "parametrize", help="flatten a mesh: write texture coordinates (OBJ vt)",
        description="Parametrization (§5.1): " + "; ".join(f"{name}: {what}" for name, what in
                                                           PARAMETRIZATION_METHODS.items())
        + ". A mesh that is not a disk is cut with a spanning-tree cut graph first. Prints the distortion.",
        examples=["meshsmith parametrize disk.obj -o lscm.obj",
                  "meshsmith parametrize disk.obj --method abf++ -o abf.obj --picture abf.png",
                  "meshsmith parametrize mesh.off --method harmonic -o harmonic.obj"])
    parametrize.add_argument("input", help="mesh file (.obj, .ply, .off, .stl)")
    parametrize.add_argument("--method", choices=list(PARAMETRIZATION_METHODS), default="lscm",
                             help="default: lscm")
    parametrize.add_argument("-o", "--output", required=True, help="output .obj with vt texture coordinates")
    parametrize.add_argument("--picture", help="also write a PNG: the UV layout and the surface under a checkerboard")
    parametrize.set_defaults(run=command_parametrize)
