"""Side-by-side timing for benchmarks/bench_<chapter>.py: medians, ratios, result checks, a table, JSON.

Usage in a bench file::

    from harness import Benchmark, size
    n = size(1_000_000, 20_000)              # the full input, or the --quick one
    bench = Benchmark("io", f"read {n:,}-face binary PLY")
    bench.time("meshsmith", lambda: meshsmith.io.read_mesh(path))
    bench.time("trimesh", lambda: trimesh.load(path, process=False))
    bench.report()            # runs the timings, prints the table, ratios relative to meshsmith
    V, F = bench.output("meshsmith")           # what the last timed run returned
    bench.check("vertices differing from trimesh's", differing(V, bench.output("trimesh").vertices), 0)

Timings: one warm-up of each implementation, then `repeats` rounds that run the implementations
in turn (alternating, so a change of machine load hits every side alike); the median of each is
kept (quick mode: five rounds, the fewest a README ratio may come from — issue 14's rule). The machine is small and noisy, so ratios are what to quote,
and timings never fail a run.

What does fail a run (`run_all.py` exits non-zero): a timed implementation that raises, a chapter
whose benchmark crashes, and a result check whose value exceeds its stated tolerance. Every bench
file checks meshsmith's result against its peer's on the timed input (`Benchmark.check`, or
`check` outside a case), with the tolerance written next to the check.

A row timed with `same_work=False` is a peer that does different work (a floor, such as the
unweighted Voronoi diagram under a power diagram, or a different algorithm shown for scale): its
ratio is printed in parentheses and is not a like-for-like figure.

Quick mode (`--quick` on the command line, or MESHSMITH_BENCH_QUICK=1): every bench file takes its
input sizes from `size(full, quick)`, so one switch shrinks every chapter (`make bench-quick`).
Full runs store each case in benchmarks/results/<chapter>.json; run_all.py writes the whole run
(cases, checks, failures, machine) to results/quick.json or results/full.json.
"""
from __future__ import annotations

import importlib
import json
import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path

RESULTS_DIR = Path(__file__).resolve().parent / "results"

QUICK = "--quick" in sys.argv[1:] or os.environ.get("MESHSMITH_BENCH_QUICK") == "1"

# Everything this process measured and checked, for run_all.py's summary and JSON.
CASES: list[dict] = []
CHECKS: list[dict] = []
FAILURES: list[str] = []
MISSING_PEERS: list[str] = []

# Environment variables that set the thread counts of meshsmith's peers (and their BLAS).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "IGL_NUM_THREADS", "OPENBLAS_NUM_THREADS")


#: Rounds per implementation in quick mode (medians of at least five alternating runs).
QUICK_ROUNDS = 5


def set_quick(quick: bool) -> None:
    global QUICK
    QUICK = quick


def reset() -> None:
    """Forget what this process measured and checked (run_all.py starts each run with it)."""
    for record in (CASES, CHECKS, FAILURES, MISSING_PEERS):
        record.clear()


def size(full, quick):
    """The input size (or any parameter) of this run: `quick` in quick mode, else `full`."""
    return quick if QUICK else full


def optional(module_name: str):
    """Import a peer library, or return None and remember that it is missing."""
    try:
        return importlib.import_module(module_name)
    except Exception as error:  # ImportError, or an OSError from a missing shared library (open3d)
        note = f"{module_name} ({type(error).__name__}: {error})"[:160]
        if note not in MISSING_PEERS:
            MISSING_PEERS.append(note)
            print(f"peer not available: {note}")
        return None


def shared_data_dir() -> Path | None:
    """The shared real meshes (../shared/data or $MESHSMITH_DATA), found as the tests find them."""
    tests = str(Path(__file__).resolve().parents[1] / "tests")
    if tests not in sys.path:
        sys.path.insert(0, tests)
    from conftest import shared_data_dir as find
    return find()


def load_average() -> str:
    try:
        return " ".join(f"{value:.2f}" for value in os.getloadavg())
    except OSError:
        return "unknown"


def machine_description() -> str:
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"


