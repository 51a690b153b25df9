"""`meshsmith reconstruct`: a closed surface from a point cloud by screened Poisson (§2.2, §3.1)."""
from __future__ import annotations

import argparse

from .. import io, points, reconstruction
from .common import MESH_SUFFIXES, ProgressBar, add_command, check_output, integer, number


def command_reconstruct(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    P, N = io.read_points(args.input)
    progress = ProgressBar()
    if N is None:  # no normals in the file: PCA normals, oriented along a spanning tree
        N = points.orient_normals(P, points.estimate_normals(P, k=args.k, progress=progress), k=args.k,
                                  progress=progress)
    mesh = reconstruction.poisson(P, N, depth=args.depth, screening=args.screening, progress=progress)
    V, F = mesh.V, mesh.F
    if args.trim:
        V, F, _ = reconstruction.trim_by_density(V, F, mesh.density, quantile=args.trim)
    io.write_mesh(args.output, V, F)
    print(f"wrote {args.output}: {len(V)} vertices, {len(F)} triangles from {len(P)} points (depth {args.depth})")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    reconstruct = add_command(
        commands, "reconstruct", help="reconstruct a closed surface from a point cloud (screened Poisson)",
        description="Screened Poisson reconstruction (Kazhdan & Hoppe 2013) of a point cloud with outward normals "
                    "(a file without normals gets PCA normals oriented along a minimum spanning tree). The "
                    "output is closed and manifold; --trim removes the given fraction of least supported "
                    "vertices (by sample density), opening where there were no samples.",
        examples=["meshsmith reconstruct points.xyz -o surface.obj --depth 6",
                  "meshsmith reconstruct points.xyz -o trimmed.ply --depth 5 --trim 0.05"])
    reconstruct.add_argument("input", help="point cloud (XYZ or PLY, with or without normals)")
    reconstruct.add_argument("-o", "--output", required=True, help="output mesh (OBJ, OFF, PLY, STL)")
    reconstruct.add_argument("--depth", type=integer(2, 10), default=8, help="grid depth: 2^depth cells along the "
                             "bounding cube, 2 to 10 (default 8)")
    reconstruct.add_argument("--screening", type=number(0), default=4.0, help="screening weight (default 4)")
    reconstruct.add_argument("--trim", type=number(0, 1), default=0.0, help="fraction of vertices to trim by "
                             "density, 0 to 1 (default 0: none)")
    reconstruct.add_argument("--k", type=integer(3, 10_000), default=16, help="neighbours for normals when the "
                             "file has none (default 16)")
    reconstruct.set_defaults(run=command_reconstruct)
