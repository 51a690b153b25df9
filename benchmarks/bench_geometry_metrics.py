"""Geometry metrics benchmarks: Hausdorff distance and point-to-mesh closest points against libigl,
and parametrization distortion against a numpy reference.

Input (distances): an icosphere with 7 subdivisions (327,680 faces, 163,842 vertices; 5
subdivisions, 20,480 faces, in quick mode) and a noisy copy of it (vertices moved along their
normals by 0.3 mean edge lengths): two different surfaces with the same connectivity, the typical
"original vs processed" comparison. Input (distortion): a 400×400 grid (200×200 in quick mode)
bent into a height field, parametrized by its stretched xy coordinates.

Same work: closest points are timed tree build + query on both sides, and then the query alone
against a prebuilt tree on both sides; the two squared-distance calls of libigl also take the
square root and the maximum, as a Hausdorff distance does.

Result checks (tolerances): the Hausdorff distance within 1e-12 relative of libigl's; closest
squared distances within 1e-12 of libigl's (absolute, on the unit sphere) and each closest point
at its returned distance from the query (1e-12; at ties the two libraries may pick different
points at the same distance); singular values within 1e-10 relative of numpy's SVD.
"""
from __future__ import annotations

import sys
from pathlib import Path

import igl
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, size  # noqa: E402

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
    VA, FA = datasets.icosphere(size(7, 5))
    VB, FB = datasets.noisy(VA, FA, sigma=0.3, seed=1)
    print(f"A: {len(FA)} faces, B: {len(FB)} faces")
    faces = f"{len(FA) // 1000}k"

    def igl_two_sided():
        return np.sqrt(max(igl.point_mesh_squared_distance(VA, VB, FB)[0].max(),
                           igl.point_mesh_squared_distance(VB, VA, FA)[0].max()))

    bench = Benchmark("geometry_metrics", f"hausdorff (vertex-sampled), {faces} vs {faces} faces", repeats=5)
    bench.time("meshsmith", lambda: hausdorff_distance(VA, FA, VB, FB))
    bench.time("igl.hausdorff", lambda: igl.hausdorff(VA, FA, VB, FB))
    bench.time("igl.point_mesh_squared_distance x2, sqrt, max", igl_two_sided)
    bench.time("meshsmith sampled, 4/face", lambda: hausdorff_distance(VA, FA, VB, FB, sampled=True, samples_per_face=4))
    bench.report()
    ours, reference = bench.output("meshsmith"), bench.output("igl.hausdorff")
    bench.check("Hausdorff distance vs igl.hausdorff, relative", abs(ours - reference) / reference, 1e-12)

    Q = VB
    tree = SurfaceDistance(VA, FA)
    queries = f"{len(Q) // 1000}k queries on {faces} faces"
    bench = Benchmark("geometry_metrics", f"closest points (tree build + query), {queries}", repeats=5)
    bench.time("meshsmith", lambda: SurfaceDistance(VA, FA).closest_points(Q))
    bench.time("igl.point_mesh_squared_distance", lambda: igl.point_mesh_squared_distance(Q, VA, FA))
    bench.time("meshsmith build alone", lambda: SurfaceDistance(VA, FA))
    bench.report()
    distance, _, point = bench.output("meshsmith")
    squared, _, igl_point = bench.output("igl.point_mesh_squared_distance")
    bench.check("closest squared distances vs libigl, max |difference|", np.abs(distance**2 - squared).max(), 1e-12)
    # Where a query is equally far from two faces the two libraries may return different points:
    # each point must lie at the returned distance, which must equal libigl's (checked above).
    bench.check("closest points: max | |q - c| - distance |", np.abs(np.linalg.norm(Q - point, axis=1) - distance).max(),
                1e-12)
    ties = int((np.abs(point - igl_point).max(axis=1) > 1e-9).sum())
    print(f"  closest points differing from libigl's (ties at equal distance): {ties} of {len(Q)}")

    igl_tree = igl.AABB()
    igl_tree.init(VA, FA)
    bench = Benchmark("geometry_metrics", f"closest points, query of a prebuilt tree, {queries}", repeats=5)
    bench.time("meshsmith", lambda: tree.closest_points(Q))
    bench.time("igl.AABB squared_distance", lambda: igl_tree.squared_distance(VA, FA, Q))
    bench.report()

    n = size(400, 200)
    VG, FG = datasets.grid(n, n)  # a height field over its own xy as parametrization
    VG[:, 2] = 0.2 * np.sin(6 * VG[:, 0]) * np.cos(4 * VG[:, 1])
    UV = VG[:, :2] * [1.3, 0.8]
    bench = Benchmark("geometry_metrics", f"triangle_distortion, {len(FG) // 1000}k faces", repeats=5)
    bench.time("meshsmith", lambda: triangle_distortion(VG, FG, UV))
    bench.time("numpy Jacobians + SVD", lambda: numpy_distortion(VG, FG, UV))
    bench.report()
    _, sigma = bench.output("numpy Jacobians + SVD")
    d = bench.output("meshsmith")
    finite = np.isfinite(sigma).all(1)
    bench.check("singular values vs numpy SVD, max |difference| / sigma1",
                (np.abs(d.singular_values - sigma)[finite] / sigma[finite].max(1, keepdims=True)).max(), 1e-10)


if __name__ == "__main__":
    main()
