"""Contouring benchmarks (tessellation chapter): power diagrams, the 2D crust and Cocone.

Peers where one exists: scipy.spatial.Voronoi (unweighted, unclipped cells: a lower bound for the
power diagram's work), scipy.spatial.Delaunay (the triangulation alone, a floor for the crust and
Cocone) and Open3D's alpha-shape reconstruction (a different surface reconstruction of the same
points, for scale).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay, Voronoi

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

import meshsmith  # noqa: E402
from meshsmith import tessellation as tess  # noqa: E402

try:
    import open3d as o3d
except Exception:  # not installable everywhere
    o3d = None


def main() -> None:
    rng = np.random.default_rng(0)
    P2 = rng.random((20_000, 2))
    w2 = 1e-5 * rng.random(len(P2))
    bench = Benchmark("contouring", "power diagram, 20k weighted sites in 2D (cells clipped)", repeats=3)
    bench.time("meshsmith", lambda: tess.power_diagram(P2, w2))
    bench.time("scipy Voronoi (unweighted)", lambda: Voronoi(P2))
    bench.report()

    P3 = rng.random((5_000, 3))
    w3 = 1e-4 * rng.random(len(P3))
    bench = Benchmark("contouring", "power diagram, 5k weighted sites in 3D (cells clipped)", repeats=3)
    bench.time("meshsmith", lambda: tess.power_diagram(P3, w3))
    bench.time("scipy Voronoi (unweighted)", lambda: Voronoi(P3))
    bench.report()

    t = np.linspace(0, 2 * np.pi, 100_000, endpoint=False)
    curve = np.c_[(1 + 0.3 * np.cos(5 * t)) * np.cos(t), (1 + 0.3 * np.cos(5 * t)) * np.sin(t)]
    bench = Benchmark("contouring", "crust of 100k samples of a star curve", repeats=3)
    bench.time("meshsmith", lambda: tess.crust(curve))
    bench.time("scipy Delaunay (samples only)", lambda: Delaunay(curve))
    bench.report()

    V0, F0 = meshsmith.datasets.torus(n_major=256, n_minor=128)
    P, _ = meshsmith.datasets.sample_points(V0, F0, 100_000, seed=0)
    bench = Benchmark("contouring", "Cocone (crust_3d) of 100k torus samples", repeats=3)
    bench.time("meshsmith", lambda: tess.crust_3d(P))
    bench.time("scipy Delaunay 3D (triangulation only)", lambda: Delaunay(P))
    if o3d is not None:
        o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(P))
        bench.time("open3d alpha shape (alpha 0.05)",
                   lambda: o3d.geometry.TriangleMesh.create_from_point_cloud_alpha_shape(cloud, 0.05))
    bench.report()


if __name__ == "__main__":
    main()
