"""Read speed of meshsmith.io against trimesh, meshio and libigl on a 1M-face mesh.

A 708 x 708 grid (501,264 vertices, 1,000,000 triangles) with irregular heights, written by
meshsmith as binary PLY and as OBJ (shortest round-trip decimals) into a temporary folder; every
reader loads each file. Writing both formats is timed too (each library's default encoding:
libigl writes ASCII PLY, the others binary).
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark  # noqa: E402

import meshsmith.io  # noqa: E402


def grid_mesh(side: int = 708):
    """(V, F) of a side x side vertex grid over [0, 1]^2 with random heights: 2 (side-1)^2 faces."""
    x, y = np.meshgrid(np.linspace(0, 1, side), np.linspace(0, 1, side))
    z = np.random.default_rng(0).normal(scale=0.01, size=x.shape)
    V = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    i = np.arange(side - 1)
    a = (i[:, None] * side + i[None, :]).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + side + 1]),
                        np.column_stack([a, a + side + 1, a + side])])
    return V, F


def peers():
    """Readers of the peer libraries that import here, as name -> function(path)."""
    found = {}
    try:
        import trimesh
        found["trimesh"] = lambda path: trimesh.load(path, process=False)
    except ImportError as error:
        print("trimesh unavailable:", error)
    try:
        import meshio
        found["meshio"] = lambda path: meshio.read(path)
    except ImportError as error:
        print("meshio unavailable:", error)
    try:
        import igl
        found["libigl read_triangle_mesh"] = lambda path: igl.read_triangle_mesh(str(path))
    except ImportError as error:
        print("libigl unavailable:", error)
    return found


def main() -> None:
    V, F = grid_mesh()
    print(f"mesh: {len(V)} vertices, {len(F)} triangles")
    readers = peers()
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        files = {"binary PLY": folder / "grid.ply", "OBJ": folder / "grid.obj"}
        for path in files.values():
            meshsmith.io.write_mesh(path, V, F)
        V_ply, F_ply = meshsmith.io.read_mesh(files["binary PLY"])
        assert np.array_equal(V_ply, V) and np.array_equal(F_ply, F)
        for label, path in files.items():
            size = path.stat().st_size / 1e6
            bench = Benchmark("io", f"read 1M-face {label} ({size:.0f} MB)", repeats=3)
            bench.time("meshsmith", lambda: meshsmith.io.read_mesh(path))
            for name, read in readers.items():
                bench.time(name, lambda read=read: read(path))
            bench.report()

        write_peers = {}
        try:
            import trimesh
            mesh = trimesh.Trimesh(V, F, process=False)
            write_peers["trimesh"] = lambda path: mesh.export(path)
        except ImportError:
            pass
        try:
            import meshio
            mesh_io = meshio.Mesh(V, [("triangle", F)])
            write_peers["meshio"] = lambda path: meshio.write(path, mesh_io)
        except ImportError:
            pass
        try:
            import igl
            write_peers["libigl write_triangle_mesh"] = lambda path: igl.write_triangle_mesh(str(path), V, F)
        except ImportError:
            pass
        for label, extension, repeats in (("binary PLY", "ply", 3), ("OBJ", "obj", 1)):
            bench = Benchmark("io", f"write 1M-face {label}", repeats=repeats)
            target = folder / f"written.{extension}"
            bench.time("meshsmith", lambda: meshsmith.io.write_mesh(target, V, F))
            for name, write in write_peers.items():
                bench.time(name, lambda write=write: write(target))
            bench.report()


if __name__ == "__main__":
    main()
