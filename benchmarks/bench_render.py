"""meshsmith.render: time of one 800×600 picture (3×3 supersampling). No peer renders offscreen
here without a display, so the table has meshsmith rows only; it tracks the "a 100k-face mesh
renders in seconds" goal."""
import tempfile
from pathlib import Path

from harness import Benchmark

from meshsmith import datasets, render


def main():
    with tempfile.TemporaryDirectory() as folder:
        png = Path(folder) / "picture.png"
        for subdivisions in (6, 7, 8):
            V, F = datasets.icosphere(subdivisions)
            bench = Benchmark("render", f"800x600 picture, {len(F):,}-face sphere", repeats=3)
            bench.time("meshsmith render() + PNG", lambda: render.render(V, F, png))
            bench.time("meshsmith render() + PNG, wireframe", lambda: render.render(V, F, png, wireframe=True))
            bench.report()


if __name__ == "__main__":
    main()
