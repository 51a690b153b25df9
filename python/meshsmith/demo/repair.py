"""Demo stages of the repair chapter: the input cleaned before every other stage, and a broken
copy of it repaired (§2.4)."""
from __future__ import annotations

from typing import Any

import numpy as np

from .. import geometry, render, repair
from .context import DemoContext, Section, builtin_shape


def stage_clean(context: DemoContext) -> Section:
    """§2.4: :func:`meshsmith.repair.clean` with its defaults; the later stages see the cleaned mesh.
    Per-corner texture coordinates follow their faces (and a flipped face's corners)."""
    V, F, report = repair.clean(context.V, context.F)
    if report.changed:
        if context.uv is not None:
            uv = context.uv[report.face_map]
            uv[report.flipped] = uv[report.flipped][:, [0, 2, 1]]
            context.uv = uv
        before = f"{len(context.V):,} vertices, {len(context.F):,} faces"
        context.V, context.F = V, F
        text = (f"meshsmith.repair.clean (§2.4) changed the input ({before}) into {len(V):,} vertices, "
                f"{len(F):,} faces; the stages below use the cleaned mesh.")
    else:
        text = "meshsmith.repair.clean (§2.4) found nothing to change: the input is clean."
    figures: dict[str, object] = dict(report.counts())
    context.figures["clean"] = figures
    return Section("Cleaning", text + " Counts of each kind of change:", figures)


#: The largest input the repair stage breaks and repairs itself (larger: the built-in torus).
REPAIR_STAGE_FACES = 60_000


def broken_scan(V: np.ndarray, F: np.ndarray, seed: int = 11) -> tuple[np.ndarray, np.ndarray]:
    """A copy of (V, F) broken as scans are: up to four holes (the faces within 8% of the bounding-box
    diagonal of four random face centres), one vertex pushed through the surface along its
    inward normal (a quarter of the diagonal: self-intersections), 3% of the faces flipped and
    20 faces duplicated; the vertices the holes leave unused are removed."""
    rng = np.random.default_rng(seed)
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    centres = V[F].mean(axis=1)
    keep = np.ones(len(F), dtype=bool)
    for centre in centres[rng.choice(len(F), 4, replace=False)]:
        keep &= np.linalg.norm(centres - centre, axis=1) > 0.08 * diagonal
    faces = F[keep].copy()
    points = V.copy()
    used = np.unique(faces)
    poked = int(used[rng.integers(len(used))])
    points[poked] -= 0.25 * diagonal * geometry.vertex_normals(V, F)[poked]
    flip = rng.random(len(faces)) < 0.03
    faces[flip] = faces[flip][:, ::-1]
    faces = np.vstack([faces, faces[rng.choice(len(faces), 20, replace=False)]])
    points, faces, _ = repair.remove_unreferenced(points, faces)
    return points, faces


def stage_repair(context: DemoContext) -> Section:
    """§2.4: a broken copy of the input (:func:`broken_scan`: holes, a vertex poked through,
    flipped and duplicated faces) through the whole repair: :func:`meshsmith.repair.clean`,
    :func:`~meshsmith.repair.remove_self_intersections`, :func:`~meshsmith.repair.fill_holes`
    (which turns a component its fills close outward, counted as reoriented_components); the
    defects :func:`~meshsmith.repair.find_defects` counts before and after, pictures of
    both. The later stages keep the unbroken input. An input of more than
    :data:`REPAIR_STAGE_FACES` faces, or with a non-orientable component, gives way to the
    built-in torus (the stage shows the repair, not the input's size)."""
    source, (V0, F0) = context.name, (context.V, context.F)
    if len(F0) > REPAIR_STAGE_FACES or repair.orient_faces(V0, F0).non_orientable_components:
        source, V0, F0, _ = builtin_shape()
    V, F = broken_scan(V0, F0)
    before = repair.find_defects(V, F)
    V1, F1, cleaned = repair.clean(V, F)
    V1, F1, removal = repair.remove_self_intersections(V1, F1)
    V1, F1, filled = repair.fill_holes(V1, F1)
    after = repair.find_defects(V1, F1)
    figures: dict[str, Any] = {f"before: {name}": value for name, value in before.counts().items() if value}
    figures.update({f"clean: {name}": value for name, value in cleaned.counts().items() if value})
    figures.update({f"self-intersections: {name}": value for name, value in removal.counts().items()})
    figures.update({f"fill holes: {name}": value for name, value in filled.counts().items()})
    if filled.patches:
        figures["fill holes: largest dihedral angle in a patch (degrees)"] = max(
            p.max_dihedral_angle for p in filled.patches)
        figures["fill holes: patch edge length / surrounding ring"] = [
            round(p.edge_length_ratio, 3) for p in filled.patches]
    figures.update({f"after: {name}": value for name, value in after.counts().items()})
    figures["input"] = source
    context.figures["repair"] = figures
    images = []
    for name, (W, G), caption in (
            ("broken", (V, F), f"the broken copy: {before.boundary_loops} holes, "
                               f"{before.self_intersecting_pairs} self-intersecting pairs, "
                               f"{before.flipped_faces} flipped faces (the warm tint is the back side)"),
            ("repaired", (V1, F1), f"repaired: {after.boundary_loops} holes, "
                                   f"{after.self_intersecting_pairs} self-intersecting pairs, "
                                   f"{filled.filled} patches")):
        file_name = f"repair_{name}.png"
        render.render(W, G, context.out / file_name, size=(700, 520), title=name)
        images.append((file_name, caption))
    return Section("Repairing a broken scan",
                   f"meshsmith.repair (§2.4) on a copy of {source} broken as scans are (up to four holes, a vertex "
                   "pushed through the surface, 3% of the faces flipped, 20 duplicated): clean (duplicates "
                   "removed, non-manifold splits, orientation), remove_self_intersections (the intersecting "
                   "faces cut out and the holes they leave filled), fill_holes (Liepa, refined and faired; "
                   "a component the fills close is turned outward). "
                   "The defects find_defects counts before and after:", figures, images)