def threads_description() -> str:
    """The thread settings the peers see: every variable that sets one, 'unset' = all cores."""
    settings = ", ".join(f"{name}={os.environ.get(name, 'unset')}" for name in THREAD_VARIABLES)
    return (f"threads: {settings} (unset: all {os.cpu_count()} cores). meshsmith: TBB, all cores; "
            "Open3D: OpenMP (OMP_NUM_THREADS); libigl: its parallel_for (IGL_NUM_THREADS); scipy: cKDTree "
            "queries with workers=-1 (all cores) where the row says so, SuperLU and Qhull on one; "
            "fast-simplification, trimesh, meshio, triangle, pymeshlab's decimation: one thread")


def run_header() -> str:
    return (f"{time.strftime('%Y-%m-%d %H:%M:%S %Z')}; {machine_description()}; "
            f"load average {load_average()} (1, 5, 15 min)")


def check(chapter: str, case: str, quantity: str, value, tolerance) -> bool:
    """Record a result check: passes when value <= tolerance (NaN fails). Prints one line."""
    value = float(value)
    passed = not math.isnan(value) and value <= tolerance
    CHECKS.append({"chapter": chapter, "case": case, "quantity": quantity, "value": value,
                   "tolerance": tolerance, "passed": passed})
    print(f"  check {'ok  ' if passed else 'FAIL'} {quantity}: {value:.3g} (tolerance {tolerance:.3g})")
    return passed


def relative_difference(a, b) -> float:
    """max |a - b| / max |b| over all entries (0 when both are zero): for arrays of like shape."""
    import numpy as np
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape:
        return math.inf
    scale = np.abs(b).max() if b.size else 0.0
    difference = np.abs(a - b).max() if a.size else 0.0
    return float(difference / scale) if scale > 0 else float(difference)


def differing_simplices(A, B) -> int:
    """Size of the symmetric difference of two lists of simplices (edges, triangles, tetrahedra),
    each taken as a set of vertex indices: 0 when both hold the same simplices in any order."""
    import numpy as np
    as_set = lambda T: set(map(tuple, np.sort(np.asarray(T), axis=1).tolist()))  # noqa: E731
    return len(as_set(A) ^ as_set(B))


