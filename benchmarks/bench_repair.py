"""Repair (§2.4). Hole filling (§2.4.1): meshsmith.repair.fill_holes vs pymeshfix (MeshFix), pymeshlab's
meshing_close_holes and trimesh's fill_holes, on the shared meshes with holes, in one run.

Inputs: stanford-bunny.obj (5 holes), plane_holes.obj (27 holes), camelhead.off (one 56-edge
outline), each through repair.clean first (the same cleaned arrays go to every side); quick mode:
plane_holes.obj only. Then one Liepa triangulation (refinement off) of a single hole of ~1,000
boundary vertices cut through a lat-long sphere, Delaunay search space against the exact O(n³)
search (full mode only: about 20 s), and refinement of that patch. Then a hole with an island in
it, filled as one region (islands=True, the default) and loop by loop (islands=False).

The row "meshsmith" is fill_holes with its defaults (Liepa triangulation on the Delaunay search
space, refined); in the large-hole case it is the triangulation alone (refine=False).

Same work: every side is asked to close every hole. meshsmith and pymeshfix `fill_holes` refine the
patch; pymeshlab closes holes of up to 10⁶ edges without refinement (its `refinehole` took 15 s on
the bunny here); pymeshfix's `repair` (fill, plus removal of small components and of
self-intersections) and trimesh's fill_holes (it closes only holes of three or four edges) are
shown for scale (ratios in parentheses).

Per side, after the run: holes left open, manifold output, components and input faces kept, and
the largest dihedral angle at an edge of a new face (patch smoothness; near 180°: a fold-over).
Last, self-intersecting faces of two overlapping icospheres (2 × 81,920 faces; 2 × 5,120 in quick
mode) against pymeshlab's compute_selection_by_self_intersections_per_face: the same faces (0
differences; pymeshlab skips pairs of faces with a common vertex, which this input has none of).

Then removal of self-intersections on an icosphere (81,920 faces; 5,120 in quick mode) with one
vertex pushed through its centre and out of the far side: repair.remove_self_intersections (cut the
intersecting faces out, fill the holes, repeat) against pymeshlab's selection of self-intersecting
faces, their deletion and meshing_close_holes (one round), and pymeshfix's MeshFix.repair (shown
for scale: it also removes small components); checked on each output: self-intersecting pairs left
(by meshsmith's exact test) and holes left.

Result checks (tolerances): meshsmith leaves 0 holes, 0 non-manifold edges, keeps every component
and every input face, and its largest patch angle is below 150° and no larger than pymeshfix's
plus 30°.

Volumetric repair (§2.4.2): two overlapping icospheres merged into one face list (2 × 20,480 faces;
2 × 1,280 in quick mode) and fandisk.obj at epsilon = extent/80 (full mode): the sparse grid
(default; "meshsmith") against the dense voxel grid (grid="dense", same lattice, same solid) — time,
peak memory of the call (resident set, measured in a child process) and output->input Hausdorff;
pymeshfix's MeshFix.repair for scale (other work: it deletes intersecting faces and refills). Then
(full mode) fandisk.obj at epsilon = extent/500 on the sparse grid alone, timed once: the dense
grid would hold 3.2e8 voxels (~3.2 GB) and refuses (at extent/1000 it would be 2.6e9 voxels; the
sparse grid's output there is ~15 million faces, which then dominate memory). Checks: no self-intersection, no
non-manifold edge, no boundary loop in meshsmith's output; the sparse and dense grids give the same
number of output faces up to the manifold fix's cells.

Zippering (§2.4.1): repair.zipper of two overlapping halves of a sphere triangulated differently (an
icosphere's upper part and a rotated icosphere's lower part, 2 × ~6,000 faces; ~1,500 in quick mode)
and of pmp-bunny.off split by a plane with an overlap of 3 edge lengths (full mode). No peer here
zippers (pymeshlab, pymeshfix and trimesh have no such filter), so meshsmith is timed alone. Checks:
manifold, one component, the boundary loops of the union (0), no self-intersecting pair (CGAL's
test), output->original Hausdorff below one mean edge length.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, check, load_average, optional, shared_data_dir, size  # noqa: E402

import meshsmith  # noqa: E402
from meshsmith import datasets, repair, topology  # noqa: E402


def quality(V_in, F_in, V, F):
    """(holes left, manifold, components kept, input faces missing, largest new-face dihedral angle
    in degrees) of an output (V, F) against the cleaned input."""
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    # Output vertices that are input vertices, by position (peers may renumber).
    lookup = {tuple(p): i for i, p in enumerate(np.asarray(V_in).tolist())}
    same = np.array([lookup.get(tuple(p), -1) for p in V.tolist()])
    mapped = np.where((same[F] >= 0).all(axis=1)[:, None], same[F], -1)
    input_faces = {tuple(sorted(f)) for f in np.asarray(F_in).tolist()}
    output_faces = {tuple(sorted(f)) for f in mapped.tolist() if f[0] >= 0}
    missing = len(input_faces - output_faces)
    is_new = np.array([f[0] < 0 or tuple(sorted(f)) not in input_faces for f in mapped.tolist()])
    manifold = topology.is_manifold(F)
    holes = len(topology.boundary_loops(F)) if manifold else -1
    components = topology.connected_components(F, len(V)).count
    kept = components == topology.connected_components(F_in).count
    # Largest dihedral angle over the edges with two faces, one of them new.
    sides = np.stack([F, np.roll(F, -1, axis=1)], axis=2).reshape(-1, 2)
    key = np.sort(sides, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, face = key[order], order // 3
    pair = np.flatnonzero((key[1:] == key[:-1]).all(axis=1))
    a, b = face[pair], face[pair + 1]
    use = is_new[a] | is_new[b]
    N = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    N /= np.maximum(np.linalg.norm(N, axis=1, keepdims=True), 1e-300)
    cosine = np.einsum("ij,ij->i", N[a[use]], N[b[use]])
    angle = float(np.degrees(np.arccos(np.clip(cosine, -1, 1))).max()) if use.any() else 0.0
    return holes, manifold, kept, missing, angle


def meshfix_repaired(pymeshfix, V, F):
    """pymeshfix's MeshFix.repair of (V, F): (points, faces)."""
    fix = pymeshfix.MeshFix(V, F)
    fix.repair()
    return fix.points, fix.faces


