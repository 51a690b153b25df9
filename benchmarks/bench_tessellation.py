"""Tessellation chapter benchmarks: 2D Delaunay against scipy and Shewchuk's Triangle, Delaunay
refinement against Triangle (time and Steiner point counts on the same input and angle bound).

Peers: scipy.spatial.Delaunay (Qhull), `triangle` (PyPI wrapper of Shewchuk's Triangle; absent
peers are reported as missing). Sizes: 1M points for Delaunay, a 20k-edge polygon with 200k
points for constrained Delaunay (50k and 3k + 30k in quick mode).

Result checks (tolerance 0 unless stated): the Delaunay triangles (as vertex sets) equal
Triangle's (random points are in general position, so the triangulation is unique, and both
decide with exact predicates), and differ from scipy's (Qhull, floating point) at most at a
share of 1e-5 of them; the constrained Delaunay triangles equal Triangle's; refinement meets
the angle bound (down to 1e-9 degrees; at a smaller input angle, that angle) on every domain of
the Steiner table and covers the same area as Triangle's mesh (1e-12 relative). On the small-angle
domains (issue 14's 1e-9 slivers, 1e-3 degree wedges, a star, a fan of 2.1-degree angles, a hole 1e-9
from the boundary) every triangle below the bound lies in the cluster of a small input angle (all
three vertices on its two segments); Triangle runs in a child process with a time limit, since it
does not finish on some of them.
"""
from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay as ScipyDelaunay

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, check, differing_simplices, optional, relative_difference, size  # noqa: E402

from meshsmith.tessellation import constrained_delaunay, delaunay, refine  # noqa: E402

triangle = optional("triangle")  # Shewchuk's Triangle


def total_area(V, F) -> float:
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return float(0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])).sum())


def refinement_domains() -> dict:
    """PSLGs (points, segments, hole seeds) used for the refinement comparison."""
    square_hole = (np.array([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]], float),
                   np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]),
                   np.array([[2.0, 2.0]]))
    outline = np.array([[0, 0], [5, 0], [5, 1], [1.2, 1], [1.2, 2], [4, 2], [4, 3], [1.2, 3],
                        [1.2, 4], [5, 4], [5, 5], [0, 5]], float)
    letter_e = (outline, np.array([[i, (i + 1) % 12] for i in range(12)]), None)
    wedge = (np.array([[0, 0], [10, 0], [10, 10 * np.tan(np.radians(5.0))]]),  # 5° at the origin
             np.array([[0, 1], [1, 2], [2, 0]]), None)
    return {"square with square hole": square_hole, "letter E": letter_e, "5-degree wedge": wedge}


def triangle_refine(P, segments, holes, min_angle, max_area=None):
    pslg = {"vertices": P, "segments": segments}
    if holes is not None:
        pslg["holes"] = holes
    switches = f"pq{min_angle}" + (f"a{max_area}" if max_area else "") + "Q"
    return triangle.triangulate(pslg, switches)


def smallest_angles(V, F) -> np.ndarray:
    """The smallest angle of each triangle, in degrees."""
    corners = V[F]
    angles = []
    for k in range(3):
        u = corners[:, (k + 1) % 3] - corners[:, k]
        w = corners[:, (k + 2) % 3] - corners[:, k]
        cos = (u * w).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.min(angles, axis=0)


def minimum_angle(V, F) -> float:
    return float(smallest_angles(V, F).min())


def steiner_comparison() -> None:
    """Steiner points added by meshsmith.refine and by Triangle, same input/bound."""
    print("\nDelaunay refinement: Steiner points and minimum angle (meshsmith vs Triangle)")
    print(f"{'domain':36s} {'bound':>6s} {'meshsmith pts':>14s} {'min angle':>10s} "
          f"{'Triangle pts':>13s} {'min angle':>10s}")
    for name, (P, segments, holes) in refinement_domains().items():
        for bound, max_area in ((20.7, None), (30.0, None), (33.0, None), (30.0, 0.01)):
            V, F, steiner = refine(P, segments, holes, min_angle=bound, max_area=max_area)
            ours = f"{steiner:14d} {minimum_angle(V, F):10.2f}"
            # Angles below the bound at a small input angle are left alone, as Triangle does (its
            # small-angle rule: skinny triangles between two points of one concentric shell of the
            # apex stay), so such a corner may keep a triangle slightly below the input angle; the
            # bound to meet is then Triangle's own minimum on the same input (5-degree wedge with
            # an area bound: 4.962 degrees on both sides, measured 2026-12-01).
            wanted = min(bound, 5.0 if name == "5-degree wedge" else 90.0)
            if triangle is not None:
                result = triangle_refine(P, segments, holes, bound, max_area)
                their_minimum = minimum_angle(result['vertices'], result['triangles'])
                theirs = f"{len(result['vertices']) - len(P):13d} {their_minimum:10.2f}"
                wanted, what = min(bound, their_minimum), "min(bound, Triangle's minimum angle)"
            else:
                theirs, what = "   (triangle not installed)", "min(bound, smallest input angle)"
            label = name + (f", area<={max_area}" if max_area else "")
            print(f"{label:36s} {bound:6.1f} {ours} {theirs}")
            check("tessellation", "Steiner points and minimum angle", f"{label}, bound {bound}: degrees below {what}",
                  max(0.0, wanted - minimum_angle(V, F)), 1e-9)


