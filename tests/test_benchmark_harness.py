"""The benchmark harness (benchmarks/harness.py, run_all.py): quick sizes, alternating rounds, result
checks and crashes that fail the run, the Markdown table. Timings themselves are never asserted."""
import json
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCHMARKS))
import harness  # noqa: E402
import run_all  # noqa: E402


@pytest.fixture(autouse=True)
def fresh_harness(tmp_path, monkeypatch):
    monkeypatch.setattr(harness, "RESULTS_DIR", tmp_path / "results")
    quick = harness.QUICK
    harness.reset()
    yield
    harness.set_quick(quick)
    harness.reset()


def test_size_follows_the_mode():
    harness.set_quick(True)
    assert harness.size(1_000_000, 20_000) == 20_000
    harness.set_quick(False)
    assert harness.size(1_000_000, 20_000) == 1_000_000


def test_rounds_alternate_and_each_implementation_runs_warm_up_plus_repeats():
    order = []
    bench = harness.Benchmark("demo", "case", repeats=3)
    bench.time("meshsmith", lambda: order.append("m"))
    bench.time("peer", lambda: order.append("p"))
    bench.time("slow peer", lambda: order.append("s"), repeats=1)
    harness.set_quick(True)
    rows = bench.report()
    assert "".join(order) == "mps" + "mps" + "mp" + "mp"   # warm-ups, then three rounds
    assert {row["implementation"] for row in rows} == {"meshsmith", "peer", "slow peer"}
    assert harness.FAILURES == []


def test_a_raising_implementation_and_a_failed_check_are_recorded():
    bench = harness.Benchmark("demo", "case", repeats=2)
    bench.time("meshsmith", lambda: None)
    bench.time("peer", lambda: 1 / 0)
    harness.set_quick(True)
    bench.report()
    assert len(harness.FAILURES) == 1 and "ZeroDivisionError" in harness.FAILURES[0]
    assert bench.check("within", 1e-12, 1e-10) is True
    assert bench.check("beyond", 2e-10, 1e-10) is False
    assert bench.check("not a number", float("nan"), 1.0) is False
    assert [c["passed"] for c in harness.CHECKS] == [True, False, False]


def test_markdown_table_gives_ratios_peer_over_meshsmith_and_brackets_different_work():
    case = {"chapter": "demo", "case": "case", "reference": "meshsmith", "rows": [
        {"implementation": "meshsmith", "median_s": 0.010, "same_work": True},
        {"implementation": "peer", "median_s": 0.025, "same_work": True},
        {"implementation": "floor", "median_s": 0.005, "same_work": False}]}
    table = harness.markdown_table([case]).splitlines()
    assert table[2] == "| demo | case | 10 | peer | 25 | 2.50 |"
    assert table[3] == "| demo | case | 10 | floor | 5 | (0.50) |"


def test_run_all_exits_1_on_a_failed_check_or_a_crash_and_writes_quick_json(tmp_path):
    folder = tmp_path / "benches"
    folder.mkdir()
    (folder / "bench_good.py").write_text(
        "from harness import Benchmark\n"
        "def main():\n"
        "    bench = Benchmark('good', 'case', repeats=1)\n"
        "    bench.time('meshsmith', lambda: None)\n"
        "    bench.report()\n"
        "    bench.check('exact', 0, 0)\n")
    assert run_all.main(["--quick"], directory=folder) == 0
    written = json.loads((harness.RESULTS_DIR / "quick.json").read_text())
    assert written["mode"] == "quick" and len(written["checks"]) == 1 and written["failures"] == []

    (folder / "bench_wrong.py").write_text(
        "from harness import check\n"
        "def main():\n"
        "    check('wrong', 'case', 'difference from the peer', 1.0, 1e-10)\n")
    assert run_all.main(["--quick"], directory=folder) == 1
    (folder / "bench_wrong.py").unlink()
    (folder / "bench_crash.py").write_text("def main():\n    raise RuntimeError('boom')\n")
    assert run_all.main(["--quick"], directory=folder) == 1
    assert "bench_crash.py:2: RuntimeError: boom" in harness.FAILURES[0]