def compare(name, V, F):
    loops = len(topology.boundary_loops(F))
    bench = Benchmark("repair", f"fill the {loops} holes of {name} ({len(F):,} faces after clean)")
    bench.time("meshsmith", lambda: repair.fill_holes(V, F))
    pymeshfix = optional("pymeshfix")
    if pymeshfix:
        def meshfix_fill():
            fix = pymeshfix.MeshFix(V, F)
            fix.fill_holes()
            return fix.points, fix.faces

        bench.time("pymeshfix MeshFix.fill_holes (refined)", meshfix_fill)
        bench.time("pymeshfix MeshFix.repair", lambda: meshfix_repaired(pymeshfix, V, F), same_work=False)
    pymeshlab = optional("pymeshlab")
    if pymeshlab:
        def meshlab_close():
            meshes = pymeshlab.MeshSet()
            meshes.add_mesh(pymeshlab.Mesh(V, F))
            meshes.meshing_close_holes(maxholesize=10 ** 6)
            mesh = meshes.current_mesh()
            return mesh.vertex_matrix(), mesh.face_matrix()
        bench.time("pymeshlab meshing_close_holes", meshlab_close)
    trimesh = optional("trimesh")
    if trimesh:
        def trimesh_fill():
            mesh = trimesh.Trimesh(V, F, process=False)
            mesh.fill_holes()
            return mesh.vertices, mesh.faces
        bench.time("trimesh fill_holes (3- and 4-edge holes)", trimesh_fill, same_work=False)
    bench.report()
    print(f"  {'implementation':<44} {'holes left':>10} {'manifold':>9} {'components':>11} "
          f"{'input faces lost':>17} {'max patch angle':>16}")
    figures = {}
    for implementation in bench.medians:
        out = bench.output(implementation)
        V_out, F_out = (out.V, out.F) if implementation.startswith("meshsmith") else out
        figures[implementation] = quality(V, F, V_out, F_out)
        holes, manifold, kept, missing, angle = figures[implementation]
        print(f"  {implementation:<44} {holes:>10} {str(manifold):>9} {'kept' if kept else 'CHANGED':>11} "
              f"{missing:>17} {angle:>15.1f}°")
    ours = figures["meshsmith"]
    bench.check("meshsmith: holes left", ours[0], 0)
    bench.check("meshsmith: non-manifold output (1 = yes)", 0 if ours[1] else 1, 0)
    bench.check("meshsmith: components changed (1 = yes)", 0 if ours[2] else 1, 0)
    bench.check("meshsmith: input faces lost", ours[3], 0)
    bench.check("meshsmith: largest dihedral angle at a patch edge [deg]", ours[4], 150)
    if "pymeshfix MeshFix.fill_holes (refined)" in figures:
        bench.check("meshsmith's largest patch angle minus pymeshfix's [deg]",
                    ours[4] - figures["pymeshfix MeshFix.fill_holes (refined)"][4], 30)