class Benchmark:
    """One benchmark case: several implementations of the same task on the same input."""

    def __init__(self, chapter: str, case: str, repeats: int = 5, reference: str = "meshsmith"):
        self.chapter, self.case, self.repeats, self.reference = chapter, case, repeats, reference
        self.medians: dict[str, float] = {}
        self.failures: dict[str, str] = {}
        self.different_work: set[str] = set()
        self.outputs: dict[str, object] = {}
        self.rounds = 0
        self._pending: list[tuple[str, object, int]] = []

    def time(self, name: str, run, repeats: int | None = None, *, same_work: bool = True) -> None:
        """Add an implementation: `run()` is timed when report() runs the case (warm-up + repeats).

        same_work=False marks a peer that does different work than the reference (see the module
        docstring); its ratio is shown in parentheses.
        """
        if QUICK:  # small inputs: five alternating rounds each, so a quick table's ratios are quotable
            repeats = QUICK_ROUNDS
        self._pending.append((name, run, repeats or self.repeats))
        if not same_work:
            self.different_work.add(name)

    def check(self, quantity: str, value, tolerance) -> bool:
        """A result check of this case (see the module function `check`)."""
        return check(self.chapter, self.case, quantity, value, tolerance)

    def output(self, name: str):
        """What `name`'s run returned in its last timed round (after report()), for the checks."""
        return self.outputs[name]

    def _run(self, name: str, run) -> float | None:
        try:
            start = time.perf_counter()
            self.outputs[name] = run()
            return time.perf_counter() - start
        except Exception as error:  # reported, and the run as a whole fails
            self.failures[name] = f"{type(error).__name__}: {error}"[:160]
            FAILURES.append(f"{self.chapter}: {self.case}: {name} raised {self.failures[name]}")
            return None

    def _measure(self) -> None:
        """Warm up each implementation once, then time them in alternating rounds."""
        pending = [(name, run, repeats) for name, run, repeats in self._pending
                   if self._run(name, run) is not None]
        samples: dict[str, list[float]] = {name: [] for name, _, _ in pending}
        self.rounds = max((repeats for _, _, repeats in pending), default=0)
        for round_index in range(self.rounds):
            for name, run, repeats in pending:
                if round_index < repeats and name not in self.failures:
                    elapsed = self._run(name, run)
                    if elapsed is not None:
                        samples[name].append(elapsed)
        for name, values in samples.items():
            if values and name not in self.failures:
                self.medians[name] = statistics.median(values)
        self._pending = []

    def rows(self) -> list[dict]:
        base = self.medians.get(self.reference)
        rows = []
        for name, median in sorted(self.medians.items(), key=lambda item: item[1]):
            rows.append({"implementation": name, "median_s": median,
                         "ratio_to_" + self.reference: (median / base) if base else None,
                         "same_work": name not in self.different_work})
        for name, failure in self.failures.items():
            rows.append({"implementation": name, "median_s": None, "failed": failure})
        return rows

    def report(self) -> list[dict]:
        """Time every implementation, print the table; store it (results/<chapter>.json if full)."""
        self._measure()
        rows = self.rows()
        print(f"\n## {self.chapter}: {self.case}  ({machine_description()}, median of {self.rounds}, "
              f"load average {load_average()})")
        print(f"{'implementation':<44} {'median [s]':>12} {'x ' + self.reference:>16}")
        for row in rows:
            if row.get("median_s") is None:
                print(f"{row['implementation']:<44} {'failed':>12}  {row['failed']}")
                continue
            ratio = row["ratio_to_" + self.reference]
            shown = "-" if ratio is None else (f"{ratio:.2f}" if row["same_work"] else f"({ratio:.2f})")
            print(f"{row['implementation']:<44} {row['median_s']:>12.4f} {shown:>16}")
        entry = {"chapter": self.chapter, "case": self.case, "reference": self.reference,
                 "repeats": self.rounds, "rows": rows, "load_average": load_average(),
                 "when": time.strftime("%Y-%m-%d %H:%M:%S")}
        CASES.append(entry)
        if not QUICK:
            RESULTS_DIR.mkdir(exist_ok=True)
            path = RESULTS_DIR / f"{self.chapter}.json"
            stored = json.loads(path.read_text()) if path.exists() else {}
            stored[self.case] = {"machine": machine_description(), **entry}
            path.write_text(json.dumps(stored, indent=2))
        return rows


def _milliseconds(seconds: float) -> str:
    return f"{seconds * 1e3:.3g}" if seconds < 1 else f"{seconds * 1e3:,.0f}"


def markdown_table(cases: list[dict]) -> str:
    """One row per (case, implementation other than the reference): medians and ratios."""
    lines = ["| chapter | case | meshsmith [ms] | peer or variant | its time [ms] | ratio (its time ÷ meshsmith's) |",
             "|---|---|---:|---|---:|---:|"]
    for case in cases:
        rows = {row["implementation"]: row for row in case["rows"]}
        base = rows.get(case["reference"], {}).get("median_s")
        base_text = _milliseconds(base) if base else "failed"
        label = case["case"] if case["reference"] == "meshsmith" else f"{case['case']} (reference: {case['reference']})"
        others = [row for name, row in rows.items() if name != case["reference"]]
        if not others:
            lines.append(f"| {case['chapter']} | {label} | {base_text} | — | | |")
        for row in others:
            if row.get("median_s") is None:
                lines.append(f"| {case['chapter']} | {label} | {base_text} | {row['implementation']} | failed | |")
                continue
            ratio = row["median_s"] / base if base else None
            shown = "" if ratio is None else (f"{ratio:.2f}" if row["same_work"] else f"({ratio:.2f})")
            lines.append(f"| {case['chapter']} | {label} | {base_text} | {row['implementation']} | "
                         f"{_milliseconds(row['median_s'])} | {shown} |")
    return "\n".join(lines)
