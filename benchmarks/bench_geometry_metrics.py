"""Geometry metrics benchmarks: Hausdorff distance and point-to-mesh closest points against libigl,
and parametrization distortion against a numpy reference.

Input (distances): an icosphere with 7 subdivisions (327,680 faces, 163,842 vertices) and a noisy copy of it
(vertices moved along their normals by 0.3 mean edge lengths): two different surfaces with the
same connectivity, the typical "original vs processed" comparison. Input (distortion): a 400×400
grid bent into a height field, parametrized by its stretched xy coordinates.
"""
from __future__ import annotations

import sys
from pathlib import Path

import igl
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

from meshsmith import datasets  # noqa: E402
from meshsmith.geometry import SurfaceDistance, hausdorff_distance, triangle_distortion  # noqa: E402


def numpy_distortion(V, F, UV):
    """Reference: per-face Jacobians in the triangle frame and their singular values (numpy SVD)."""
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    n = np.cross(e1, e2)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    x = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    y = np.cross(n, x)
    D3 = np.stack([np.stack([(e1 * x).sum(1), (e2 * x).sum(1)], -1),
                   np.stack([(e1 * y).sum(1), (e2 * y).sum(1)], -1)], 1)
    Duv = np.stack([UV[F[:, 1]] - UV[F[:, 0]], UV[F[:, 2]] - UV[F[:, 0]]], -1)
    J = D3 @ np.linalg.inv(Duv)
    return J, np.linalg.svd(J, compute_uv=False)


def main() -> None:
    VA, FA = datasets.icosphere(7)
    VB, FB = datasets.noisy(VA, FA, sigma=0.3, seed=1)
    print(f"A: {len(FA)} faces, B: {len(FB)} faces")

    ours, reference = hausdorff_distance(VA, FA, VB, FB), igl.hausdorff(VA, FA, VB, FB)
    print(f"hausdorff: meshsmith {ours:.17g}, igl {reference:.17g}, relative difference "
          f"{abs(ours - reference) / reference:.2e}")
    bench = Benchmark("geometry_metrics", "hausdorff (vertex-sampled), 327k vs 327k faces", repeats=3)
    bench.time("meshsmith", lambda: hausdorff_distance(VA, FA, VB, FB))
    bench.time("igl.hausdorff", lambda: igl.hausdorff(VA, FA, VB, FB))
    bench.time("igl.point_mesh_squared_distance x2",
               lambda: (igl.point_mesh_squared_distance(VA, VB, FB), igl.point_mesh_squared_distance(VB, VA, FA)))
    bench.time("meshsmith sampled, 4/face", lambda: hausdorff_distance(VA, FA, VB, FB, sampled=True, samples_per_face=4))
    bench.report()

    Q = VB
    tree = SurfaceDistance(VA, FA)
    distance, _, point = tree.closest_points(Q)
    squared, _, igl_point = igl.point_mesh_squared_distance(Q, VA, FA)
    print(f"closest points: max |d^2 - igl d^2| = {np.abs(distance**2 - squared).max():.2e}, "
          f"max |C - igl C| = {np.abs(point - igl_point).max():.2e}")
    bench = Benchmark("geometry_metrics", "closest points, 164k queries on 327k faces", repeats=3)
    bench.time("meshsmith", lambda: SurfaceDistance(VA, FA).closest_points(Q))
    bench.time("meshsmith query (prebuilt)", lambda: tree.closest_points(Q))
    bench.time("meshsmith build", lambda: SurfaceDistance(VA, FA))
    bench.time("igl.point_mesh_squared_distance", lambda: igl.point_mesh_squared_distance(Q, VA, FA))
    igl_tree = igl.AABB()
    igl_tree.init(VA, FA)
    bench.time("igl.AABB query (prebuilt)", lambda: igl_tree.squared_distance(VA, FA, Q))
    bench.report()

    VG, FG = datasets.grid(400, 400)  # 320k faces, a height field over its own xy as parametrization
    VG[:, 2] = 0.2 * np.sin(6 * VG[:, 0]) * np.cos(4 * VG[:, 1])
    UV = VG[:, :2] * [1.3, 0.8]
    J, sigma = numpy_distortion(VG, FG, UV)
    d = triangle_distortion(VG, FG, UV)
    finite = np.isfinite(sigma).all(1)
    print(f"distortion: max |sigma - numpy svd| / sigma = "
          f"{(np.abs(d.singular_values - sigma)[finite] / sigma[finite].max(1, keepdims=True)).max():.2e}")
    bench = Benchmark("geometry_metrics", "triangle_distortion, 320k faces", repeats=3)
    bench.time("meshsmith", lambda: triangle_distortion(VG, FG, UV))
    bench.time("numpy Jacobians + SVD", lambda: numpy_distortion(VG, FG, UV))
    bench.report()


if __name__ == "__main__":
    main()