def zigzag_hole(n_longitude):
    """A lat-long sphere without a wavy cap: one loop of about 1.36 n_longitude edges."""
    V, F = datasets.uv_sphere(150, n_longitude)
    centre = V[F].mean(axis=1)
    phi = np.arctan2(centre[:, 1], centre[:, 0])
    polar = np.arccos(np.clip(centre[:, 2] / np.linalg.norm(centre, axis=1), -1, 1))
    V, F, _ = repair.remove_unreferenced(V, F[polar > 0.6 + 0.15 * np.sin(3 * phi)])
    return V, F


def large_hole():
    V, F = zigzag_hole(size(740, 300))
    n = len(topology.boundary_loops(F)[0])
    bench = Benchmark("repair", f"Liepa triangulation of one {n:,}-edge hole ({len(F):,} faces around it)")
    bench.time("meshsmith", lambda: repair.fill_holes(V, F, refine=False))
    bench.time("meshsmith, then refinement and fairing", lambda: repair.fill_holes(V, F), same_work=False)
    if size(True, False):   # full mode only: about 20 s a run
        bench.time("meshsmith exact O(n^3) search", lambda: repair.fill_holes(V, F, refine=False, search="exact"),
                   repeats=1)
    bench.report()
    fast = bench.output("meshsmith").report.patches[0]
    bench.check("Delaunay search fell back to the exact one (1 = yes)", 0 if fast.search == "delaunay" else 1, 0)
    if "meshsmith exact O(n^3) search" in bench.medians:
        exact = bench.output("meshsmith exact O(n^3) search").report.patches[0]
        bench.check("largest dihedral angle: Delaunay search minus exact optimum [deg]",
                    fast.max_dihedral_angle - exact.max_dihedral_angle, 5.0)
        bench.check("exact optimum worse than the Delaunay search's [deg]",
                    exact.max_dihedral_angle - fast.max_dihedral_angle, 1e-9)