def small_angle_domains() -> dict:
    """PSLGs with small input angles or features (points, segments, hole seeds)."""
    def crack(degrees):
        a = np.radians(degrees)
        return (np.array([[-1, -1], [2, -1], [2, 2], [-1, 2], [0, 0], [1, 0], [np.cos(a), np.sin(a)]]),
                np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [4, 6]]), None)
    a = np.radians(1e-3)
    t = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    r = np.where(np.arange(24) % 2 == 0, 1.0, 0.3)
    fan = np.radians(np.linspace(0, 40, 20))
    issue = np.array([[0, 0], [1, 0], [1, 1e-9], [0.5, 2]], float)
    return {
        "issue 14, segments 0-1-2-3": (issue, np.array([[0, 1], [1, 2], [2, 3], [3, 0]]), None),
        "issue 14, segments 0-1-3-2 (slivers)": (issue, np.array([[0, 1], [1, 3], [3, 2], [2, 0]]), None),
        "wedge of 1e-3 degrees": (np.array([[0, 0], [1, 0], [np.cos(a), np.sin(a)]]),
                                  np.array([[0, 1], [1, 2], [2, 0]]), None),
        "crack of 1e-3 degrees in a square": crack(1e-3),
        "crack of 1 degree in a square": crack(1.0),
        "12-point star (12.5-degree tips)": (np.c_[r * np.cos(t), r * np.sin(t)],
                                             np.array([[i, (i + 1) % 24] for i in range(24)]), None),
        "fan of 20 segments, 2.1 degrees apart": (
            np.vstack([[[-2, -2], [2, -2], [2, 2], [-2, 2], [0, 0]], np.c_[np.cos(fan), np.sin(fan)]]),
            np.array([[0, 1], [1, 2], [2, 3], [3, 0]] + [[4, 5 + i] for i in range(20)]), None),
        "diamond hole 1e-9 from the boundary": (
            np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 1e-9], [0.7, 0.3], [0.5, 0.6], [0.3, 0.3]]),
            np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]]), np.array([[0.5, 0.3]])),
    }


def outside_clusters(V, F, P, segments, bound) -> int:
    """Triangles below `bound` that do not lie in the cluster of a small input angle (three
    vertices on the two segments of two input segments meeting at less than 60 degrees)."""
    def on(x, a, b):
        d, e = b - a, x - a
        return abs(d[0] * e[1] - d[1] * e[0]) <= 1e-12 * (d @ d) and -1e-12 <= d @ e <= (d @ d) * (1 + 1e-12)
    clusters = []
    for v in range(len(P)):
        ends = [int(t) for s in segments.tolist() for t in s if v in s and t != v]
        clusters += [(P[v], P[i], P[j]) for k, i in enumerate(ends) for j in ends[k + 1:]
                     if (P[i] - P[v]) @ (P[j] - P[v]) > 0.5 * np.linalg.norm(P[i] - P[v]) * np.linalg.norm(P[j] - P[v])]
    smallest = smallest_angles(V, F)
    return sum(not any(all(on(x, a, e0) or on(x, a, e1) for x in V[F[f]]) for a, e0, e1 in clusters)
               for f in np.flatnonzero(smallest < bound - 1e-9))


def triangle_in_child(P, segments, holes, bound, limit):
    """Triangle's Steiner count and time on the domain, or None when it does not finish in `limit` s."""
    code = ("import sys, time, numpy as np, triangle\n"
            "P, S, H = (np.array(x) if x is not None else None for x in eval(sys.stdin.read()))\n"
            "pslg = {'vertices': P, 'segments': S}\n"
            "if H is not None: pslg['holes'] = H\n"
            f"start = time.perf_counter(); r = triangle.triangulate(pslg, 'pq{bound}Q')\n"
            "print(len(r['vertices']) - len(P), time.perf_counter() - start)\n")
    payload = repr((P.tolist(), segments.tolist(), None if holes is None else holes.tolist()))
    try:
        done = subprocess.run([sys.executable, "-c", code], input=payload, capture_output=True, text=True, timeout=limit)
    except subprocess.TimeoutExpired:
        return None
    points, seconds = done.stdout.split()
    return int(points), float(seconds)


