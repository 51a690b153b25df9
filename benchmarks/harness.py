"""Side-by-side timing for benchmarks/bench_<chapter>.py: medians, ratios, a table, JSON.

Usage in a bench file::

    from harness import Benchmark
    bench = Benchmark("io", "read 1M-face binary PLY")
    bench.time("meshsmith", lambda: meshsmith.io.read_mesh(path))
    bench.time("trimesh", lambda: trimesh.load(path, process=False))
    bench.report()            # prints the table, ratios relative to meshsmith

Timings are medians over `repeats` runs after one warm-up; the machine is small and noisy, so
ratios are what to quote. Results accumulate in benchmarks/results/<chapter>.json.
"""
from __future__ import annotations

import json
import os
import platform
import statistics
import time
from pathlib import Path

RESULTS_DIR = Path(__file__).resolve().parent / "results"


def machine_description() -> str:
    return f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"


class Benchmark:
    """One benchmark case: several implementations of the same task on the same input."""

    def __init__(self, chapter: str, case: str, repeats: int = 5, reference: str = "meshsmith"):
        self.chapter, self.case, self.repeats, self.reference = chapter, case, repeats, reference
        self.medians: dict[str, float] = {}
        self.failures: dict[str, str] = {}

    def time(self, name: str, run, repeats: int | None = None) -> float | None:
        """Run `run()` once to warm up, then `repeats` times; record and return the median (s)."""
        try:
            run()
            samples = []
            for _ in range(repeats or self.repeats):
                start = time.perf_counter()
                run()
                samples.append(time.perf_counter() - start)
        except Exception as error:  # a peer that fails on this input is reported, not fatal
            self.failures[name] = f"{type(error).__name__}: {error}"[:120]
            return None
        self.medians[name] = statistics.median(samples)
        return self.medians[name]

    def rows(self) -> list[dict]:
        base = self.medians.get(self.reference)
        rows = []
        for name, median in sorted(self.medians.items(), key=lambda item: item[1]):
            rows.append({"implementation": name, "median_s": median,
                         "ratio_to_" + self.reference: (median / base) if base else None})
        for name, failure in self.failures.items():
            rows.append({"implementation": name, "median_s": None, "failed": failure})
        return rows

    def report(self) -> list[dict]:
        """Print the table and append it to benchmarks/results/<chapter>.json."""
        rows = self.rows()
        print(f"\n## {self.chapter}: {self.case}  ({machine_description()}, median of {self.repeats})")
        print(f"{'implementation':<28} {'median [s]':>12} {'x ' + self.reference:>16}")
        for row in rows:
            if row.get("median_s") is None:
                print(f"{row['implementation']:<28} {'failed':>12}  {row['failed']}")
                continue
            ratio = row["ratio_to_" + self.reference]
            print(f"{row['implementation']:<28} {row['median_s']:>12.4f} {ratio:>16.2f}" if ratio
                  else f"{row['implementation']:<28} {row['median_s']:>12.4f} {'-':>16}")
        RESULTS_DIR.mkdir(exist_ok=True)
        path = RESULTS_DIR / f"{self.chapter}.json"
        stored = json.loads(path.read_text()) if path.exists() else {}
        stored[self.case] = {"machine": machine_description(), "repeats": self.repeats, "rows": rows,
                             "when": time.strftime("%Y-%m-%d %H:%M:%S")}
        path.write_text(json.dumps(stored, indent=2))
        return rows
