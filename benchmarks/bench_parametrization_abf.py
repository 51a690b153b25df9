"""ABF++ and plain ABF (§5.1.3): time, Newton iterations and final residual.

Inputs: a ~100k-face hemisphere cap (datasets.disk(180, 560) wrapped onto the unit sphere, polar
angle up to 0.45 π: curved, so the optimization has work to do) for ABF++, with this chapter's and
libigl's LSCM on the same mesh for scale (no Python package offers ABF/ABF++ to compare against); a ~5k-face cap
and, when ../shared/data is present, hand_lowres (1.6k faces) and camelhead (22.7k faces) for
ABF++ against plain ABF (the full KKT system by sparse LU: same iterates, far slower, so it is
run only on the meshes of at most 10k faces). Quick mode: a ~9k-face cap, then a ~1.3k-face cap
and hand_lowres.

Same work: meshsmith's and libigl's LSCM get the same two pins (meshsmith's default pins),
computed outside the timing.

Result checks (tolerances): ABF++ converges (residual at most 1e-8, its stopping tolerance) with
no flipped triangle; plain ABF reaches the same angles as ABF++ (max |difference| 1e-6 radians);
the two LSCM maps agree within 1e-8 of the map's extent.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, optional, relative_difference, shared_data_dir, size  # noqa: E402

from meshsmith import datasets, io, parametrization  # noqa: E402


def hemisphere_cap(n_rings, n_segments, opening=0.45 * np.pi):
    V, F = datasets.disk(n_rings, n_segments)
    r = np.linalg.norm(V[:, :2], axis=1)
    phi = np.arctan2(V[:, 1], V[:, 0])
    theta = r * opening
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], 1), F


def shared_mesh(name):
    directory = shared_data_dir()
    if directory is None:
        return None
    V, F = io.read_mesh(directory / name)
    return np.asarray(V), np.asarray(F)


def flipped_triangles(uv, F) -> int:
    a = uv[F]
    e1, e2 = a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]
    return int((e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] <= 0).sum())


def convergence_note(result, F, method):
    return (f"{method}: {result.iterations} Newton iterations, residual {result.residual:.1e} (inf-norm), "
            f"{flipped_triangles(result.uv, F)} flipped triangles")


def check_abf(bench, result, F) -> None:
    bench.check("ABF++ residual (inf-norm)", result.residual, 1e-8)
    bench.check("ABF++ flipped triangles", flipped_triangles(result.uv, F), 0)


def main():
    igl = optional("igl")

    V, F = hemisphere_cap(size(180, 55), size(560, 170))
    case = f"ABF++ on a hemisphere cap, {len(V):,} V, {len(F):,} F"
    result = parametrization.abf(V, F, method="abf++")
    print(f"\n{case}: {convergence_note(result, F, 'abf++')}")
    pins, pins_uv = parametrization.default_lscm_pins(V, F)
    bench = Benchmark("parametrization_abf", case, repeats=5, reference="meshsmith abf++")
    bench.time("meshsmith abf++", lambda: parametrization.abf(V, F, method="abf++"))
    bench.time("meshsmith lscm (for scale)", lambda: parametrization.lscm(V, F, pins, pins_uv), same_work=False)
    bench.report()
    check_abf(bench, result, F)
    if igl:
        bench = Benchmark("parametrization_abf", f"LSCM on the same cap, {len(F):,} F", repeats=5)
        bench.time("meshsmith", lambda: parametrization.lscm(V, F, pins, pins_uv))
        bench.time("libigl lscm", lambda: igl.lscm(V, F, pins, pins_uv))
        bench.report()
        bench.check("LSCM map vs libigl's, max |difference| / extent",
                    relative_difference(parametrization.lscm(V, F, pins, pins_uv), igl.lscm(V, F, pins, pins_uv)[0]),
                    1e-8)

    inputs = [("hemisphere cap", hemisphere_cap(size(40, 20), size(128, 64)))]
    for name in size(("hand_lowres.obj", "camelhead.off"), ("hand_lowres.obj",)):
        mesh = shared_mesh(name)
        if mesh is not None:
            inputs.append((name, mesh))
    for label, (V, F) in inputs:
        case = f"ABF++ vs ABF, {label}, {len(V):,} V, {len(F):,} F"
        result = parametrization.abf(V, F, method="abf++")
        print(f"\n{case}: {convergence_note(result, F, 'abf++')}")
        bench = Benchmark("parametrization_abf", case, repeats=5, reference="meshsmith abf++")
        bench.time("meshsmith abf++", lambda: parametrization.abf(V, F, method="abf++"))
        if len(F) <= 10_000:   # camelhead: ~50 s per ABF run here (measured once), too long to repeat
            bench.time("meshsmith abf (full KKT, LU)", lambda: parametrization.abf(V, F, method="abf"))
        bench.report()
        check_abf(bench, result, F)
        if len(F) <= 10_000:
            bench.check("ABF vs ABF++ angles, max |difference| [rad]",
                        np.abs(parametrization.abf(V, F, method="abf").angles - result.angles).max(), 1e-6)


if __name__ == "__main__":
    main()
