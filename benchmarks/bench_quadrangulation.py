"""Quadrangulation (§5.2.2): meshsmith's quadrangulate (cross field → MIQ → quad extraction) side by
side with Instant Meshes (pynanoinstantmeshes) and QuadriFlow (pyQuadriFlow), at the same target.

Inputs: a torus (datasets.torus, 48×20 → 1,920 faces) and, when ../shared/data is present, the
issue's meshes spot.obj (5,856 faces), fertility.off (9,000, genus 4), kitten.off (5,000, genus 1),
fandisk.obj (12,946, sharp features), rocker-arm.obj (20,088, genus 1) and pmp-bunny.off (69,666),
three alternating rounds each (pmp-bunny's ratio to QuadriFlow is close); quick mode: the torus and spot. Target: 3,000
quads on the shared meshes, 300 on the torus; the peers get the same count (Instant Meshes as its
target vertex count — a closed quad mesh has about as many vertices as faces —, QuadriFlow as its
requested faces); Instant Meshes again asked for a quarter of the target ("Instant Meshes/4"), which
returns about the target, so that its figures are also read at the same output size.

Same work: each call remeshes the same triangle mesh into quads at the same target; the peers
solve the problem differently (Instant Meshes: local position/orientation fields, quad-dominant
output; QuadriFlow: a min-cost-flow integer field), so their ratios compare tools, not algorithms.

Printed per tool: quads, non-quad faces, irregular (valence ≠ 4) interior vertices, mean
|angle − 90°|, minimum scaled Jacobian, Hausdorff distance to the input ÷ its bounding-box diagonal, whether it is a closed manifold with the input's χ.
Spectral cases (§5.2.1, spectral_quadrangulate) on the torus and the real meshes at 2,000 quads
(see spectral_cases): meshsmith spectral against meshsmith's MIQ pipeline and Instant Meshes, same
figures; checks: pure quads, manifold, oriented, χ kept (0 violations), the Morse invariant, quad
count within 50% of the target.
Result checks (tolerances): meshsmith's mesh is pure quads, manifold and oriented (0 violations);
on the torus it is complete (χ = 0) with 0 irregular vertices; the quad count within 10% of the
target (40% on the 300-quad torus; MIQ calibrates its grid on the continuous map); no MIQ flip
left, the extraction complete and every quad convex (minimum scaled Jacobian > 0).

fandisk.obj again with sharp_angle=40 (MIQ holds its feature edges on integer iso-lines) at 3,000
quads, the peers as above: the same figures plus the fraction of the feature length on integer
iso-lines and of the feature-edge midpoints within 1e-6 / 0.01 quad edges of a quad edge (also for
the peers). Checks: pure quads, no MIQ flip left, complete, convex; ≥ 95% of the feature length on
integer iso-lines. Then fandisk once more with conformal_scale=0 (MIQ's uniform grid scale).

Dual-loop layouts (§5.3, `dual_loop_layout`, no peer on PyPI): the torus (48×16) and spot's smooth
cross field (computed once, outside the timing), default spacing; printed: loops, crossings
(= coarse quads), regions (= layout vertices), regions left with several singularities, whether
the layout is complete; spot again with parallel crossings allowed (parallel_crossing_penalty=4).
Each is one attempt on the field as it is (merge=0, refine=0, max_failed_seeds=2000: the defaults
before dual_loop_layout's schedule of attempts), so the figures stay comparable.
Checks: the torus layout complete with every layout vertex of valence 4; every region of spot a
disk; with parallel crossings, spot's layout a manifold with χ = 2.
"""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import Benchmark, optional, shared_data_dir, size  # noqa: E402

from meshsmith import datasets, geometry, io, repair, topology  # noqa: E402
from meshsmith.io import Polygons  # noqa: E402
from meshsmith.quadrangulation import cross_field, dual_loop_layout, quad_quality, quadrangulate  # noqa: E402


def shared_mesh(name):
    directory = shared_data_dir()
    if directory is None:
        return None
    V, F = io.read_mesh(directory / name)
    return repair.clean(V, F)[:2]


def instant_meshes(module, V, F, faces):
    # Instant Meshes takes a vertex count (a closed quad mesh has about as many vertices as faces).
    Vq, Q = module.remesh(V.astype(np.float32), F.astype(np.uint32), faces, deterministic=True)
    return np.asarray(Vq, dtype=np.float64), np.asarray(Q, dtype=np.int64)