def small_angle_comparison() -> None:
    """Refinement near small input angles: meshsmith terminates with the bound met outside the
    clusters; Triangle, in a child process, where it finishes."""
    limit = size(20.0, 5.0)
    print("\nDelaunay refinement near small input angles (Triangle: own process, "
          f"{limit:g} s limit; both single runs)")
    print(f"{'domain':40s} {'bound':>5s} {'meshsmith pts':>13s} {'ms':>7s} {'below bound':>11s} "
          f"{'Triangle pts':>12s} {'ms':>7s}")
    for name, (P, segments, holes) in small_angle_domains().items():
        for bound in (25.0, 30.0):
            start = time.perf_counter()
            V, F, steiner = refine(P, segments, holes, min_angle=bound)
            ours = time.perf_counter() - start
            theirs = "(triangle not installed)" if triangle is None else None
            if triangle is not None:
                result = triangle_in_child(P, segments, holes, bound, limit)
                theirs = (f"{result[0]:12d} {1000 * result[1]:7.1f}" if result is not None
                          else f"{'no result in ' + format(limit, 'g') + ' s':>20s}")
            below = int(np.sum(smallest_angles(V, F) < bound - 1e-9))
            print(f"{name:40s} {bound:5.1f} {steiner:13d} {1000 * ours:7.1f} {below:11d} {theirs}")
            check("tessellation", "refinement near small input angles",
                  f"{name}, bound {bound}: triangles below the bound outside small-angle clusters",
                  outside_clusters(V, F, P, segments, bound), 0)


def main() -> None:
    rng = np.random.default_rng(0)
    n = size(1_000_000, 50_000)
    P = rng.random((n, 2))
    bench = Benchmark("tessellation", f"2D Delaunay, {n:,} uniform random points", repeats=5)
    bench.time("meshsmith", lambda: delaunay(P))
    bench.time("scipy.spatial.Delaunay", lambda: ScipyDelaunay(P))
    if triangle is not None:
        bench.time("triangle", lambda: triangle.triangulate({"vertices": P}, "Q"))
    bench.report()
    F = bench.output("meshsmith")[0]
    # Qhull decides in floating point, so it may flip a nearly cocircular pair (4 of 2M triangles at
    # 1M points, measured); Triangle and meshsmith use exact predicates and must agree exactly.
    bench.check("share of Delaunay triangles differing from scipy's (Qhull, inexact)",
                differing_simplices(F, bench.output("scipy.spatial.Delaunay").simplices) / len(F), 1e-5)
    if triangle is not None:
        bench.check("Delaunay triangles differing from Triangle's",
                    differing_simplices(F, bench.output("triangle")["triangles"]), 0)

    # Constrained Delaunay: a polygon with many edges (a wavy circle) plus interior points.
    k, m = size(20_000, 3_000), size(200_000, 30_000)
    # Jittered angles: the evenly spaced samples of this symmetric curve hold cocircular quadruples,
    # whose two triangulations are both Delaunay, and the check compares triangles one to one.
    angles = (np.arange(k) + rng.uniform(-0.25, 0.25, k)) * (2 * np.pi / k)
    radius = 1 + 0.1 * np.sin(17 * angles)
    boundary = np.column_stack([radius * np.cos(angles), radius * np.sin(angles)])
    interior = rng.uniform(-0.8, 0.8, size=(m, 2)) * 0.85
    points = np.vstack([boundary, interior])
    segments = np.column_stack([np.arange(k), (np.arange(k) + 1) % k])
    bench = Benchmark("tessellation", f"constrained Delaunay, {k // 1000}k-edge polygon + {m // 1000}k points",
                      repeats=5)
    bench.time("meshsmith", lambda: constrained_delaunay(points, segments))
    if triangle is not None:
        bench.time("triangle", lambda: triangle.triangulate({"vertices": points, "segments": segments}, "pQ"))
    bench.report()
    if triangle is not None:
        bench.check("constrained Delaunay triangles differing from Triangle's",
                    differing_simplices(bench.output("meshsmith")[1], bench.output("triangle")["triangles"]), 0)

    P_e, segments_e, _ = refinement_domains()["letter E"]
    max_area = size(1e-4, 1e-3)
    bench = Benchmark("tessellation", f"refine letter E, min angle 30, max area {max_area:g}", repeats=5)
    bench.time("meshsmith", lambda: refine(P_e, segments_e, min_angle=30.0, max_area=max_area))
    if triangle is not None:
        bench.time("triangle", lambda: triangle_refine(P_e, segments_e, None, 30.0, max_area))
    bench.report()
    V, F, _ = bench.output("meshsmith")
    bench.check("refinement: degrees below the 30-degree bound", max(0.0, 30.0 - minimum_angle(V, F)), 1e-9)
    if triangle is not None:
        theirs = bench.output("triangle")
        bench.check("refinement: area vs Triangle's mesh, relative",
                    relative_difference(total_area(V, F), total_area(theirs["vertices"], theirs["triangles"])), 1e-12)

    steiner_comparison()
    small_angle_comparison()


if __name__ == "__main__":
    main()
