"""Benchmarks of the geometry chapter against libigl on an icosphere (an icosahedron subdivided
8 times, ~1.3M faces; 6 times, 82k faces, in quick mode): cotangent Laplacian + mass matrix,
vertex normals, Gaussian curvature, mean curvature. Issue goal: each at most half of libigl's
time. On the shared armadillo (when ../shared/data or $MESHSMITH_DATA is there): principal
curvatures against libigl, and 20 Laplacian eigenpairs against scipy's ARPACK shift-invert.

Same work on both sides: both get the same float64 V and int64 F and return the same quantities
(the mean-curvature case returns H and Hn on both sides: libigl's side signs |Hn| by its
angle-weighted vertex normals as meshsmith does; principal curvatures use a 2-ring on both sides).

Result checks (tolerances): L, M, normals, Hn and H within 1e-10 of libigl's, relative to
the largest entry; the angle defects K within 1e-12 radians (absolute: K is 2 pi minus a sum of
angles); eigenvalues within 1e-8 relative of scipy's; principal curvatures: the mean curvature
(k1 + k2) / 2 of meshsmith and libigl agree in sign at 99% of the vertices. Quick mode computes
the eigenpairs on a 5k-face icosphere instead.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, relative_difference, shared_data_dir, size  # noqa: E402

from meshsmith.datasets import icosphere  # noqa: E402  (20·4^s faces: 8 → 1,310,720)
from meshsmith import geometry  # noqa: E402

TOLERANCE = 1e-10  # relative to the largest entry: both sides sum the same cotangents


def sparse_relative_difference(A, B) -> float:
    return float(abs(A - B).max() / abs(B).max())


def main() -> None:
    import igl

    V, F = icosphere(size(8, 6))
    size_label = f"{len(F):,} faces, {len(V):,} vertices"

    bench = Benchmark("geometry", f"cotan Laplacian + Voronoi mass matrix, icosphere {size_label}")
    bench.time("meshsmith", lambda: (geometry.cotan_laplacian(V, F), geometry.mass_matrix(V, F)))
    bench.time("libigl", lambda: (igl.cotmatrix(V, F), igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)))
    bench.report()
    (L, M), (L_igl, M_igl) = bench.output("meshsmith"), bench.output("libigl")
    bench.check("cotan Laplacian entries vs libigl, max |difference| / max |entry|",
                sparse_relative_difference(L, L_igl), TOLERANCE)
    bench.check("Voronoi mass matrix vs libigl, max relative", sparse_relative_difference(M, M_igl), TOLERANCE)

    for weighting, igl_type in [("angle", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE),
                                ("area", igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_AREA)]:
        bench = Benchmark("geometry", f"vertex normals ({weighting}-weighted), icosphere {size_label}")
        bench.time("meshsmith", lambda: geometry.vertex_normals(V, F, weighting))
        bench.time("libigl", lambda: igl.per_vertex_normals(V, F, igl_type))
        bench.report()
        bench.check("normals vs libigl, max |difference|",
                    relative_difference(bench.output("meshsmith"), bench.output("libigl")), TOLERANCE)

    bench = Benchmark("geometry", f"Gaussian curvature (angle defect), icosphere {size_label}")
    bench.time("meshsmith", lambda: geometry.gaussian_curvature(V, F))
    bench.time("libigl", lambda: igl.gaussian_curvature(V, F))
    bench.report()
    # An angle defect is 2 pi minus a sum of angles: its rounding error is that of 2 pi, not of the
    # (tiny, on a fine mesh) defect, so the tolerance is absolute, in radians.
    bench.check("angle defects vs libigl, max |difference| [rad]",
                np.abs(bench.output("meshsmith") - bench.output("libigl")).max(), 1e-12)

    def igl_mean_curvature():
        """(H, Hn) as meshsmith returns them: Hn = -1/2 M^-1 L V, H = |Hn| signed by Hn . n."""
        M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
        Hn = -0.5 * (igl.cotmatrix(V, F) @ V) / M.diagonal()[:, None]
        normals = igl.per_vertex_normals(V, F, igl.PER_VERTEX_NORMALS_WEIGHTING_TYPE_ANGLE)
        return np.copysign(np.linalg.norm(Hn, axis=1), (Hn * normals).sum(axis=1)), Hn

    bench = Benchmark("geometry", f"mean curvature H and normal -1/2 M^-1 L V, icosphere {size_label}")
    bench.time("meshsmith", lambda: geometry.mean_curvature(V, F))
    bench.time("libigl (cotmatrix, massmatrix, per_vertex_normals)", igl_mean_curvature)
    bench.report()
    (H, Hn), (H_igl, Hn_igl) = bench.output("meshsmith"), bench.output("libigl (cotmatrix, massmatrix, per_vertex_normals)")
    bench.check("mean curvature normal Hn vs libigl, max relative", relative_difference(Hn, Hn_igl), TOLERANCE)
    bench.check("mean curvature H vs libigl, max relative", relative_difference(H, H_igl), TOLERANCE)

    shared = shared_data_dir()
    armadillo = shared / "armadillo.obj" if shared else None
    if armadillo is None or not armadillo.is_file():
        print("\n(shared data not found: principal curvature and eigenpair cases skipped)")
        return
    import scipy.sparse.linalg

    V, F = igl.read_triangle_mesh(str(armadillo))
    size_label = f"armadillo {len(F):,} faces"
    bench = Benchmark("geometry", f"principal curvatures and directions (2-ring), {size_label}", repeats=5)
    bench.time("meshsmith", lambda: geometry.principal_curvatures(V, F))  # 2-ring quadric fit
    bench.time("meshsmith (shape operator)",
               lambda: geometry.principal_curvatures(V, F, method="shape_operator"))
    # libigl fits its quadrics to the radius-k ring with use_k_ring (its default radius is 5 rings).
    bench.time("libigl (2-ring quadrics)", lambda: igl.principal_curvature(V, F, 2))
    bench.report()
    k1, k2, _, _ = bench.output("meshsmith")
    igl_k1, igl_k2 = bench.output("libigl (2-ring quadrics)")[2:4]
    bench.check("principal curvatures: share of vertices where the sign of (k1 + k2) differs from libigl's",
                np.mean(np.sign(k1 + k2) != np.sign(igl_k1 + igl_k2)), 0.01)

    if size(False, True):  # scipy's shift-invert takes seconds on the armadillo: a smaller sphere
        V, F = icosphere(4)
        size_label = f"icosphere {len(F):,} faces"

    def arpack_eigenpairs():
        L = igl.cotmatrix(V, F)
        M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
        return scipy.sparse.linalg.eigsh(-L, k=20, M=M, sigma=-1e-3)

    bench = Benchmark("geometry", f"20 smallest Laplacian eigenpairs, {size_label}", repeats=5)
    bench.time("meshsmith", lambda: geometry.laplacian_eigenpairs(V, F, 20))
    bench.time("scipy eigsh (SuperLU shift-invert)", arpack_eigenpairs)
    bench.report()
    values, _ = bench.output("meshsmith")
    reference = np.sort(bench.output("scipy eigsh (SuperLU shift-invert)")[0])
    bench.check("eigenvalues vs scipy, max |difference| / largest", relative_difference(values, reference), 1e-8)


if __name__ == "__main__":
    main()
