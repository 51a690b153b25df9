"""`meshsmith smooth`: Laplacian and Taubin smoothing with error control (§3.0.1–3.0.2)."""
from __future__ import annotations

import argparse
from typing import Callable

import numpy as np

from .. import geometry, io, smoothing, topology
from .._typing import FloatArray
from .common import MESH_SUFFIXES, ProgressBar, UsageError, add_command, check_output, integer, number, read_mesh


def _options(args: argparse.Namespace, V: np.ndarray, F: np.ndarray) -> dict:
    """The keyword options both mesh methods share, from the command line."""
    options: dict = {"weights": args.weights, "direction": args.direction, "iterations": args.iterations}
    if args.fix_boundary:
        loops = topology.boundary_loops(F)
        options["fixed"] = np.unique(np.concatenate(loops)) if loops else None
    if args.epsilon is not None:
        options["error_slab" if args.slab else "epsilon_ball"] = args.epsilon
    return options


def _laplacian(args: argparse.Namespace, V: np.ndarray, F: np.ndarray, progress: ProgressBar) -> FloatArray:
    return smoothing.laplacian(V, F, lam=0.5 if args.lam is None else args.lam, implicit=args.implicit,
                               progress=progress, **_options(args, V, F))


def _taubin(args: argparse.Namespace, V: np.ndarray, F: np.ndarray, progress: ProgressBar) -> FloatArray:
    if args.implicit:
        raise UsageError("--implicit needs --method laplacian (Taubin's steps are explicit)")
    return smoothing.taubin(V, F, lam=0.5 if args.lam is None else args.lam, mu=args.mu, progress=progress,
                            **_options(args, V, F))


def _bilaplacian(args: argparse.Namespace, V: np.ndarray, F: np.ndarray, progress: ProgressBar) -> FloatArray:
    """One solve of Δ²x = 0 with the boundary ring held: no steps, weights or error bound."""
    for given, flag in ((args.implicit, "--implicit"), (args.epsilon is not None, "--epsilon"),
                        (args.lam is not None, "--lambda"), (args.direction != "full", "--direction"),
                        (args.weights != "uniform", "--weights")):
        if given:
            raise UsageError(f"{flag} does not apply to --method bilaplacian (one cotan bi-Laplace solve)")
    return smoothing.bilaplacian(V, F)


#: `--method` choices: name -> runner(args, V, F, progress) returning the smoothed positions.
METHODS: dict[str, Callable[[argparse.Namespace, np.ndarray, np.ndarray, ProgressBar], FloatArray]] = {
    "laplacian": _laplacian,
    "taubin": _taubin,
    "bilaplacian": _bilaplacian,
}


def command_smooth(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    if args.slab and args.epsilon is None:
        raise UsageError("--slab needs --epsilon (the slab's half width)")
    V, F = read_mesh(args.input)
    W = METHODS[args.method](args, V, F, ProgressBar())
    io.write_mesh(args.output, W, F)
    moved = np.linalg.norm(W - V, axis=1)
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    steps = "one solve" if args.method == "bilaplacian" else f"{args.iterations} iterations"
    print(f"wrote {args.output}: {args.method} smoothing, {steps}, {len(V):,} vertices")
    print(f"vertices moved by {moved.mean():.6g} on average, {moved.max():.6g} at most "
          f"({100 * moved.max() / diagonal:.3g}% of the bounding-box diagonal)")
    if not topology.boundary_loops(F) and topology.is_manifold(F):
        before, after = geometry.volume(V, F), geometry.volume(W, F)
        if before != 0:
            print(f"volume {before:.6g} -> {after:.6g} ({100 * (after / before - 1):+.3g}%)")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    smooth = add_command(
        commands, "smooth", help="smooth a mesh (Laplacian or Taubin) with an optional error bound",
        description="Smooth a triangle mesh (§3.0.1-3.0.2) by the umbrella operator: Taubin's lambda|mu "
                    "filter (default: removes noise, keeps the volume) or Laplacian steps (explicit, or implicit "
                    "with --implicit: stable for any --lambda). --epsilon keeps every vertex within that distance "
                    "of its input position (with --slab: only along its normal, free tangentially). Prints how far "
                    "the vertices moved and, for a closed mesh, the volume before and after. --method bilaplacian fairs "
                    "the mesh in one solve of the bi-Laplace equation (the thin plate) with the boundary and the "
                    "ring inside it held (a mesh with a boundary).",
        examples=["meshsmith smooth mesh.off -o smooth.obj",
                  "meshsmith smooth mesh.off -o laplace.ply --method laplacian --iterations 5 --weights cotan_delaunay",
                  "meshsmith smooth mesh.off -o bounded.obj --iterations 50 --epsilon 0.01",
                  "meshsmith smooth mesh.off -o slab.off --epsilon 0.005 --slab --direction normal",
                  "meshsmith smooth disk.obj -o implicit.obj --method laplacian --implicit --lambda 5 --fix-boundary",
                  "meshsmith smooth disk.obj -o faired.obj --method bilaplacian"])
    smooth.add_argument("input", help="mesh file (OBJ, OFF, PLY, STL)")
    smooth.add_argument("-o", "--output", required=True, help="smoothed mesh file (same faces)")
    smooth.add_argument("--method", choices=tuple(METHODS), default="taubin", help="default: taubin")
    smooth.add_argument("--iterations", type=integer(0), default=10,
                        help="steps (taubin: lambda|mu pairs); default 10")
    smooth.add_argument("--lambda", dest="lam", type=number(0, open_low=True), default=None,
                        help="step size lambda > 0 (default 0.5; explicit steps diverge above 1)")
    smooth.add_argument("--mu", type=number(high=0, open_high=True), default=-0.53,
                        help="taubin's inflating step, < 0 (default -0.53)")
    smooth.add_argument("--weights", choices=smoothing.WEIGHTS, default="uniform", help="edge weights; default uniform")
    smooth.add_argument("--direction", choices=smoothing.DIRECTIONS, default="full",
                        help="apply each step's full displacement, its normal or its tangential part; default full")
    smooth.add_argument("--implicit", action="store_true", help="laplacian: implicit (backward Euler) steps")
    smooth.add_argument("--fix-boundary", action="store_true", help="hold the boundary vertices in place")
    smooth.add_argument("--epsilon", type=number(0, open_low=True), metavar="E",
                        help="no vertex moves farther than E from its input position")
    smooth.add_argument("--slab", action="store_true",
                        help="with --epsilon: bound only the motion along the input vertex normal (error slab)")
    smooth.set_defaults(run=command_smooth)
