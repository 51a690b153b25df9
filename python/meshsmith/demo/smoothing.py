"""Demo stage of the smoothing chapter: denoising a noisy copy of the input (§3.0.1–3.0.2)."""
from __future__ import annotations

from typing import Any

import numpy as np

from .. import datasets, geometry, render, smoothing, topology
from .context import DemoContext, Section


def stage_smoothing(context: DemoContext) -> Section:
    """§3.0.1–3.0.2: noise along the normals (0.3 × the mean edge length) removed by 10 iterations of
    plain Laplacian and of Taubin smoothing; the mean distance to the clean input before and after,
    and the volume each keeps (closed inputs)."""
    V, F = context.V, context.F
    noisy, _ = datasets.noisy(V, F, sigma=0.3, seed=17)
    results = {"noisy": noisy,
               "Laplacian": smoothing.laplacian(noisy, F, iterations=10),
               "Taubin": smoothing.taubin(noisy, F, iterations=10)}
    clean = geometry.SurfaceDistance(V, F)
    closed = not topology.boundary_loops(F) and topology.is_manifold(F)
    volume = geometry.volume(V, F) if closed else 0.0
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    figures: dict[str, Any] = {}
    images: list[tuple[str, str]] = []
    for name, W in results.items():
        distance = float(clean.distances(W).mean())
        figures[f"{name}: mean distance to the clean surface / bounding-box diagonal"] = distance / diagonal
        caption = f"{name}: mean distance to the clean surface {100 * distance / diagonal:.3g}% of the diagonal"
        if volume:
            change = geometry.volume(W, F) / volume - 1
            figures[f"{name}: volume change"] = change
            caption += f", volume {100 * change:+.2f}%"
        file_name = f"smoothing_{name.lower()}.png"
        render.render(W, F, context.out / file_name, size=(700, 520), title=name)
        images.append((file_name, caption))
    context.figures["smoothing"] = figures
    return Section("Smoothing", "meshsmith.smoothing (§3.0.1–3.0.2): the input with Gaussian noise along its "
                   "normals (σ = 0.3 × the mean edge length), then 10 iterations of the uniform umbrella "
                   "operator: plain Laplacian steps (λ = 0.5) shrink the shape with the noise; Taubin's λ|μ "
                   "filter (0.5, −0.53) removes the noise and keeps the volume.", figures, images)
