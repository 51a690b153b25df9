"""ABF++ and plain ABF (§5.1.3): time, Newton iterations and final residual.

Inputs: a ~100k-face hemisphere cap (datasets.disk(180, 560) wrapped onto the unit sphere, polar
angle up to 0.45 π: curved, so the optimization has work to do) for ABF++, with this chapter's and
libigl's LSCM on the same mesh for scale (no Python package offers ABF/ABF++ to compare against); a ~5k-face cap
and, when ../shared/data is present, hand_lowres (1.6k faces) and camelhead (22.7k faces) for
ABF++ against plain ABF (the full KKT system by sparse LU: same iterates, far slower, so it is
run only on the meshes of at most 10k faces).
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from harness import Benchmark  # noqa: E402

from meshsmith import datasets, io, parametrization  # noqa: E402


def hemisphere_cap(n_rings, n_segments, opening=0.45 * np.pi):
    V, F = datasets.disk(n_rings, n_segments)
    r = np.linalg.norm(V[:, :2], axis=1)
    phi = np.arctan2(V[:, 1], V[:, 0])
    theta = r * opening
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], 1), F


def shared_mesh(name):
    from conftest import shared_data_dir
    directory = shared_data_dir()
    if directory is None:
        return None
    V, F = io.read_mesh(directory / name)
    return np.asarray(V), np.asarray(F)


def convergence_note(V, F, method):
    result = parametrization.abf(V, F, method)
    a = result.uv[F]
    e1, e2 = a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]
    areas = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    return (f"{method}: {result.iterations} Newton iterations, residual {result.residual:.1e} (inf-norm), "
            f"{int((areas <= 0).sum())} flipped triangles")


def main():
    igl = None
    try:
        import igl
    except ImportError:
        pass

    V, F = hemisphere_cap(180, 560)
    case = f"ABF++ on a hemisphere cap, {len(V):,} V, {len(F):,} F"
    print(f"\n{case}: {convergence_note(V, F, 'abf++')}")
    bench = Benchmark("parametrization_abf", case, repeats=3)
    bench.time("meshsmith abf++", lambda: parametrization.abf(V, F, method="abf++"))
    bench.time("meshsmith lscm (for scale)", lambda: parametrization.lscm(V, F))
    if igl:
        boundary = igl.boundary_loop(F)
        pins = np.array([boundary[0], boundary[len(boundary) // 2]])
        bench.time("libigl lscm (for scale)", lambda: igl.lscm(V, F, pins, np.array([[0.0, 0.0], [1.0, 0.0]])))
    bench.reference = "meshsmith abf++"
    bench.report()

    inputs = [("hemisphere cap", hemisphere_cap(40, 128))]
    for name in ("hand_lowres.obj", "camelhead.off"):
        mesh = shared_mesh(name)
        if mesh is not None:
            inputs.append((name, mesh))
    for label, (V, F) in inputs:
        case = f"ABF++ vs ABF, {label}, {len(V):,} V, {len(F):,} F"
        print(f"\n{case}: {convergence_note(V, F, 'abf++')}")
        bench = Benchmark("parametrization_abf", case, repeats=3)
        bench.time("meshsmith abf++", lambda: parametrization.abf(V, F, method="abf++"))
        if len(F) <= 10_000:   # camelhead: ~50 s per ABF run here (measured once), too long to repeat
            bench.time("meshsmith abf (full KKT, LU)", lambda: parametrization.abf(V, F, method="abf"))
        bench.reference = "meshsmith abf++"
        bench.report()


if __name__ == "__main__":
    main()
