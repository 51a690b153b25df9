"""meshsmith.render: time of one 800×600 picture (3×3 supersampling). No peer renders offscreen
here without a display, so the table has meshsmith rows only; it tracks the "a 100k-face mesh
renders in seconds" goal. Spheres of 82k, 328k and 1.3M faces (20k in quick mode).

Result check: the picture decodes (Pillow) to 800×600 and the sphere covers between 20% and 80%
of it (pixels that differ from the background at the left end of their row).
"""
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, size  # noqa: E402

from meshsmith import datasets, render  # noqa: E402


def covered_share(png: Path) -> float:
    from PIL import Image
    with Image.open(png) as image:
        if image.size != (800, 600):
            return float("nan")
        pixels = np.asarray(image.convert("RGB")).astype(int)
    return float(np.any(pixels != pixels[:, :1], axis=2).mean())  # the background changes by row only


def main():
    with tempfile.TemporaryDirectory() as folder:
        png = Path(folder) / "picture.png"
        for subdivisions in size((6, 7, 8), (5,)):
            V, F = datasets.icosphere(subdivisions)
            bench = Benchmark("render", f"800x600 picture, {len(F):,}-face sphere", repeats=5,
                              reference="meshsmith render() + PNG")
            bench.time("meshsmith render() + PNG", lambda: render.render(V, F, png))
            bench.time("meshsmith render() + PNG, wireframe", lambda: render.render(V, F, png, wireframe=True))
            bench.report()
            render.render(V, F, png)
            share = covered_share(png)
            bench.check(f"the sphere covers {share:.0%} of the picture: outside 20-80% (1) or not (0)",
                        0 if 0.2 <= share <= 0.8 else 1, 0)


if __name__ == "__main__":
    main()
