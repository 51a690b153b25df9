"""Points chapter benchmarks: kNN, PCA normals and normal orientation against scipy and Open3D.

Input: points uniform on a unit sphere with a little noise (a scan-like surface sample).
Neighbourhoods are the same everywhere: 16 points = the point itself and its 15 nearest others
(meshsmith k=15, Open3D KDTreeSearchParamKNN(16), scipy query(P, 16)).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

import meshsmith.points as mp  # noqa: E402

try:
    import open3d as o3d
except Exception:  # not installable everywhere (needs Debian's libusb-1.0-0)
    o3d = None


def noisy_sphere(n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(n, 3))
    P /= np.linalg.norm(P, axis=1)[:, None]
    return P + rng.normal(scale=1e-3, size=P.shape)


def scipy_numpy_normals(P: np.ndarray, neighbourhood: int = 16, chunk: int = 100_000) -> np.ndarray:
    """Reference implementation: cKDTree (all cores) + batched numpy covariance and eigh."""
    _, neighbours = cKDTree(P).query(P, neighbourhood, workers=-1)
    normals = np.empty_like(P)
    for start in range(0, len(P), chunk):
        patch = P[neighbours[start:start + chunk]]
        patch = patch - patch.mean(axis=1, keepdims=True)
        covariance = np.einsum("nki,nkj->nij", patch, patch)
        normals[start:start + chunk] = np.linalg.eigh(covariance)[1][:, :, 0]
    return normals


def open3d_normals(P: np.ndarray, neighbourhood: int = 16) -> np.ndarray:
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(P))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(neighbourhood))
    return np.asarray(cloud.normals)


def open3d_oriented(P: np.ndarray, N: np.ndarray, k: int = 16) -> np.ndarray:
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(P))
    cloud.normals = o3d.utility.Vector3dVector(N)
    cloud.orient_normals_consistent_tangent_plane(k)
    return np.asarray(cloud.normals)


def main() -> None:
    P = noisy_sphere(1_000_000)

    mine = mp.estimate_normals(P, k=15)
    reference = scipy_numpy_normals(P)
    agreement = np.abs((mine * reference).sum(axis=1))
    print(f"meshsmith vs scipy+numpy normals: min |cos| = {agreement.min():.12f}")

    bench = Benchmark("points", "estimate_normals, 1M points, 16-point neighbourhoods", repeats=3)
    bench.time("meshsmith", lambda: mp.estimate_normals(P, k=15))
    bench.time("scipy cKDTree + numpy eigh", lambda: scipy_numpy_normals(P))
    if o3d is not None:
        bench.time("open3d estimate_normals", lambda: open3d_normals(P))
    bench.report()

    bench = Benchmark("points", "kNN of every point, 1M points, k=16", repeats=3)
    bench.time("meshsmith", lambda: mp.knn(P, 16))
    bench.time("meshsmith KdTree build", lambda: mp.KdTree(P))
    bench.time("scipy cKDTree build+query", lambda: cKDTree(P).query(P, 17, workers=-1))
    bench.report()

    Q = noisy_sphere(100_000, seed=1)
    N = mp.estimate_normals(Q, k=15)
    outward = (mp.orient_normals(Q, N, k=16) * Q).sum(axis=1) > 0
    print(f"meshsmith orient_normals: {outward.mean():.2%} outward")
    bench = Benchmark("points", "orient_normals, 100k points, k=16", repeats=3)
    bench.time("meshsmith", lambda: mp.orient_normals(Q, N, k=16))
    if o3d is not None:
        outward = (open3d_oriented(Q, N) * Q).sum(axis=1) > 0
        print(f"open3d orient_normals_consistent_tangent_plane: {max(outward.mean(), 1 - outward.mean()):.2%}"
              " consistent")
        bench.time("open3d consistent_tangent_plane", lambda: open3d_oriented(Q, N))
    bench.report()


if __name__ == "__main__":
    main()
