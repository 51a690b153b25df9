"""Decimation (§4.2): meshsmith's QEM decimate vs fast_simplification, libigl's decimate/qslim,
open3d's simplify_quadric_decimation and pymeshlab's quadric edge collapse (those installed).

1. Speed: a 1,310,720-face sphere (datasets.icosphere(8), slightly bumped so costs differ) to 10%,
   every decimator (libigl's decimate takes about 10 s and qslim about 22 s there; the slow peers
   run once after the warm-up, the others three times), with meshsmith both parallel (default) and
   serial; then an 81,920-face sphere (icosphere(6)), three repeats. Quick mode: icosphere(6)
   only.
2. Peak memory of each method on the 1.3M-face input: one subprocess per method, the increase of
   VmHWM (peak resident set, /proc/self/status) over the level after loading the input — this
   sees C++ allocations, which tracemalloc does not. Skipped in quick mode.
3. Quality: symmetric Hausdorff distance (vertices + 4 samples per face, both ways) relative to
   the bounding-box diagonal on the shared meshes at 10% and 1% of the faces (quick mode: two
   meshes).

Same inputs: every decimator gets the same float64 V and the same C-contiguous int32 F, made once
outside the timing (each library's own conversion into its structures is timed, as meshsmith's
is), and returns numpy (V, F). The peers' decimators are serial; meshsmith's default is parallel, and
its serial figure is the "parallel=False" row.

Result checks (tolerances): meshsmith reaches the target face count within 2 faces (a collapse
removes two); its relative Hausdorff error is at most 1.5 times fast-simplification's on every
input (speed and quality meshes alike).
"""
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, check, machine_description, optional, shared_data_dir, size  # noqa: E402

from meshsmith import datasets, decimation, geometry, io  # noqa: E402

DATA = shared_data_dir() or Path("../shared/data")
QUALITY_MESHES = ["armadillo.obj", "pmp-bunny.off", "nefertiti-lowres.obj", "fandisk.obj", "bumpy-cube.obj"]


def bumped_sphere(subdivisions):
    V, F = datasets.icosphere(subdivisions)
    return V + 0.01 * np.sin(7 * V[:, [1, 2, 0]]), np.ascontiguousarray(F, dtype=np.int32)


def check_decimation(label, V, F, target, outputs) -> None:
    """Face count of meshsmith's output, and its error against fast-simplification's."""
    if "meshsmith" in outputs:
        check("decimation", label, "meshsmith: |faces - target|", abs(len(outputs["meshsmith"][1]) - target), 2)
    if "meshsmith" in outputs and "fast_simplification" in outputs:
        ours = relative_hausdorff(V, F, *outputs["meshsmith"])
        theirs = relative_hausdorff(V, F, *outputs["fast_simplification"])
        check("decimation", label, f"meshsmith's relative Hausdorff error ({ours:.2e}) / fast-simplification's "
              f"({theirs:.2e})", ours / theirs, 1.5)


def methods():
    """name -> fn(V, F, target_faces) -> (V, F), for every installed decimator (F: int32)."""
    out = {"meshsmith": lambda V, F, t: decimation.decimate(V, F, target_faces=t),
           "meshsmith (parallel=False)": lambda V, F, t: decimation.decimate(V, F, target_faces=t, parallel=False),
           "meshsmith (multiple choice k=8)": lambda V, F, t: decimation.decimate(V, F, target_faces=t, candidates=8)}
    fs = optional("fast_simplification")
    if fs:
        out["fast_simplification"] = lambda V, F, t: fs.simplify(V, F, target_count=t)
    igl = optional("igl")
    if igl:
        def igl_call(function):
            def run(V, F, t):
                result = function(V, F, t)
                return result[0], result[1]
            return run
        out["libigl decimate"] = igl_call(igl.decimate)
        out["libigl qslim"] = igl_call(igl.qslim)
    o3d = optional("open3d")
    if o3d:
        def open3d_run(V, F, t):
            mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(V), o3d.utility.Vector3iVector(F))
            out_mesh = mesh.simplify_quadric_decimation(target_number_of_triangles=t)
            return np.asarray(out_mesh.vertices), np.asarray(out_mesh.triangles)
        out["open3d"] = open3d_run
    ml = optional("pymeshlab")
    if ml:
        def meshlab_run(V, F, t):
            ms = ml.MeshSet()
            ms.add_mesh(ml.Mesh(V, F))
            ms.meshing_decimation_quadric_edge_collapse(targetfacenum=t)
            m = ms.current_mesh()
            return m.vertex_matrix(), m.face_matrix()
        out["pymeshlab"] = meshlab_run
    return out