def island_hole():
    """A hole with an island (a grid patch floating in it): fill_holes joins the island to the
    rim by a bridge and fills the ring between them as one region, against islands=False (each loop
    on its own: the hole's patch covers the island). Checks: one component, no self-intersection,
    the patch's area that of the ring (the plane's area exactly)."""
    n = size(160, 48)
    V, F = datasets.grid(n, n)
    centre = V[F].mean(axis=1)
    inside = (np.abs(centre[:, :2] - 0.5) < 0.25).all(axis=1)
    island_V, island_F = datasets.grid(n // 4, n // 4, size=(0.2, 0.2))
    V = np.vstack([V, island_V + [0.4, 0.4, 0.0]])
    F = np.vstack([F[~inside], island_F + len(V) - len(island_V)])
    bench = Benchmark("repair", f"hole with an island ({len(F):,} faces, loops of "
                                f"{'/'.join(str(len(loop)) for loop in topology.boundary_loops(F))} edges, rim kept)")
    bench.time("meshsmith", lambda: repair.fill_holes(V, F, keep_border=True))
    bench.time("meshsmith, islands=False", lambda: repair.fill_holes(V, F, keep_border=True, islands=False),
               same_work=False)
    bench.report()
    Vo, Fo, report = bench.output("meshsmith")
    patch = report.patches[0]
    print(f"  meshsmith: islands joined {report.counts()['islands_joined']}, largest patch angle "
          f"{patch.max_dihedral_angle:.2g} deg, edge length / ring {patch.edge_length_ratio:.2f}")
    bench.check("components in the output", topology.connected_components(Fo, len(Vo)).count, 1)
    bench.check("self-intersecting pairs in the output", len(repair.self_intersections(Vo, Fo)), 0)
    bench.check("|area - 1| (the unit square, covered once)", abs(meshsmith.geometry.surface_area(Vo, Fo) - 1.0), 1e-9)
    Vs, Fs, _ = bench.output("meshsmith, islands=False")
    print(f"  islands=False: {topology.connected_components(Fs, len(Vs)).count} components, "
          f"{len(repair.self_intersections(Vs, Fs)):,} self-intersecting pairs (the hole's patch over the island)")


def meshlab_with_intersections_selected(pymeshlab, V, F):
    """A pymeshlab MeshSet holding (V, F) with its self-intersecting faces selected."""
    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(pymeshlab.Mesh(V, F))
    meshes.compute_selection_by_self_intersections_per_face()
    return meshes


def intersections():
    V, F = datasets.icosphere(size(6, 4))
    V2 = np.vstack([V, 0.9 * V + [0.5, 0, 0]])
    F2 = np.vstack([F, F + len(V)])
    bench = Benchmark("repair", f"self-intersecting faces of two overlapping spheres ({len(F2):,} faces)")
    bench.time("meshsmith", lambda: repair.self_intersections(V2, F2))
    pymeshlab = optional("pymeshlab")
    if pymeshlab:
        def meshlab_select():
            meshes = meshlab_with_intersections_selected(pymeshlab, V2, F2)
            return np.flatnonzero(meshes.current_mesh().face_selection_array())
        bench.time("pymeshlab compute_selection_by_self_intersections_per_face", meshlab_select)
    bench.report()
    ours = np.unique(bench.output("meshsmith"))
    print(f"  meshsmith: {len(bench.output('meshsmith')):,} pairs on {len(ours):,} faces")
    if "pymeshlab compute_selection_by_self_intersections_per_face" in bench.medians:
        theirs = bench.output("pymeshlab compute_selection_by_self_intersections_per_face")
        bench.check("faces selected by one side only (meshsmith vs pymeshlab)",
                    len(set(ours.tolist()) ^ set(theirs.tolist())), 0)


PEAK_MEMORY_SCRIPT = """
import resource, sys, time
import numpy as np
from meshsmith import repair
data = np.load(sys.argv[1])
V, F = data["V"], data["F"]
before = int(next(line.split()[1] for line in open("/proc/self/status") if line.startswith("VmRSS")))
start = time.perf_counter()
V2, F2, report = repair.volumetric_repair(V, F, epsilon=float(sys.argv[2]), grid=sys.argv[3], max_cells=2 ** 34)
elapsed = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(peak - before, elapsed, len(F2), report.stored_cells, report.dense_cells, report.fine_faces)
"""


def peak_memory(V, F, epsilon, grid):
    """(resident memory the call added at its peak in MB, seconds, output faces, stored cells, dense
    cells, fine faces before the adaptive step) of volumetric_repair in a child process (ru_maxrss
    minus the resident set before the call)."""
    import subprocess
    import tempfile
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / "mesh.npz"
        np.savez(path, V=np.asarray(V, dtype=float), F=np.asarray(F, dtype=np.int64))
        out = subprocess.run([sys.executable, "-c", PEAK_MEMORY_SCRIPT, str(path), repr(epsilon), grid],
                             capture_output=True, text=True, check=True).stdout.split()
    return int(out[0]) / 1024, float(out[1]), int(out[2]), int(out[3]), float(out[4]), int(out[5])


def volumetric(directory):
    """Volumetric repair (§2.4.2) of two overlapping spheres merged into one face list, and of fandisk
    (full mode): sparse grid against dense grid (time, memory, Hausdorff); pymeshfix's MeshFix.repair
    (removes self-intersections by a different method) for scale; fandisk at extent/500 (full mode)."""
    V, F = datasets.icosphere(size(5, 3))
    cases = [("two overlapping spheres", np.vstack([V, 0.9 * V + [0.5, 0, 0]]), np.vstack([F, F + len(V)]), 0.04)]
    if directory is not None and not size(False, True):
        Vf, Ff = meshsmith.io.read_mesh(directory / "fandisk.obj")
        cases.append(("fandisk.obj", Vf, Ff, float(np.ptp(Vf, axis=0).max()) / 80))
    for name, V2, F2, epsilon in cases:
        bench = Benchmark("repair", f"volumetric repair of {name} ({len(F2):,} faces, epsilon {epsilon:.3g})")
        bench.time("meshsmith", lambda: repair.volumetric_repair(V2, F2, epsilon=epsilon))
        bench.time("meshsmith dense grid", lambda: repair.volumetric_repair(V2, F2, epsilon=epsilon, grid="dense"))
        pymeshfix = optional("pymeshfix")
        if pymeshfix:
            bench.time("pymeshfix MeshFix.repair", lambda: meshfix_repaired(pymeshfix, V2, F2), same_work=False)
        bench.report()
        Vo, Fo, report = bench.output("meshsmith")
        Vd, Fd, dense = bench.output("meshsmith dense grid")
        bench.check("self-intersecting pairs in the output", len(repair.self_intersections(Vo, Fo)), 0)
        bench.check("non-manifold edges in the output", len(topology.non_manifold_edges(Fo)), 0)
        bench.check("boundary loops in the output", len(topology.boundary_loops(Fo)), 0)
        bench.check("inside cells, sparse minus dense, beyond the manifold fix's",
                    abs((report.inside_cells - report.manifold_cells) - (dense.inside_cells - dense.manifold_cells)), 0)
        surface = meshsmith.geometry.SurfaceDistance(V2, F2)
        for label, (W, G, r) in (("sparse", (Vo, Fo, report)), ("dense", (Vd, Fd, dense))):
            d = surface.distances(W)
            megabytes, _, _, _, _, _ = peak_memory(V2, F2, epsilon, label)
            print(f"  meshsmith {label} grid: {len(G):,} faces, grid {r.shape}, {r.stored_cells:,} cells stored "
                  f"({r.stored_cells / r.dense_cells:.1%} of {r.dense_cells:,.0f}), peak memory of the call "
                  f"{megabytes:.0f} MB, output->input Hausdorff {d.max() / r.cell_size:.2f} cells, "
                  f"mean {d.mean() / r.cell_size:.3f} cells")
    if directory is not None and not size(False, True):
        Vf, Ff = meshsmith.io.read_mesh(directory / "fandisk.obj")
        epsilon = float(np.ptp(Vf, axis=0).max()) / 500
        megabytes, seconds, faces, stored, cells, fine = peak_memory(Vf, Ff, epsilon, "sparse")
        print(f"\n## repair: volumetric repair of fandisk.obj at epsilon = extent/500 (sparse grid, one run, "
              f"load average {load_average()})\n  {seconds:.1f} s, peak memory of the call {megabytes:.0f} MB, "
              f"{faces:,} faces out ({fine:,} before the adaptive step), {stored:,} cells stored of {cells:.3g} ({stored / cells:.2%}; dense: "
              f"~{cells * 10 / 1e9:.0f} GB)")
        check("repair", "volumetric repair of fandisk.obj at extent/500", "stored cells / dense cells",
              stored / cells, 0.1)


def remove_intersections():
    V, F = datasets.icosphere(size(6, 4))
    V = V.copy()
    V[0] *= -1.3
    bench = Benchmark("repair", f"removing the self-intersections of a poked sphere ({len(F):,} faces)")
    bench.time("meshsmith", lambda: repair.remove_self_intersections(V, F)[:2])
    pymeshlab = optional("pymeshlab")
    if pymeshlab:
        def meshlab_remove():
            meshes = meshlab_with_intersections_selected(pymeshlab, V, F)
            meshes.meshing_remove_selected_faces()
            meshes.meshing_remove_unreferenced_vertices()
            meshes.meshing_close_holes(maxholesize=10 ** 6)
            return meshes.current_mesh().vertex_matrix(), meshes.current_mesh().face_matrix()
        bench.time("pymeshlab select, delete, close holes", meshlab_remove)
    pymeshfix = optional("pymeshfix")
    if pymeshfix:
        bench.time("pymeshfix MeshFix.repair", lambda: meshfix_repaired(pymeshfix, V, F), same_work=False)
    bench.report()
    for name in bench.medians:
        W, G = (np.asarray(a) for a in bench.output(name))
        G = G.astype(np.int64)
        left = len(repair.self_intersections(W, G))
        holes = len(topology.boundary_loops(G))
        print(f"  {name}: {left:,} self-intersecting pairs left, {holes:,} holes, {len(G):,} faces")
        if name == "meshsmith":
            bench.check("meshsmith: self-intersecting pairs left", left, 0)
            bench.check("meshsmith: holes left", holes, 0)


def zipper_halves(V, F, normal, overlap):
    """Two pieces of (V, F) split by the plane through the centre with this normal, overlapping by 2·overlap."""
    height = (V[F].mean(axis=1) - V.mean(axis=0)) @ np.asarray(normal, dtype=float)
    A = repair.remove_unreferenced(V, F[height > -overlap])
    B = repair.remove_unreferenced(V, F[height < overlap])
    return A.V, A.F, B.V, B.F


def zipper(directory):
    from scipy.spatial.transform import Rotation
    V, F = datasets.icosphere(size(5, 4))
    spacing = float(np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean())
    VA, FA, _, _ = zipper_halves(V, F, [0, 0, 1], 0.2)
    _, _, VB, FB = zipper_halves(Rotation.from_euler("xyz", [0.3, 0.5, 0.7]).apply(V), F, [0, 0, 1], 0.2)
    cases = [("two differently triangulated sphere halves", V, F, (VA, FA, VB, FB), 0.05 * spacing, spacing)]
    if directory is not None and not size(False, True):
        Vb, Fb, _ = repair.clean(*meshsmith.io.read_mesh(directory / "pmp-bunny.off"))
        spacing = float(np.linalg.norm(Vb[Fb[:, 0]] - Vb[Fb[:, 1]], axis=1).mean())
        VA, FA, VB, FB = zipper_halves(Vb, Fb, [0.3, 0.2, 0.93], 3 * spacing)
        cases.append(("pmp-bunny.off split by a plane", Vb, Fb, (VA, FA, VB + 1e-3 * spacing, FB),
                      0.05 * spacing, spacing))
    for name, V0, F0, pieces, tolerance, spacing in cases:
        faces = f"{len(pieces[1]):,} + {len(pieces[3]):,} faces"
        bench = Benchmark("repair", f"zippering {name} ({faces}, tolerance {tolerance:.3g})")
        bench.time("meshsmith", lambda: repair.zipper(*pieces, tolerance=tolerance))
        bench.report()
        Vo, Fo, report = bench.output("meshsmith")
        bench.check("non-manifold edges in the output", len(topology.non_manifold_edges(Fo)), 0)
        bench.check("boundary loops: output's minus the original's",
                    abs(len(topology.boundary_loops(Fo)) - len(topology.boundary_loops(F0))), 0)
        bench.check("components in the output", topology.connected_components(Fo, len(Vo)).count, 1)
        distance = meshsmith.geometry.hausdorff_distance(Vo, Fo, V0, F0)
        pairs = len(repair.self_intersections(Vo, Fo))
        print(f"  meshsmith: {len(Fo):,} faces, Hausdorff to the original {distance / spacing:.2f} mean edges, "
              f"{pairs:,} self-intersecting pairs ({report.untangled_pairs} made by the seam and untangled), "
              f"{report.removed_faces:,} B faces removed, {report.snapped_vertices:,} snapped, "
              f"{report.filled_gaps} seam gaps filled")
        bench.check("self-intersecting pairs in the output", pairs, 0)
        bench.check("Hausdorff to the original / mean edge length", distance / spacing, 1.0)


def main():
    directory = shared_data_dir()
    if directory is None:
        print("repair: shared meshes not found (set MESHSMITH_DATA): only the synthetic hole is timed")
    else:
        names = size(["stanford-bunny.obj", "plane_holes.obj", "camelhead.off"], ["plane_holes.obj"])
        for name in names:
            V, F = meshsmith.io.read_mesh(directory / name)
            V, F, _ = repair.clean(V, F)
            compare(name, V, F)
    large_hole()
    island_hole()
    intersections()
    volumetric(directory)
    remove_intersections()
    zipper(directory)


if __name__ == "__main__":
    main()