def quadriflow(module, V, F, faces):
    mesh = module.pyquadriflow(faces, 0, V, F, False, False, False, False, False)
    return np.asarray(mesh["vertices"], dtype=np.float64), np.asarray(mesh["faces"], dtype=np.int64)


def describe(V, Q, euler, input_mesh):
    """Figures of a quad(-dominant) mesh given as (k, 4) arrays (a triangle has a repeated corner)."""
    Q = np.asarray(Q)
    pure = np.array([len(set(q)) == 4 for q in Q.tolist()])
    quads = Q[pure]
    faces = Polygons.from_list([list(dict.fromkeys(q)) for q in Q.tolist()])
    summary = topology.info(V, faces)
    quality = quad_quality(V, quads) if len(quads) else None
    edges = np.sort(np.stack([quads, np.roll(quads, -1, axis=1)], -1).reshape(-1, 2), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    boundary = np.zeros(len(V), bool)
    boundary[unique[counts == 1].ravel()] = True
    valence = np.bincount(Q.ravel(), minlength=len(V))
    irregular = int(((valence > 0) & ~boundary & (valence != 4)).sum())
    V0, F0 = input_mesh
    diagonal = float(np.linalg.norm(V0.max(0) - V0.min(0)))
    hausdorff = geometry.hausdorff_distance(V, faces.fan_triangles()[0], V0, F0) / diagonal
    return dict(quads=int(pure.sum()), non_quads=int((~pure).sum()), irregular=irregular, hausdorff=hausdorff,
                angle=float(np.abs(quality.angles - 90).mean()) if quality else float("nan"),
                max_angle=float(np.abs(quality.angles - 90).max()) if quality else float("nan"),
                jacobian=float(quality.scaled_jacobian.min()) if quality else float("nan"),
                valid=bool(summary.is_manifold and summary.is_oriented and summary.euler_characteristic == euler))


#: Instant Meshes asked for a quarter of the target (it returns about 4× the vertex count asked for).
IM_QUARTER = "Instant Meshes/4"


def side_by_side(bench, im, qf, V, F, target, euler, options):
    """Times quadrangulate(V, F, target_faces=target, **options) and the peers at the same target,
    prints the report and describe()'s figures per tool; returns meshsmith's result and the figures."""
    bench.time("meshsmith", lambda: quadrangulate(V, F, target_faces=target, **options))
    if im:
        bench.time("Instant Meshes", lambda: instant_meshes(im, V, F, target))
        # asked for a quarter, Instant Meshes returns about the count the others return: its
        # figures at the same output size
        bench.time(IM_QUARTER, lambda: instant_meshes(im, V, F, target // 4))
    if qf:
        bench.time("QuadriFlow", lambda: quadriflow(qf, V, F, target))
    bench.report()
    result = bench.output("meshsmith")
    figures = {"meshsmith": describe(result.V, result.Q, euler, (V, F))}
    for peer in ("Instant Meshes", IM_QUARTER, "QuadriFlow"):
        if peer in bench.outputs:
            figures[peer] = describe(*bench.output(peer), euler, (V, F))
    print_figures(figures, euler)
    return result, figures


def print_figures(figures, euler):
    """One row of describe()'s figures per tool."""
    print(f"  {'tool':16s} {'quads':>6s} {'non-quads':>9s} {'irregular':>9s} {'|angle-90|':>10s} {'max':>6s} {'min SJ':>7s} "
          f"{'Hausdorff':>9s}  valid (manifold, oriented, χ={euler})")
    for tool, f in figures.items():
        print(f"  {tool:16s} {f['quads']:6d} {f['non_quads']:9d} {f['irregular']:9d} {f['angle']:10.2f} {f['max_angle']:6.1f} "
              f"{f['jacobian']:7.3f} {f['hausdorff']:9.4f}  {f['valid']}")


def main():
    im = optional("pynanoinstantmeshes")
    qf = optional("pyQuadriFlow.pyQuadriFlow")
    cases = [("torus", datasets.torus(1.0, 0.4, 48, 20), 300)]
    names = ["spot.obj", "fertility.off", "kitten.off", "fandisk.obj", "rocker-arm.obj", "pmp-bunny.off"]
    for name in (["spot.obj"] if size(False, True) else names):
        mesh = shared_mesh(name)
        if mesh is not None:
            cases.append((name, mesh, 3000))
    for name, (V, F), target in cases:
        V, F = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
        euler = topology.euler_characteristic(F)
        case = f"quadrangulate {name} ({len(F):,} F) to {target:,} quads"
        bench = Benchmark("quadrangulation", case, repeats=3)
        result, figures = side_by_side(bench, im, qf, V, F, target, euler, {})
        report = result.report
        print(f"  meshsmith: {len(report.singular_vertices)} singularities (index sum {int(report.singular_indices.sum())}), "
              f"MIQ flips {report.flipped_before} → {report.flipped_after} (merge distance "
              f"{report.merge_distance / report.target_edge_length:.1f} quad edges, {report.miq_attempts} MIQ solves), "
              f"extraction complete: {report.extraction.complete}, left out {report.extraction.squares_inconsistent} "
              f"squares, min scaled Jacobian {report.min_scaled_jacobian_extracted:.3f} → {report.min_scaled_jacobian:.3f} "
              f"({report.relaxed_vertices} vertices relaxed), MIQ map's mean |μ| {report.map_distortion:.3f}")
        T = np.concatenate([result.Q[:, [0, 1, 2]], result.Q[:, [0, 2, 3]]])
        bench.check("meshsmith: non-quad faces + non-manifold + unoriented",
                    figures["meshsmith"]["non_quads"] + (not topology.is_manifold(T)) + (not topology.is_oriented(T)), 0)
        bench.check("meshsmith: |quads − target| / target", abs(len(result.Q) - target) / target,
                    0.4 if name == "torus" else 0.1)
        bench.check("meshsmith: MIQ flips left + (not complete) + (min scaled Jacobian <= 0)",
                    report.flipped_after + (not report.extraction.complete) + (not report.min_scaled_jacobian > 0), 0)
        # the issue's comparison at the same output size: fewer irregular vertices, angles as close to 90°
        for peer in (IM_QUARTER, "QuadriFlow") if name != "torus" else ():
            if peer in figures:
                ours, theirs = figures["meshsmith"], figures[peer]
                bench.check(f"meshsmith irregular vertices − {peer}'s + 1 (≤ 0: fewer)",
                            max(0, ours["irregular"] - theirs["irregular"] + 1), 0)
                bench.check(f"meshsmith mean |angle − 90°| − {peer}'s (≤ 0)", max(0.0, ours["angle"] - theirs["angle"]), 0)
        if name == "torus":
            bench.check("torus: irregular vertices + (χ ≠ 0)",
                        figures["meshsmith"]["irregular"] + (not report.extraction.complete), 0)
    feature_cases(im, qf)
    spectral_cases(im, cases[:1])


def feature_fractions(V, F, UV, Vq, Q, length, sharp_angle):
    """Of the edges whose dihedral angle exceeds sharp_angle: the fraction of their length on an
    integer iso-line of UV (both ends' same coordinate equal and an integer to 1e-6 on some side:
    a line of quad edges), and the fraction of their midpoints within 1e-6 and within 0.01 quad
    edges (`length`) of a quad edge of (Vq, Q) in 3D (quad edges are chords of curved features)."""
    field = cross_field(V, F, sharp_angle=sharp_angle)
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    ef = field.edge_faces
    sharp = (ef[:, 1] >= 0) & (np.einsum("ij,ij->i", n[ef[:, 0]], n[ef[:, 1]]) < np.cos(np.radians(sharp_angle)))
    edges = field.edges[sharp]
    on_line = np.zeros(len(edges), dtype=bool)
    for k, ((i, j), faces) in enumerate(zip(edges, ef[sharp])):
        for f in faces:
            a, b = UV[f, list(F[f]).index(i)], UV[f, list(F[f]).index(j)]
            on_line[k] |= bool(np.any((np.abs(a - b) < 1e-6) & (np.abs(a - np.round(a)) < 1e-6)))
    lengths = np.linalg.norm(V[edges[:, 1]] - V[edges[:, 0]], axis=1)
    quad_edges = np.unique(np.sort(np.stack([Q, np.roll(Q, -1, axis=1)], -1).reshape(-1, 2), axis=1), axis=0)
    A, B = Vq[quad_edges[:, 0]], Vq[quad_edges[:, 1]]
    points = (V[edges[:, 0]] + V[edges[:, 1]]) / 2
    t = np.clip(np.einsum("kij,ij->ki", points[:, None] - A, B - A) / ((B - A) ** 2).sum(1), 0, 1)
    distance = np.linalg.norm(A + t[..., None] * (B - A) - points[:, None], axis=2).min(axis=1)
    return (float(lengths[on_line].sum() / lengths.sum()), float((distance < 1e-6).mean()),
            float((distance < 0.01 * length).mean()), len(edges))


def feature_cases(im, qf):
    """fandisk.obj with sharp_angle=40 (its feature edges held on integer iso-lines by MIQ) at
    3,000 quads against the peers (asked for the same count; neither has feature constraints):
    the figures above plus the fractions of feature_fractions. Checks: pure quads, no MIQ flip
    left, complete, every quad convex; ≥ 95% of the feature length on integer iso-lines. Then
    fandisk without features and with MIQ's uniform grid scale (conformal_scale=0: what the
    default's conformal scale gains), the same checks but the last."""
    mesh = shared_mesh("fandisk.obj")
    if mesh is None:
        return
    V, F = np.asarray(mesh[0], dtype=np.float64), np.asarray(mesh[1], dtype=np.int64)
    target, euler = 3000, topology.euler_characteristic(F)
    bench = Benchmark("quadrangulation", f"quadrangulate fandisk.obj ({len(F):,} F) to {target:,} quads, sharp_angle=40",
                      repeats=3)
    result, figures = side_by_side(bench, im, qf, V, F, target, euler, dict(sharp_angle=40))
    report = result.report
    on_line, exact, near, count = feature_fractions(V, F, result.UV, result.V, result.Q, report.target_edge_length, 40)
    print(f"  meshsmith: {report.feature_edges} of {count} feature edges held by MIQ, {on_line:.1%} of the feature "
          f"length on integer iso-lines; feature-edge midpoints within 1e-6 of a quad edge {exact:.1%}, within 0.01 "
          f"quad edges {near:.1%}; MIQ flips {report.flipped_before} → {report.flipped_after}, "
          f"{report.miq_attempts} MIQ solve(s), complete: {report.extraction.complete}")
    for peer in ("Instant Meshes", "QuadriFlow"):
        if peer in bench.outputs:
            Vp, Qp = bench.output(peer)
            _, exact_p, near_p, _ = feature_fractions(V, F, np.zeros((len(F), 3, 2)) + 0.5, Vp, Qp,
                                                      report.target_edge_length, 40)
            print(f"  {peer}: feature-edge midpoints within 1e-6 of a quad edge {exact_p:.1%}, within 0.01 quad edges "
                  f"{near_p:.1%}")
    bench.check("fandisk features: non-quads + MIQ flips left + (not complete) + (min scaled Jacobian <= 0)",
                figures["meshsmith"]["non_quads"] + report.flipped_after + (not report.extraction.complete)
                + (not report.min_scaled_jacobian > 0), 0)
    bench.check("fandisk features: 0.95 − feature length fraction on integer iso-lines (≤ 0)", max(0.0, 0.95 - on_line), 0)
    # without features and with a uniform grid scale (Bommes et al.'s MIQ)
    bench = Benchmark("quadrangulation", f"quadrangulate fandisk.obj ({len(F):,} F) to {target:,} quads, conformal_scale=0",
                      repeats=3)
    result, figures = side_by_side(bench, im, qf, V, F, target, euler, dict(conformal_scale=0))
    report = result.report
    bench.check("fandisk conformal_scale=0: non-quads + MIQ flips left + (not complete) + (min scaled Jacobian <= 0)",
                figures["meshsmith"]["non_quads"] + report.flipped_after + (not report.extraction.complete)
                + (not report.min_scaled_jacobian > 0), 0)


def spectral_cases(im, cases):
    """Spectral Morse–Smale quadrangulation (§5.2.1) against the MIQ pipeline and Instant Meshes at
    the same quad count ("meshsmith" is spectral_quadrangulate here, "meshsmith cells" the same with
    each cell mapped on its own, coupled=False): the torus above and the
    issue's real meshes at 2,000 quads — quick mode: spot.obj and kitten.off (genus 1); full: also
    rocker-arm.obj (genus 1), fertility.off (genus 4), cheburashka.off, pmp-bunny.off (69,666 faces,
    one round) and bumpy-cube.obj. Printed besides the figures: the eigenvector, cells, critical
    points after the persistence simplification (and how many extrema it cancelled), lines routed
    through gaps, inverted quads before and after the relaxation. Checks: pure quads, manifold,
    oriented, χ kept (0 violations); the Morse invariant #max − #saddle + #min = χ; quad count
    within 50% of the target."""
    from meshsmith.quadrangulation import spectral_quadrangulate
    names = ["spot.obj", "kitten.off"]
    if not size(False, True):
        names += ["rocker-arm.obj", "fertility.off", "cheburashka.off", "pmp-bunny.off", "bumpy-cube.obj"]
    for name in names:
        mesh = shared_mesh(name)
        if mesh is not None:
            cases = cases + [(name, mesh, 2000)]
    for name, (V, F), target in cases:
        V, F = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
        euler = topology.euler_characteristic(F)
        bench = Benchmark("quadrangulation", f"spectral quadrangulation of {name} ({len(F):,} F) to {target:,} quads",
                          repeats=1 if len(F) > 30000 else 3)
        bench.time("meshsmith", lambda: spectral_quadrangulate(V, F, target_faces=target))
        bench.time("meshsmith cells", lambda: spectral_quadrangulate(V, F, target_faces=target, coupled=False))
        bench.time("meshsmith miq", lambda: quadrangulate(V, F, target_faces=target))
        if im:
            bench.time("Instant Meshes", lambda: instant_meshes(im, V, F, target))
        bench.report()
        result = bench.output("meshsmith")
        cells = bench.output("meshsmith cells")
        figures = {"spectral": describe(result.V, result.Q, euler, (V, F)),
                   "spectral cells": describe(cells.V, cells.Q, euler, (V, F)),
                   "miq": describe(bench.output("meshsmith miq").V, bench.output("meshsmith miq").Q, euler, (V, F))}
        if "Instant Meshes" in bench.outputs:
            figures["Instant Meshes"] = describe(*bench.output("Instant Meshes"), euler, (V, F))
        print_figures(figures, euler)
        report = result.report
        print(f"  spectral: eigenvector {report.eigenvector} ({report.candidates_tried} tried, {report.traced_faces:,} faces "
              f"traced), {report.patches} cells, "
              f"{report.maxima} max / {report.saddles} saddles / {report.minima} min after cancelling "
              f"{report.cancelled_extrema} extrema, {report.refinements} refinement(s), {report.gap_routes} lines "
              f"through gaps, inverted quads {report.inverted_before_relaxing} → {report.inverted_quads} "
              f"({report.relaxed_vertices} vertices relaxed), coupled map flips {report.flipped_before} → "
              f"{report.flipped_after} ({report.repair_rounds} stiffening rounds)")
        bench.check("spectral: non-quads + invalid (manifold, oriented, χ)",
                    figures["spectral"]["non_quads"] + (not figures["spectral"]["valid"]), 0)
        bench.check("spectral: |#max − #saddle + #min − χ|",
                    abs(report.maxima - report.saddles + report.minima - euler), 0)
        bench.check("spectral: |quads − target| / target", abs(len(result.Q) - target) / target, 0.5)

    dual_loop_cases()


def dual_loop_cases():
    cases = [("torus", datasets.torus(1.0, 0.35, 48, 16), dict(curvature_weight=1.0), None)]
    spot = shared_mesh("spot.obj")
    if spot is not None:
        cases += [("spot.obj", spot, dict(align="smooth"), None), ("spot.obj", spot, dict(align="smooth"), 4.0)]
    for name, (V, F), options, penalty in cases:
        V, F = np.asarray(V, dtype=np.float64), np.asarray(F, dtype=np.int64)
        field = cross_field(V, F, **options)
        crossing = "" if penalty is None else f", parallel crossings at cost {penalty:g}"
        bench = Benchmark("quadrangulation", f"dual_loop_layout {name} ({len(F):,} F{crossing})", repeats=3)
        bench.time("meshsmith", lambda: dual_loop_layout(
            V, F, field, merge=0.0, refine=0, max_failed_seeds=2000,
            parallel_crossing_penalty=np.inf if penalty is None else penalty))
        bench.report()
        layout = bench.output("meshsmith")
        report = layout.report
        print(f"  {len(layout.singular_vertices)} singularities; {report.loops} loops, {report.crossings} coarse quads, "
              f"{report.regions} regions ({report.multi_singular_regions} with several singularities, "
              f"{report.non_disk_regions} not disks), layout χ {report.euler_layout} (input {report.euler_input}), "
              f"{report.parallel_crossings} parallel crossings, {report.low_valence_vertices} layout vertices of "
              f"valence 2, complete: {report.complete}")
        if name == "torus":
            valence = np.bincount(layout.Q.ravel(), minlength=report.regions)
            bench.check("torus: (not complete) + layout vertices of valence ≠ 4",
                        (not report.complete) + int((valence != 4).sum()), 0)
        else:
            bench.check(f"{name}: regions that are not disks", report.non_disk_regions, 0)
        if penalty is not None:
            bench.check(f"{name}: non-manifold layout edges + vertices + |χ − χ_input|",
                        report.non_manifold_edges + report.non_manifold_vertices
                        + abs(report.euler_layout - report.euler_input), 0)


if __name__ == "__main__":
    main()