def speed():
    all_methods = methods()
    for subdivisions, slow_repeats in size([(8, 1), (6, 5)], [(6, 1)]):
        V, F = bumped_sphere(subdivisions)
        target = len(F) // 10
        label = f"to 10%: icosphere({subdivisions}) bumped, {len(F):,} faces -> {target:,}"
        bench = Benchmark("decimation", label, repeats=5)
        for name, run in all_methods.items():  # the slow peers (10-25 s at 1.3M faces) once after the warm-up
            slow = name.startswith(("libigl", "open3d", "pymeshlab"))
            bench.time(name, lambda run=run: run(V, F, target), repeats=slow_repeats if slow else None)
        bench.report()
        check_decimation(label, V, F, target, bench.outputs)


def _vm_hwm_kib():
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1])
    return 0


def memory_child(name):
    """Run in a subprocess: one decimation of the 1.3M-face input; print the peak increase (MiB)."""
    V, F = bumped_sphere(8)
    run = methods()[name]
    before = _vm_hwm_kib()
    run(V, F, len(F) // 10)
    print((_vm_hwm_kib() - before) / 1024.0)


def memory():
    print(f"\n## decimation: peak memory, icosphere(8) bumped to 10% ({machine_description()})")
    print(f"{'implementation':<34} {'peak increase [MiB]':>20}")
    for name in methods():
        result = subprocess.run([sys.executable, __file__, "--memory", name], capture_output=True, text=True)
        value = result.stdout.strip().splitlines()[-1] if result.returncode == 0 and result.stdout.strip() else "failed"
        print(f"{name:<34} {value:>20}")


def relative_hausdorff(V, F, V2, F2):
    diagonal = np.linalg.norm(V.max(0) - V.min(0))
    V2, F2 = np.asarray(V2, dtype=float), np.asarray(F2)
    return geometry.hausdorff_distance(V, F, V2, F2, sampled=True, samples_per_face=4) / diagonal


def quality():
    all_methods = methods()
    meshes = size(QUALITY_MESHES, ["armadillo.obj", "fandisk.obj"])
    names = [name for name in all_methods if not name.startswith("meshsmith (")]
    print("\n## decimation: symmetric Hausdorff / bbox diagonal (vertices + 4 samples/face, both ways)")
    print(f"{'mesh':<22} {'kept':>5} {'faces':>7} " + " ".join(f"{name:>19}" for name in names))
    for mesh_name in meshes:
        path = DATA / mesh_name
        if not path.is_file():
            print(f"{mesh_name:<22} (not found under {DATA})")
            continue
        V, F = io.read_mesh(path)
        F = np.ascontiguousarray(F, dtype=np.int32)
        for ratio in (0.1, 0.01):
            target = int(round(ratio * len(F)))
            cells, outputs = [], {}
            for name in names:
                try:
                    V2, F2 = outputs[name] = all_methods[name](V, F, target)
                    cells.append(f"{relative_hausdorff(V, F, V2, F2):.5f} ({len(F2)})")
                except Exception as error:  # a peer that fails is reported, not fatal
                    cells.append(f"failed: {type(error).__name__}"[:19])
            print(f"{mesh_name:<22} {ratio:>5.0%} {target:>7} " + " ".join(f"{cell:>19}" for cell in cells), flush=True)
            check_decimation(f"quality: {mesh_name} to {ratio:.0%}", V, F, target, outputs)


def main():
    speed()
    if size(True, False):
        memory()
    quality()


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--memory":
        memory_child(sys.argv[2])
    else:
        main()
