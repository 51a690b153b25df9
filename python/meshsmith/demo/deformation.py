"""Demo stage of the deformation chapter: one handle moved three ways (§3.1)."""
from __future__ import annotations

import time
from typing import Any

import numpy as np

from .. import deformation, render
from .context import DemoContext, Section


def stage_deformation(context: DemoContext) -> Section:
    """§3.1: the tenth of the input with the largest x is the handle, turned by 0.5 rad about the y
    axis and lifted by a fifth of the x extent, the tenth with the smallest x is fixed; the bi-Laplacian deformation (Δ²d = 0), its
    detail-preserving variant and 10 ARAP iterations, with their precompute and solve times and the
    ARAP energy each leaves (lower: closer to a rigid motion of every vertex's neighbourhood)."""
    V, F = context.V, context.F
    x = V[:, 0]
    handle = np.flatnonzero(x >= np.quantile(x, 0.9))
    fixed = np.flatnonzero(x <= np.quantile(x, 0.1))
    centre = V[handle].mean(axis=0)
    c, s = np.cos(0.5), np.sin(0.5)
    T = np.eye(4)
    T[:3, :3] = [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    T[:3, 3] = centre - T[:3, :3] @ centre + [0.0, 0.0, 0.2 * float(np.ptp(x))]
    moved = V[handle] @ T[:3, :3].T + T[:3, 3]
    figures: dict[str, Any] = {}
    results: dict[str, np.ndarray] = {}
    for name, details in (("bi-Laplacian", False), ("bi-Laplacian with details", True)):
        start = time.perf_counter()
        deformer = deformation.Deformer(V, F, handle, fixed, details=details)
        precompute = time.perf_counter() - start
        start = time.perf_counter()
        results[name] = deformer.transform(T)
        figures[f"{name}: precompute [ms]"] = 1e3 * precompute
        figures[f"{name}: transform [ms]"] = 1e3 * (time.perf_counter() - start)
    start = time.perf_counter()
    arap = deformation.ArapDeformer(V, F, np.concatenate([handle, fixed]))
    figures["ARAP: precompute [ms]"] = 1e3 * (time.perf_counter() - start)
    start = time.perf_counter()
    results["ARAP, 10 iterations"] = arap.solve(np.concatenate([moved, V[fixed]]), 10)
    figures["ARAP: 10 iterations [ms]"] = 1e3 * (time.perf_counter() - start)
    images: list[tuple[str, str]] = []
    largest = max(float(np.linalg.norm(U - V, axis=1).max()) for U in results.values())
    for index, (name, U) in enumerate(results.items()):
        energy = arap.energy(U)
        figures[f"{name}: ARAP energy"] = energy
        file_name = f"deformation_{index}.png"
        render.render(U, F, context.out / file_name, size=(700, 520), title=name,
                      scalar=np.linalg.norm(U - V, axis=1), scalar_range=(0.0, largest or 1.0),
                      scalar_label="displacement")
        images.append((file_name, f"{name}: ARAP energy {energy:.4g}"))
    context.figures["deformation"] = figures
    return Section("Deformation", f"meshsmith.deformation (§3.1): {len(handle)} handle vertices (the top tenth) "
                   f"turned by 0.5 rad and lifted, {len(fixed)} fixed (the bottom tenth); colour: how far each "
                   "vertex moved.", figures, images)
