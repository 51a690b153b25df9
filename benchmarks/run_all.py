"""`make bench`: runs every benchmarks/bench_<chapter>.py in one process, one after another."""
import importlib.util
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


def main(selected: list[str]) -> None:
    for path in sorted(HERE.glob("bench_*.py")):
        chapter = path.stem.removeprefix("bench_")
        if selected and chapter not in selected:
            continue
        spec = importlib.util.spec_from_file_location(path.stem, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        module.main()
    print(f"\nresults saved in {HERE / 'results'}")


if __name__ == "__main__":
    main(sys.argv[1:])
