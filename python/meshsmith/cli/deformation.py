"""`meshsmith deform`: move a handle region by an affine transform, the rest following a
bi-Laplacian (or order-k) or as-rigid-as-possible deformation (§3.1)."""
from __future__ import annotations

import argparse
import re

import numpy as np

from .. import InputError, deformation, io
from .common import MESH_SUFFIXES, ProgressBar, UsageError, add_command, check_output, integer, read_mesh

_RANGE = re.compile(r"^\s*(\d+)\s*(?:-\s*(\d+)\s*)?$")


def vertex_ids(text: str, flag: str) -> np.ndarray:
    """Vertex indices from `text`: comma-separated indices and ranges `a-b` (inclusive), or
    `@file` naming a text file of whitespace-separated indices. Raises UsageError."""
    if text.startswith("@"):
        try:
            values = np.loadtxt(text[1:], dtype=np.int64, ndmin=1).ravel()
        except (OSError, ValueError) as error:
            raise InputError(f"{flag} {text}: cannot read vertex indices ({error})") from None
        return values
    ids: list[int] = []
    for part in text.split(","):
        match = _RANGE.match(part)
        if not match:
            raise UsageError(f"{flag} {text!r}: expected indices and ranges like 0,5,10-20 (or @file)")
        first, last = int(match.group(1)), int(match.group(2) or match.group(1))
        if last < first:
            raise UsageError(f"{flag} {text!r}: range {first}-{last} runs backwards")
        ids.extend(range(first, last + 1))
    return np.asarray(ids, dtype=np.int64)


def read_transform(path: str) -> np.ndarray:
    """A 4×4 affine matrix (or its top 3×4) from a text file of whitespace-separated numbers."""
    try:
        T = np.loadtxt(path, dtype=np.float64, ndmin=2)
    except (OSError, ValueError) as error:
        raise InputError(f"--transform {path}: cannot read a matrix ({error})") from None
    if T.shape == (3, 4):
        T = np.vstack([T, [0.0, 0.0, 0.0, 1.0]])
    if T.shape != (4, 4):
        raise InputError(f"--transform {path}: a {T.shape[0]}x{T.shape[1]} matrix, expected 4x4 (or 3x4)")
    return T


def command_deform(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    handle = vertex_ids(args.handle, "--handle")
    fixed = vertex_ids(args.fixed, "--fixed") if args.fixed else np.zeros(0, dtype=np.int64)
    T = read_transform(args.transform)
    V, F = read_mesh(args.input)
    if args.method == "arap":
        for ids, flag in ((handle, "--handle"), (fixed, "--fixed")):
            if ids.size and (ids.min() < 0 or ids.max() >= len(V)):
                raise InputError(f"{flag}: vertex indices must be in [0, {len(V)}) for {args.input}")
        handles = np.concatenate([handle, fixed])
        positions = np.concatenate([V[handle] @ T[:3, :3].T + T[:3, 3], V[fixed]])
        U = deformation.arap(V, F, handles, positions, iterations=args.iterations, progress=ProgressBar())
    else:
        U = deformation.Deformer(V, F, handle, fixed, order=args.order, details=args.details).transform(T)
    io.write_mesh(args.output, U, F)
    moved_by = np.linalg.norm(U - V, axis=1)
    print(f"{args.input}: {len(V):,} vertices, {len(F):,} faces; {len(handle):,} handle and {len(fixed):,} fixed "
          f"vertices; {args.method} -> {args.output}: largest displacement {moved_by.max():.4g}, mean "
          f"{moved_by.mean():.4g}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    deform = add_command(
        commands, "deform", help="deform a mesh by moving a handle region (bi-Laplacian or ARAP)",
        description="Handle-based deformation (§3.1): the --handle vertices undergo the affine map of "
                    "--transform (a text file holding a 4x4 matrix, or its top 3x4, acting on column vectors "
                    "(x, y, z, 1)), the --fixed vertices stay, and the rest follow: with --method harmonic "
                    "(default) the displacement solves Δ^k d = 0 (--order, default 2: bi-Laplacian, the thin "
                    "plate; --details re-adds the surface details in rotated local frames); with --method arap "
                    "the as-rigid-as-possible energy is minimized by --iterations local/global steps. Vertex "
                    "lists are comma-separated indices and ranges (0,5,10-20) or @file.",
        examples=["meshsmith deform mesh.off --handle 0-11 --fixed 120-161 --transform rotate.txt -o bent.obj",
                  "meshsmith deform mesh.off --handle 0-11 --fixed 120-161 --transform rotate.txt --method arap "
                  "--iterations 5 -o arap.off",
                  "meshsmith deform disk.obj --handle 0-12 --fixed 113-144 --transform lift.txt --details "
                  "-o lifted.ply"])
    deform.add_argument("input", help="mesh file (.obj, .ply, .off, .stl)")
    deform.add_argument("-o", "--output", required=True, help="deformed mesh file (format from the extension)")
    deform.add_argument("--handle", required=True, metavar="IDS", help="the vertices moved by --transform")
    deform.add_argument("--fixed", metavar="IDS", help="vertices that stay in place (default: none)")
    deform.add_argument("--transform", required=True, metavar="T.txt", help="4x4 (or 3x4) affine matrix file")
    deform.add_argument("--method", choices=("harmonic", "arap"), default="harmonic",
                        help="k-harmonic displacement (default) or as-rigid-as-possible")
    deform.add_argument("--order", type=integer(1, 3), default=2, metavar="K",
                        help="harmonic: the order k of Δ^k d = 0 (1, 2 or 3; default 2)")
    deform.add_argument("--details", action="store_true",
                        help="harmonic: preserve details in local frames (multiresolution editing)")
    deform.add_argument("--iterations", type=integer(0, 10_000), default=10, metavar="N",
                        help="arap: local/global iterations (default 10)")
    deform.set_defaults(run=command_deform)
