"""Parametrization benchmarks (§5.1.1–2): harmonic (cotan, circle boundary) and LSCM (two pins)
against libigl on the same ~100k-face disk, plus Tutte, mean-value, stretch-minimizing,
spectral LSCM, cut_to_disk and is_bijective for scale.

Input: a procedural disk (meshsmith.datasets.disk, 126 rings, 792 outer segments: ~100k well-shaped
faces) lifted
into a bumpy height field z = 0.2 sin(3x) cos(2y), so the maps are not trivial.

meshsmith's harmonic and LSCM solves use both cores (the two halves of the nested-dissection
order are factorized side by side, cpp/src/parametrization/split_cholesky.h); libigl's run on one.
Their ratio therefore depends on the second core being free: the load average is printed first,
run the benchmark on an otherwise idle machine.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

import igl
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

from meshsmith import datasets  # noqa: E402
from meshsmith import parametrization as P  # noqa: E402


def bumpy_disk(n_rings: int, n_segments: int):
    V, F = datasets.disk(n_rings=n_rings, n_segments=n_segments)
    V = V.copy()
    V[:, 2] = 0.2 * np.sin(3 * V[:, 0]) * np.cos(2 * V[:, 1])
    return V, F


def main() -> None:
    V, F = bumpy_disk(126, 792)
    F64 = F.astype(np.int64)
    print(f"disk: {len(V)} vertices, {len(F)} faces; load average {os.getloadavg()[0]:.2f}")

    bnd = igl.boundary_loop(F64)
    bc = np.ascontiguousarray(igl.map_vertices_to_circle(np.asfortranarray(V), bnd.astype(np.int32)))
    difference = np.abs(P.harmonic(V, F, weights="cotan") - igl.harmonic(V, F64, bnd, bc, 1)).max()
    print(f"harmonic: max |meshsmith - igl| = {difference:.2e}")
    bench = Benchmark("parametrization", f"harmonic (cotan, circle boundary), {len(F)} faces", repeats=5,
                      reference="meshsmith harmonic")
    bench.time("meshsmith harmonic", lambda: P.harmonic(V, F, weights="cotan"))
    bench.time("igl.boundary_loop + map_vertices_to_circle + harmonic",
               lambda: igl.harmonic(V, F64, igl.boundary_loop(F64),
                                    np.ascontiguousarray(igl.map_vertices_to_circle(
                                        np.asfortranarray(V), igl.boundary_loop(F64).astype(np.int32))), 1))
    bench.time("igl.harmonic alone (boundary precomputed)", lambda: igl.harmonic(V, F64, bnd, bc, 1))
    bench.time("meshsmith Tutte (uniform)", lambda: P.harmonic(V, F, weights="uniform"))
    bench.time("meshsmith mean-value (sparse LU)", lambda: P.harmonic(V, F, weights="mean_value"))
    bench.report()

    pins, pins_uv = P.default_lscm_pins(V, F)
    difference = np.abs(P.lscm(V, F, pins, pins_uv) - igl.lscm(V, F64, pins, pins_uv)[0]).max()
    print(f"lscm: max |meshsmith - igl| = {difference:.2e}")
    bench = Benchmark("parametrization", f"LSCM (two pins), {len(F)} faces", repeats=3, reference="meshsmith lscm")
    bench.time("meshsmith lscm", lambda: P.lscm(V, F, pins, pins_uv))
    bench.time("igl.lscm", lambda: igl.lscm(V, F64, pins, pins_uv))
    bench.time("meshsmith lscm_spectral", lambda: P.lscm_spectral(V, F), repeats=1)
    bench.report()

    result = P.stretch_minimizing(V, F, iterations=5)
    print("stretch_minimizing: stretch per iteration", np.array2string(result.stretch, precision=4))
    bench = Benchmark("parametrization", f"other maps and tools, {len(F)} faces", repeats=1,
                      reference="meshsmith cut_to_disk (torus)")
    bench.time("meshsmith stretch_minimizing (5 iterations, mean-value)", lambda: P.stretch_minimizing(V, F, iterations=5))
    UV = P.harmonic(V, F)
    bench.time("meshsmith is_bijective", lambda: P.is_bijective(UV, F))
    VT, FT = datasets.torus(n_major=256, n_minor=128)
    print(f"torus for cut_to_disk: {len(FT)} faces")
    bench.time("meshsmith cut_to_disk (torus)", lambda: P.cut_to_disk(VT, FT))
    bench.time("igl.cut_to_disk (torus, cut graph only)", lambda: igl.cut_to_disk(FT.astype(np.int64)))
    bench.report()


if __name__ == "__main__":
    main()
