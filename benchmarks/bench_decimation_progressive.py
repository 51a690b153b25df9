"""Progressive meshes (§4.3): switching levels of detail on a 100k-face mesh, against what a
program without a progressive mesh would do (decimate again to the wanted size).

Input: datasets.torus(1, 0.4, 250, 200), 100,000 faces, built into a progressive mesh down to
the smallest mesh the decimator reaches (timed once, reported separately). The brief's figure
of merit: switching between two levels takes < 50 ms.
"""
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

from meshsmith import datasets, decimation  # noqa: E402

try:
    import fast_simplification  # the peer: today's fastest decimator
except ImportError:
    fast_simplification = None


def main():
    V, F = datasets.torus(1.0, 0.4, 250, 200)
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
                      repeats=3, reference="legality (default)")
    point = V[0]
    bench.time("legality (default)", lambda: pm.refine_where(near=point, radius=0.3))
    bench.time("whole stars", lambda: pm.refine_where(near=point, radius=0.3, whole_stars=True))
    bench.report()
    for whole_stars in (False, True):
        faces = len(pm.refine_where(near=point, radius=0.3, whole_stars=whole_stars)[1])
        print(f"  whole_stars={whole_stars}: {faces:,} faces")

    bench = Benchmark("decimation_progressive", f"get the 10% level of a {len(F):,}-face torus", repeats=3,
                      reference="pm.at(10%) from full")
    bench.time("pm.at(10%) from full", lambda: (pm.set_level(full), pm.at(len(F) // 10)))
    bench.time("meshsmith decimate again", lambda: decimation.decimate(V, F, ratio=0.1))
    if fast_simplification:
        bench.time("fast_simplification",
                   lambda: fast_simplification.simplify(V, F.astype("int32"), target_reduction=0.9))
    bench.report()


if __name__ == "__main__":
    main()
