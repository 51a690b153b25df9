"""`meshsmith reconstruct`: a closed surface from a point cloud by screened Poisson, a tangent-plane
signed distance, a graph cut or the Cocone crust (§2.1.3, §2.2, §3.1–3.2)."""
from __future__ import annotations

import argparse

import numpy as np

from .. import io, points, reconstruction, tessellation
from .common import MESH_SUFFIXES, ProgressBar, add_command, check_output, integer, number

METHODS = ("poisson", "sdf", "graphcut", "crust")


def oriented_normals(P: np.ndarray, N: np.ndarray | None, k: int, progress: ProgressBar) -> np.ndarray:
    """The file's normals, or PCA normals oriented along a minimum spanning tree."""
    if N is not None:
        return N
    return points.orient_normals(P, points.estimate_normals(P, k=k, progress=progress), k=k, progress=progress)


def tangent_plane_surface(P: np.ndarray, N: np.ndarray, resolution: int,
                          progress: ProgressBar) -> tuple[np.ndarray, np.ndarray]:
    """The zero set of the samples' tangent-plane distance (Hoppe 1992, a blend over 8 neighbours) on a
    grid of `resolution` cells along the padded bounding box, contoured from the samples outwards
    (only the piece of the level set through the samples, not the spurious far-field crossings)."""
    lower, upper = P.min(axis=0), P.max(axis=0)
    pad = 0.1 * float((upper - lower).max())
    grid = reconstruction.sample_grid([lower - pad, upper + pad], resolution + 1)
    k = min(8, len(P))
    mesh = reconstruction.marching_cubes_sparse(
        lambda X: reconstruction.tangent_plane_sdf(P, N, X, k=k), shape=grid.shape, seeds=P, origin=grid.origin,
        spacing=grid.spacing, progress=progress)
    return mesh.V, mesh.F


def command_reconstruct(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    P, N = io.read_points(args.input)
    progress = ProgressBar()
    detail = ""
    if args.method == "poisson":
        mesh = reconstruction.poisson(P, oriented_normals(P, N, args.k, progress), depth=args.depth,
                                      screening=args.screening, progress=progress)
        V, F = mesh.V, mesh.F
        if args.trim:
            V, F, _ = reconstruction.trim_by_density(V, F, mesh.density, quantile=args.trim)
        detail = f"depth {args.depth}, surface extracted at depth {mesh.extraction_depth}"
    elif args.method == "sdf":
        V, F = tangent_plane_surface(P, oriented_normals(P, N, args.k, progress), args.resolution, progress)
        detail = f"resolution {args.resolution}"
    elif args.method == "graphcut":
        cut = reconstruction.graph_cut(P, resolution=args.resolution, progress=progress)
        V, F = cut.V, cut.F
        detail = f"resolution {args.resolution}, voxel {cut.voxel_size:.4g}"
    else:
        V, F = tessellation.crust_3d(P, progress=progress)
    if args.trim and args.method != "poisson":
        print(f"note: --trim applies to --method poisson only; ignored for {args.method}")
    io.write_mesh(args.output, V, F)
    print(f"wrote {args.output}: {len(V)} vertices, {len(F)} triangles from {len(P)} points "
          f"({args.method}{', ' + detail if detail else ''})")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    reconstruct = add_command(
        commands, "reconstruct", help="reconstruct a closed surface from a point cloud (Poisson, SDF, graph cut, crust)",
        description="Reconstruct a surface from a point cloud. --method poisson (default): screened Poisson "
                    "(Kazhdan & Hoppe 2013) from outward normals, closed and manifold; --trim removes the given "
                    "fraction of least supported vertices (by sample density). --method sdf: the zero set of the "
                    "samples' tangent-plane distance (Hoppe et al. 1992) by marching cubes. Both need normals: a "
                    "file without them gets PCA normals oriented along a minimum spanning tree. --method "
                    "graphcut: a minimum s-t cut of a voxel grid scored by the unsigned distance to the points "
                    "(no normals needed), watertight. --method crust: the Cocone crust of the Delaunay "
                    "triangulation (Amenta et al.), interpolating the points; for dense, noise-free samples.",
        examples=["meshsmith reconstruct points.xyz -o surface.obj --depth 6",
                  "meshsmith reconstruct points.xyz -o trimmed.ply --depth 5 --trim 0.05",
                  "meshsmith reconstruct points.xyz -o sdf.obj --method sdf --resolution 24",
                  "meshsmith reconstruct points.xyz -o cut.obj --method graphcut --resolution 24",
                  "meshsmith reconstruct points.xyz -o crust.obj --method crust"])
    reconstruct.add_argument("input", help="point cloud (XYZ or PLY, with or without normals)")
    reconstruct.add_argument("-o", "--output", required=True, help="output mesh (OBJ, OFF, PLY, STL)")
    reconstruct.add_argument("--method", choices=METHODS, default="poisson",
                             help="poisson (default), sdf, graphcut or crust")
    reconstruct.add_argument("--depth", type=integer(2, 10), default=8, help="poisson: grid depth, 2^depth cells "
                             "along the bounding cube, 2 to 10 (default 8)")
    reconstruct.add_argument("--resolution", type=integer(2, 1024), default=64, help="sdf, graphcut: cells along "
                             "the longest bounding-box edge, 2 to 1024 (default 64)")
    reconstruct.add_argument("--screening", type=number(0), default=8.0, help="poisson: screening weight (default 8)")
    reconstruct.add_argument("--trim", type=number(0, 1), default=0.0, help="poisson: fraction of vertices to trim "
                             "by density, 0 to 1 (default 0: none)")
    reconstruct.add_argument("--k", type=integer(3, 10_000), default=16, help="neighbours for normals when the "
                             "file has none (default 16)")
    reconstruct.set_defaults(run=command_reconstruct)
