"""Read speed of meshsmith.io against trimesh, meshio and libigl on a 1M-face mesh.

A 708 x 708 grid (501,264 vertices, 1,000,000 triangles; 201 x 201, 80,000 triangles, in quick
mode) with irregular heights, written by meshsmith as binary PLY and as OBJ (shortest round-trip
decimals) into a temporary folder; every reader loads each file. Writing both formats is timed
too, binary PLY on every side (libigl's writer is asked for binary: its default is ASCII).
trimesh's OBJ writer writes 8 decimals (lossy, and less text than meshsmith's round-trip digits):
its OBJ write figure favours trimesh.

Result checks (tolerance 0: the files hold the numbers exactly): every reader's V and F equal
meshsmith's on both files, and trimesh reads meshsmith's written files back to V and F exactly.
"""
from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, optional, size  # noqa: E402

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
    """Readers of the peer libraries that import here: name -> function(path) -> (V, F)."""
    found = {}
    trimesh, meshio, igl = optional("trimesh"), optional("meshio"), optional("igl")
    if trimesh:
        found["trimesh"] = lambda path: (lambda m: (m.vertices, m.faces))(trimesh.load(path, process=False))
    if meshio:
        found["meshio"] = lambda path: (lambda m: (m.points, m.cells_dict["triangle"]))(meshio.read(path))
    if igl:
        found["libigl read_triangle_mesh"] = lambda path: igl.read_triangle_mesh(str(path))
    return found


def differing_entries(V, F, V2, F2) -> int:
    """How many entries of (V2, F2) differ from (V, F); every entry when a shape differs."""
    V2, F2 = np.asarray(V2), np.asarray(F2)
    if V2.shape != V.shape or F2.shape != F.shape:
        return V.size + F.size
    return int((V2 != V).sum() + (F2 != F).sum())


def main() -> None:
    V, F = grid_mesh(size(708, 201))
    label = f"{len(F) / 1e6:g}M-face" if len(F) >= 1e6 else f"{len(F):,}-face"
    print(f"mesh: {len(V)} vertices, {len(F)} triangles")
    readers = peers()
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        files = {"binary PLY": folder / "grid.ply", "OBJ": folder / "grid.obj"}
        for path in files.values():
            meshsmith.io.write_mesh(path, V, F)
        V_ply, F_ply = meshsmith.io.read_mesh(files["binary PLY"])
        assert np.array_equal(V_ply, V) and np.array_equal(F_ply, F)
        for file_label, path in files.items():
            megabytes = path.stat().st_size / 1e6
            bench = Benchmark("io", f"read {label} {file_label} ({megabytes:.1f} MB)", repeats=5)
            bench.time("meshsmith", lambda: meshsmith.io.read_mesh(path))
            for name, read in readers.items():
                bench.time(name, lambda read=read: read(path))
            bench.report()
            ours = bench.output("meshsmith")
            bench.check("entries differing from the input, meshsmith", differing_entries(V, F, *ours), 0)
            for name in readers:
                bench.check(f"entries differing from meshsmith's, {name}", differing_entries(*ours, *bench.output(name)), 0)

        write_peers = {}
        trimesh, meshio, igl = optional("trimesh"), optional("meshio"), optional("igl")
        if trimesh:
            mesh = trimesh.Trimesh(V, F, process=False)
            write_peers["trimesh"] = lambda path: mesh.export(path)
        if meshio:
            mesh_io = meshio.Mesh(V, [("triangle", F)])
            write_peers["meshio"] = lambda path: meshio.write(path, mesh_io)
        if igl:
            write_peers["libigl write_triangle_mesh"] = \
                lambda path: igl.write_triangle_mesh(str(path), V, F, igl.FileEncoding.Binary)
        for file_label, extension, repeats in (("binary PLY", "ply", 5), ("OBJ", "obj", size(1, 5))):
            bench = Benchmark("io", f"write {label} {file_label}", repeats=repeats)
            target = folder / f"written.{extension}"
            bench.time("meshsmith", lambda: meshsmith.io.write_mesh(target, V, F))
            for name, write in write_peers.items():
                bench.time(name, lambda write=write: write(target))
            bench.report()
            meshsmith.io.write_mesh(target, V, F)
            if trimesh:
                back = trimesh.load(target, process=False)
                bench.check("entries of meshsmith's file differing from the input, read by trimesh",
                            differing_entries(V, F, back.vertices, back.faces), 0)


if __name__ == "__main__":
    main()
