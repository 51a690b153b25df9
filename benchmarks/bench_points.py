"""Points chapter benchmarks: kNN, PCA normals and normal orientation against scipy and Open3D.

Input: points uniform on a unit sphere with a little noise (a scan-like surface sample).
Neighbourhoods are the same everywhere: 16 points = the point itself and its 15 nearest others
(meshsmith k=15, Open3D KDTreeSearchParamKNN(16), scipy query(P, 16)). Sizes: 1M points for
normals and kNN, 100k for orientation (50k and 10k in quick mode).

Threads: meshsmith uses every core (TBB), Open3D too (OpenMP), scipy's cKDTree query is given
workers=-1 (every core); the numpy covariance and eigh of the reference run on one.

Result checks (tolerances): meshsmith's normals agree with the scipy+numpy reference, |cos| >
1 - 1e-6, at all but 0.1% of the points (a tie at the 16th distance may change a neighbourhood);
kNN distances equal scipy's within 1e-12 (indices may differ only at ties); at least 99.9% of the
oriented normals point outwards on the sphere.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, optional, size  # noqa: E402

import meshsmith.points as mp  # noqa: E402

o3d = optional("open3d")  # needs Debian's libusb-1.0-0


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
    n = size(1_000_000, 50_000)
    P = noisy_sphere(n)
    label = f"{n / 1e6:g}M" if n >= 1e6 else f"{n // 1000}k"

    bench = Benchmark("points", f"estimate_normals, {label} points, 16-point neighbourhoods", repeats=5)
    bench.time("meshsmith", lambda: mp.estimate_normals(P, k=15))
    bench.time("scipy cKDTree (workers=-1) + numpy eigh", lambda: scipy_numpy_normals(P))
    if o3d is not None:
        bench.time("open3d estimate_normals", lambda: open3d_normals(P))
    bench.report()
    mine = bench.output("meshsmith")
    agreement = np.abs((mine * bench.output("scipy cKDTree (workers=-1) + numpy eigh")).sum(axis=1))
    bench.check("share of normals with |cos| <= 1 - 1e-6 against scipy+numpy", np.mean(agreement <= 1 - 1e-6), 1e-3)
    if o3d is not None:
        agreement = np.abs((mine * bench.output("open3d estimate_normals")).sum(axis=1))
        bench.check("share of normals with |cos| <= 1 - 1e-6 against open3d", np.mean(agreement <= 1 - 1e-6), 1e-3)

    bench = Benchmark("points", f"kNN of every point, {label} points, k=16", repeats=5)
    bench.time("meshsmith", lambda: mp.knn(P, 16))
    bench.time("meshsmith KdTree build", lambda: mp.KdTree(P))
    bench.time("scipy cKDTree build+query (workers=-1)", lambda: cKDTree(P).query(P, 17, workers=-1))
    bench.report()
    _, distances = bench.output("meshsmith")
    scipy_distances = bench.output("scipy cKDTree build+query (workers=-1)")[0][:, 1:]
    bench.check("kNN distances vs scipy, max |difference|", np.abs(distances - scipy_distances).max(), 1e-12)

    m = size(100_000, 10_000)
    Q = noisy_sphere(m, seed=1)
    N = mp.estimate_normals(Q, k=15)
    bench = Benchmark("points", f"orient_normals, {m // 1000}k points, k=16", repeats=5)
    bench.time("meshsmith", lambda: mp.orient_normals(Q, N, k=16))
    if o3d is not None:
        bench.time("open3d consistent_tangent_plane", lambda: open3d_oriented(Q, N))
    bench.report()
    outward = (bench.output("meshsmith") * Q).sum(axis=1) > 0
    bench.check("share of oriented normals pointing inwards, meshsmith", 1 - outward.mean(), 1e-3)
    if o3d is not None:
        outward = (bench.output("open3d consistent_tangent_plane") * Q).sum(axis=1) > 0
        print(f"  open3d orient_normals_consistent_tangent_plane: {max(outward.mean(), 1 - outward.mean()):.2%}"
              " consistent")


if __name__ == "__main__":
    main()
