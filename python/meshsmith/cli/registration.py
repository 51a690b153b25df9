"""`meshsmith register`: rigid registration of two scans by ICP (§2.3.1)."""
from __future__ import annotations

import argparse

import numpy as np

from .. import InputError, io, registration
from .common import (
    MESH_SUFFIXES,
    ProgressBar,
    add_command,
    check_output,
    integer,
    number,
    read_point_cloud,
)


def _read_transform(path: str) -> np.ndarray:
    try:
        T = np.loadtxt(path, ndmin=2)
    except (OSError, ValueError) as error:
        raise InputError(f"--initial {path}: {error}") from None
    if T.shape != (4, 4):
        raise InputError(f"--initial {path}: holds a {T.shape[0]}×{T.shape[1]} table, expected a 4×4 transform")
    return T


def command_register(args: argparse.Namespace) -> int:
    check_output(args.output, (".txt",), "-o")
    if args.apply:
        check_output(args.apply, MESH_SUFFIXES + (".xyz",), "--apply")
    source = read_point_cloud(args.source)
    target = read_point_cloud(args.target)
    initial = _read_transform(args.initial) if args.initial else None
    result = registration.icp(source, target, method=args.method, max_iterations=args.max_iterations,
                              tolerance=args.tolerance, max_distance=args.max_distance, trim=args.trim,
                              voxel_size=args.voxel_size, initial=initial, progress=ProgressBar())
    T = result.transform
    np.savetxt(args.output, T, fmt="%.17g")
    diagonal = float(np.linalg.norm(target.max(axis=0) - target.min(axis=0)))
    print(f"wrote {args.output}: {args.method} ICP, {result.iterations} iterations, "
          f"{'converged' if result.converged else 'NOT converged (raise --max-iterations or --tolerance)'} "
          f"(stop: {result.stop.replace('_', ' ')})")
    print(f"rotation {np.degrees(registration.rotation_angle(T)):.4g} degrees, translation "
          f"{np.linalg.norm(T[:3, 3]):.6g}; RMS {result.rms:.6g} ({100 * result.rms / diagonal:.4g}% of the target's "
          f"diagonal) over {100 * result.inlier_fraction:.4g}% of the source points")
    if args.apply:
        if args.apply.lower().endswith(MESH_SUFFIXES) and not args.source.lower().endswith((".xyz", ".ply")):
            V, F = io.read_mesh(args.source)
            io.write_mesh(args.apply, registration.apply_transform(T, V), F)
        elif args.apply.lower().endswith((".xyz", ".ply")):
            io.write_points(args.apply, registration.apply_transform(T, source))
        else:
            raise InputError(f"--apply {args.apply}: a point-cloud source is written as .xyz or .ply")
        print(f"wrote {args.apply}: the source moved onto the target")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    parser = add_command(
        commands, "register", help="align a scan onto another (ICP)",
        description="Rigidly align SOURCE onto TARGET by iterative closest points (§2.3.1) and write the "
                    "4×4 transform (a text file that numpy.loadtxt reads; x ↦ T[:3, :3] x + T[:3, 3]). Point "
                    "clouds (XYZ, PLY) or meshes (OBJ, OFF, STL: their vertices). ICP is local: give a start "
                    "(--initial) when the scans differ by more than about 30 degrees.",
        examples=["meshsmith register points.xyz mesh.off -o T.txt",
                  "meshsmith register mesh.off points.xyz -o T.txt --method point_to_plane --apply moved.off",
                  "meshsmith register points.xyz mesh.off -o T.txt --trim 0.8 --max-distance 0.5 --apply moved.xyz"])
    parser.add_argument("source", help="the scan to move (XYZ, PLY, OBJ, OFF, STL)")
    parser.add_argument("target", help="the scan it is aligned onto")
    parser.add_argument("-o", "--output", required=True, help="the 4×4 transform (.txt)")
    parser.add_argument("--apply", metavar="OUT", help="also write the moved source (a mesh source as a mesh; "
                        "a point cloud as .xyz or .ply)")
    parser.add_argument("--method", choices=registration.ICP_METHODS, default="point_to_point",
                        help="default: point_to_point")
    parser.add_argument("--max-iterations", type=integer(1, 100_000), default=50, help="default 50")
    parser.add_argument("--tolerance", type=number(0, open_low=True), default=1e-6,
                        help="stop when an iteration rotates less than this (radians) and moves less than this "
                             "fraction of the diagonal (default 1e-6)")
    parser.add_argument("--max-distance", type=number(0, open_low=True),
                        help="pairs farther apart are outliers (default: no limit)")
    parser.add_argument("--trim", type=number(0, 1, open_low=True), default=1.0,
                        help="use only this fraction of the closest pairs (trimmed ICP; default 1)")
    parser.add_argument("--voxel-size", type=number(0, open_low=True),
                        help="first reduce both scans to one point per cube of this edge")
    parser.add_argument("--initial", metavar="T0.txt", help="start transform (4×4 text file)")
    parser.set_defaults(run=command_register)
