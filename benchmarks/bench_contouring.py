"""Contouring benchmarks (tessellation chapter): power diagrams, the 2D crust and Cocone.

No PyPI library computes clipped power cells, a crust or Cocone, so every peer here does other
(less) work and its ratio is shown in parentheses: scipy.spatial.Voronoi (unweighted, unclipped
cells) and scipy's ConvexHull of the lifted sites (the regular triangulation alone) under the
power diagram, scipy.spatial.Delaunay (the triangulation alone) under the crust and Cocone, and
Open3D's alpha-shape reconstruction (a different surface reconstruction of the same points, for
scale). Sizes: 20k sites in 2D, 5k in 3D, 100k curve and surface samples (5k, 1k, 10k, 5k in
quick mode).

Result checks (tolerance 0 unless stated): the regular triangulation equals the lower hull of the
lifted sites (scipy's Qhull), the clipped 2D cells tile the box (area within 1e-9 relative); the
crust of the densely sampled star curve is the polygon through consecutive samples; Cocone's
torus is a closed manifold of Euler characteristic 0 through every sample.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull, Delaunay, Voronoi

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, differing_simplices, optional, relative_difference, size  # noqa: E402

import meshsmith  # noqa: E402
from meshsmith import tessellation as tess, topology  # noqa: E402

o3d = optional("open3d")


def lifted_lower_hull(P, weights) -> np.ndarray:
    """The regular triangulation as the lower hull of the sites lifted to |p|^2 - w (Qhull)."""
    hull = ConvexHull(np.column_stack([P, (P ** 2).sum(axis=1) - weights]))
    return hull.simplices[hull.equations[:, -2] < 0]


def polygon_area(corners) -> float:
    x, y = corners[:, 0], corners[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def main() -> None:
    rng = np.random.default_rng(0)
    n2 = size(20_000, 5_000)
    P2 = rng.random((n2, 2))
    w2 = 1e-5 * rng.random(len(P2))
    bench = Benchmark("contouring", f"power diagram, {n2 // 1000}k weighted sites in 2D (cells clipped)", repeats=5)
    bench.time("meshsmith", lambda: tess.power_diagram(P2, w2))
    bench.time("scipy Voronoi (unweighted)", lambda: Voronoi(P2), same_work=False)
    bench.time("scipy ConvexHull of lifted sites (triangulation only)", lambda: lifted_lower_hull(P2, w2),
               same_work=False)
    bench.report()
    diagram = bench.output("meshsmith")
    bench.check("regular triangles differing from scipy's lower hull",
                differing_simplices(diagram.triangulation, bench.output("scipy ConvexHull of lifted sites (triangulation only)")), 0)
    xmin, ymin, xmax, ymax = diagram.bounds
    bench.check("clipped cells' total area vs the box's, relative",
                relative_difference(sum(polygon_area(cell) for cell in diagram.cells if len(cell)),
                                    (xmax - xmin) * (ymax - ymin)), 1e-9)

    n3 = size(5_000, 1_000)
    P3 = rng.random((n3, 3))
    w3 = 1e-4 * rng.random(len(P3))
    bench = Benchmark("contouring", f"power diagram, {n3 // 1000}k weighted sites in 3D (cells clipped)", repeats=5)
    bench.time("meshsmith", lambda: tess.power_diagram(P3, w3))
    bench.time("scipy Voronoi (unweighted)", lambda: Voronoi(P3), same_work=False)
    bench.time("scipy ConvexHull of lifted sites (triangulation only)", lambda: lifted_lower_hull(P3, w3),
               same_work=False)
    bench.report()
    bench.check("regular tetrahedra differing from scipy's lower hull",
                differing_simplices(bench.output("meshsmith").triangulation,
                                    bench.output("scipy ConvexHull of lifted sites (triangulation only)")), 0)

    m = size(100_000, 10_000)
    t = np.linspace(0, 2 * np.pi, m, endpoint=False)
    curve = np.c_[(1 + 0.3 * np.cos(5 * t)) * np.cos(t), (1 + 0.3 * np.cos(5 * t)) * np.sin(t)]
    bench = Benchmark("contouring", f"crust of {m // 1000}k samples of a star curve", repeats=5)
    bench.time("meshsmith", lambda: tess.crust(curve))
    bench.time("scipy Delaunay (samples only)", lambda: Delaunay(curve), same_work=False)
    bench.report()
    polygon = np.sort(np.column_stack([np.arange(m), (np.arange(m) + 1) % m]), axis=1)
    bench.check("crust edges differing from the sampled polygon's", differing_simplices(bench.output("meshsmith"), polygon), 0)

    V0, F0 = meshsmith.datasets.torus(n_major=size(256, 64), n_minor=size(128, 32))
    m = size(100_000, 5_000)
    P, _ = meshsmith.datasets.sample_points(V0, F0, m, seed=0)
    bench = Benchmark("contouring", f"Cocone (crust_3d) of {m // 1000}k torus samples", repeats=5)
    bench.time("meshsmith", lambda: tess.crust_3d(P))
    bench.time("scipy Delaunay 3D (triangulation only)", lambda: Delaunay(P), same_work=False)
    if o3d is not None:
        o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(P))
        bench.time("open3d alpha shape (alpha 0.05)",
                   lambda: o3d.geometry.TriangleMesh.create_from_point_cloud_alpha_shape(cloud, 0.05),
                   same_work=False)
    bench.report()
    V, F = bench.output("meshsmith")
    summary = topology.info(V, F)
    bench.check("Cocone torus: boundary edges + non-manifold elements + unreferenced samples + |χ|",
                summary.n_boundary_edges + summary.n_non_manifold_edges + summary.n_non_manifold_vertices
                + summary.n_unreferenced_vertices + abs(summary.euler_characteristic), 0)


if __name__ == "__main__":
    main()
