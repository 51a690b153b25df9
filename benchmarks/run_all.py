"""`make bench` / `make bench-quick`: every benchmarks/bench_<chapter>.py in one process, in turn.

    python benchmarks/run_all.py [--quick] [CHAPTER ...]

Prints each case as it runs, then a summary: date, machine, load average, thread settings, and a
Markdown table of medians and ratios (peer time ÷ meshsmith time); writes the whole run to
benchmarks/results/quick.json (--quick: small inputs, a few minutes) or results/full.json.
Exits 1 when a chapter's benchmark crashed, a timed implementation raised, or a result check
exceeded its tolerance; timings themselves never fail the run.
"""
import importlib.util
import json
import sys
import time
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import harness  # noqa: E402


def main(arguments: list[str], directory: Path = HERE) -> int:
    """Run the bench files of `directory`; return the exit status (1: a crash or a failed check)."""
    quick = "--quick" in arguments
    selected = [argument for argument in arguments if not argument.startswith("--")]
    harness.set_quick(quick)
    harness.reset()
    print(f"meshsmith benchmarks ({'quick' if quick else 'full'}): {harness.run_header()}")
    print(harness.threads_description())
    started = time.perf_counter()
    chapters = {}
    for path in sorted(directory.glob("bench_*.py")):
        chapter = path.stem.removeprefix("bench_")
        if selected and chapter not in selected:
            continue
        chapter_start = time.perf_counter()
        try:
            spec = importlib.util.spec_from_file_location(path.stem, path)
            module = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(module)
            module.main()
        except Exception as error:  # the other chapters still run; the run fails
            traceback.print_exc()
            where = traceback.extract_tb(error.__traceback__)[-1]
            harness.FAILURES.append(f"{chapter}: benchmark crashed at {Path(where.filename).name}:{where.lineno}: "
                                    f"{type(error).__name__}: {error}"[:300])
        chapters[chapter] = time.perf_counter() - chapter_start
        print(f"[{chapter}: {chapters[chapter]:.1f} s]", flush=True)
    total = time.perf_counter() - started

    failed_checks = [c for c in harness.CHECKS if not c["passed"]]
    print(f"\n# meshsmith benchmarks ({'quick' if quick else 'full'})\n")
    print(f"{harness.run_header()}; {total:.0f} s in all.  ")
    print(f"{harness.threads_description()}.  ")
    print("Ratio = the peer's (or variant's) median time ÷ meshsmith's: above 1, meshsmith is faster. "
          "In parentheses: a peer that does different work (a floor or for scale).\n")
    print(harness.markdown_table(harness.CASES))
    print(f"\nresult checks: {len(harness.CHECKS) - len(failed_checks)} passed, {len(failed_checks)} failed")
    for failed in failed_checks:
        print(f"  FAILED check: {failed['chapter']}: {failed['case']}: {failed['quantity']} = "
              f"{failed['value']:.3g} > tolerance {failed['tolerance']:.3g}")
    for failure in harness.FAILURES:
        print(f"  FAILED: {failure}")
    for missing in harness.MISSING_PEERS:
        print(f"  peer not available (its rows are absent): {missing}")

    harness.RESULTS_DIR.mkdir(exist_ok=True)
    output = harness.RESULTS_DIR / ("quick.json" if quick else "full.json")
    output.write_text(json.dumps({
        "mode": "quick" if quick else "full", "when": time.strftime("%Y-%m-%d %H:%M:%S %Z"),
        "machine": harness.machine_description(), "load_average_at_end": harness.load_average(),
        "threads": harness.threads_description(), "total_s": total, "chapter_s": chapters,
        "cases": harness.CASES, "checks": harness.CHECKS, "failures": harness.FAILURES,
        "missing_peers": harness.MISSING_PEERS}, indent=2))
    print(f"results saved in {output}")
    return 1 if failed_checks or harness.FAILURES else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
