"""Benchmarks of the geometry chapter against libigl on a ~1.3M-face mesh (an icosahedron
subdivided 8 times, built here with numpy): cotangent Laplacian + mass matrix, vertex normals,
Gaussian curvature, mean curvature. Issue goal: each at most half of libigl's time. On the
shared armadillo (when ../shared/data or $MESHSMITH_DATA is there): principal curvatures against
libigl, and 20 Laplacian eigenpairs against scipy's ARPACK shift-invert."""
from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

from meshsmith.datasets import icosphere  # noqa: E402  (20·4^s faces: 8 → 1,310,720)
from meshsmith import geometry  # noqa: E402


def main() -> None:
    import igl

    V, F = icosphere(8)
    size = f"{len(F):,} faces, {len(V):,} vertices"

    bench = Benchmark("geometry", f"cotan Laplacian + Voronoi mass matrix, icosphere {size}")
    bench.time("meshsmith", lambda: (geometry.cotan_laplacian(V, F), geometry.mass_matrix(V, F)))
    bench.time("libigl", lambda: (igl.cotmatrix(V, F), igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)))
    bench.report()

    for weighting, igl_type in [("angle", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE),
                                ("area", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA)]:
        bench = Benchmark("geometry", f"vertex normals ({weighting}-weighted), icosphere {size}")
        bench.time("meshsmith", lambda: geometry.vertex_normals(V, F, weighting))
        bench.time("libigl", lambda: igl.per_vertex_normals(V, F, igl_type))
        bench.report()

    bench = Benchmark("geometry", f"Gaussian curvature (angle defect), icosphere {size}")
    bench.time("meshsmith", lambda: geometry.gaussian_curvature(V, F))
    bench.time("libigl", lambda: igl.gaussian_curvature(V, F))
    bench.report()

    def igl_mean_curvature_normal():
        M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
        return -0.5 * (igl.cotmatrix(V, F) @ V) / M.diagonal()[:, None]

    bench = Benchmark("geometry", f"mean curvature normal -1/2 M^-1 L V, icosphere {size}")
    bench.time("meshsmith", lambda: geometry.mean_curvature(V, F))
    bench.time("libigl (cotmatrix, massmatrix)", igl_mean_curvature_normal)
    bench.report()

    shared = [Path(p) for p in (os.environ.get("MESHSMITH_DATA"),
                                Path(__file__).resolve().parents[2] / "shared" / "data") if p]
    armadillo = next((d / "armadillo.obj" for d in shared if (d / "armadillo.obj").is_file()), None)
    if armadillo is None:
        print("\n(shared data not found: principal curvature and eigenpair cases skipped)")
        return
    import scipy.sparse.linalg

    V, F = igl.read_triangle_mesh(str(armadillo))
    size = f"armadillo {len(F):,} faces"
    bench = Benchmark("geometry", f"principal curvatures and directions, {size}", repeats=3)
    bench.time("meshsmith", lambda: geometry.principal_curvatures(V, F))  # 2-ring quadric fit
    bench.time("meshsmith (shape operator)",
               lambda: geometry.principal_curvatures(V, F, method="shape_operator"))
    bench.time("libigl (radius-5 quadrics)", lambda: igl.principal_curvature(V, F))
    bench.report()

    def arpack_eigenpairs():
        L = igl.cotmatrix(V, F)
        M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
        return scipy.sparse.linalg.eigsh(-L, k=20, M=M, sigma=-1e-3)

    bench = Benchmark("geometry", f"20 smallest Laplacian eigenpairs, {size}", repeats=3)
    bench.time("meshsmith", lambda: geometry.laplacian_eigenpairs(V, F, 20))
    bench.time("scipy eigsh (SuperLU shift-invert)", arpack_eigenpairs)
    bench.report()


if __name__ == "__main__":
    main()
