"""Progressive meshes (§4.3): switching levels of detail on a 100k-face mesh, against what a
program without a progressive mesh would do (decimate again to the wanted size).

Input: datasets.torus(1, 0.4, 250, 200), 100,000 faces (torus(1, 0.4, 200, 100), 40,000 faces,
in quick mode), built into a progressive mesh down to the smallest mesh the decimator reaches
(timed once, reported separately). The brief's figure of merit: switching between two levels
takes < 50 ms. Decimating again: meshsmith and fast-simplification get the same int32 faces,
made outside the timing.

Result checks (tolerances): the full level gives back the input's faces (0 differing triangles,
as sets of positions), the 10% level and decimate() hold the target face count within 2, and the
10% level's relative Hausdorff error is at most 1.5 times fast-simplification's.
"""
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, optional, size  # noqa: E402
from bench_decimation import relative_hausdorff  # noqa: E402

from meshsmith import datasets, decimation  # noqa: E402

fast_simplification = optional("fast_simplification")  # the peer: today's fastest decimator


def triangles_as_positions(V, F) -> set:
    """Each triangle as the set of its corners' coordinates (independent of vertex numbering)."""
    corners = np.asarray(V)[np.asarray(F)]
    return {frozenset(map(tuple, triangle.tolist())) for triangle in corners}


def main():
    V, F = datasets.torus(1.0, 0.4, size(250, 200), size(200, 100))
    F32 = np.ascontiguousarray(F, dtype=np.int32)
    start = time.perf_counter()
    pm = decimation.progressive_mesh(V, F)
    build = time.perf_counter() - start
    print(f"\nprogressive mesh of {len(F):,} faces: {pm.n_splits:,} vertex splits, faces "
          f"{pm.face_range[0]}..{pm.face_range[1]:,}, built in {build:.2f} s")
    full = pm.n_splits
    ten_percent = pm.level_for_face_count(len(F) // 10)
    one_percent = pm.level_for_face_count(len(F) // 100)

    bench = Benchmark("decimation_progressive", f"switch levels, {len(F):,}-face torus: two switches per run",
                      repeats=7, reference="set_level 100%<->10%")
    bench.time("set_level 100%<->10%", lambda: (pm.set_level(ten_percent), pm.set_level(full)))
    bench.time("set_level 100%<->1%", lambda: (pm.set_level(one_percent), pm.set_level(full)))
    bench.time("set_level 10%<->1%", lambda: (pm.set_level(one_percent), pm.set_level(ten_percent)))
    bench.time("at(10%)<->at(100%), (V, F) out",
               lambda: (pm.at(len(F) // 10), pm.at(len(F))))
    bench.report()

    bench = Benchmark("decimation_progressive", f"selective refinement within 0.3 of a point, {len(F):,}-face torus",
                      repeats=5, reference="legality (default)")
    point = V[0]
    bench.time("legality (default)", lambda: pm.refine_where(near=point, radius=0.3))
    bench.time("whole stars", lambda: pm.refine_where(near=point, radius=0.3, whole_stars=True))
    bench.report()
    for whole_stars in (False, True):
        faces = len(pm.refine_where(near=point, radius=0.3, whole_stars=whole_stars)[1])
        print(f"  whole_stars={whole_stars}: {faces:,} faces")

    bench = Benchmark("decimation_progressive", f"get the 10% level of a {len(F):,}-face torus", repeats=5,
                      reference="pm.at(10%) from full")
    bench.time("pm.at(10%) from full", lambda: (pm.set_level(full), pm.at(len(F) // 10)))
    # The progressive mesh was built beforehand; decimating again starts from the input alone.
    bench.time("meshsmith decimate again", lambda: decimation.decimate(V, F32, ratio=0.1), same_work=False)
    if fast_simplification:
        bench.time("fast_simplification", lambda: fast_simplification.simplify(V, F32, target_reduction=0.9),
                   same_work=False)
    bench.report()

    bench = Benchmark("decimation_progressive", f"decimate the {len(F):,}-face torus to 10%", repeats=5)
    bench.time("meshsmith", lambda: decimation.decimate(V, F32, ratio=0.1))
    if fast_simplification:
        bench.time("fast_simplification", lambda: fast_simplification.simplify(V, F32, target_reduction=0.9))
    bench.report()

    pm.set_level(full)
    V_full, F_full = pm.at(len(F))
    bench.check("full level: triangles differing from the input's (as corner positions)",
                len(triangles_as_positions(V, F) ^ triangles_as_positions(V_full, F_full)), 0)
    V10, F10 = pm.at(len(F) // 10)
    bench.check("10% level: |faces - target|", abs(len(F10) - len(F) // 10), 2)
    bench.check("decimate(ratio=0.1): |faces - target|", abs(len(decimation.decimate(V, F32, ratio=0.1)[1]) - len(F) // 10), 2)
    if fast_simplification:
        V_fs, F_fs = fast_simplification.simplify(V, F32, target_reduction=0.9)
        ours, theirs = relative_hausdorff(V, F, V10, F10), relative_hausdorff(V, F, V_fs, F_fs)
        bench.check(f"10% level's relative Hausdorff error ({ours:.2e}) / fast-simplification's ({theirs:.2e})",
                    ours / theirs, 1.5)


if __name__ == "__main__":
    main()
