"""Demo stage of the registration chapter: two noisy scans of the input aligned by ICP (§2.3.1)."""
from __future__ import annotations

from typing import Any

import numpy as np

from .. import datasets, geometry, registration, render
from .context import DemoContext, Section


def stage_registration(context: DemoContext) -> Section:
    """§2.3.1: two scans sampled from the input (3000 and 6000 points, 0.5% noise, the first with
    15% outliers), the first moved by 25° and 8% of the diagonal, aligned back by trimmed
    point-to-plane ICP; pictures of the input and its moved copy before and after. The error is
    measured as the distance of the aligned scan to the input surface, which is defined also for
    a shape with a symmetry (the built-in torus turns about its axis onto itself, so a rotation
    error about that axis is neither observable nor an error)."""
    V, F = context.V, context.F
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    pair = datasets.scan_pair(V, F, n_source=3000, n_target=6000, noise=0.005, outliers=0.15, margin=0.0,
                              angle=25.0, translation=0.08, seed=16)
    source, target, normals, motion = pair.source, pair.target, pair.target_normals, pair.motion
    scan = registration.apply_transform(np.linalg.inv(motion), source[:-pair.n_outliers])   # the surface samples
    result = registration.icp(source, target, method="point_to_plane", target_normals=normals, trim=0.8,
                              max_iterations=50)
    residual = result.transform @ motion
    surface = geometry.SurfaceDistance(V, F)
    aligned = registration.apply_transform(residual, scan)       # the scan's own points, outliers left out
    before = surface.distances(registration.apply_transform(motion, scan))
    after = surface.distances(aligned)
    images: list[tuple[str, str]] = []
    for name, T, caption in (("registration_before.png", motion, "before: the input (blue) and the moved scan's mesh (red)"),
                             ("registration_after.png", residual, "after ICP: the moved mesh mapped back")):
        both_V = np.vstack([V, registration.apply_transform(T, V)])
        both_F = np.vstack([F, F + len(V)])
        side = np.r_[np.zeros(len(V)), np.ones(len(V))]
        render.render(both_V, both_F, context.out / name, size=(700, 520), scalar=side, cmap="coolwarm",
                      colorbar=False, title=caption.split(":")[0])
        images.append((name, caption))
    figures: dict[str, Any] = {
        "source points (with outliers), target points": (len(source), len(target)),
        "iterations, converged, stop": (result.iterations, result.converged, result.stop),
        "RMS of the inlier pairs / diagonal": result.rms / diagonal,
        "inlier fraction": result.inlier_fraction,
        "mean distance of the scan to the surface / diagonal, before": float(before.mean() / diagonal),
        "mean distance of the scan to the surface / diagonal, after (noise: 0.004)": float(after.mean() / diagonal),
    }
    context.figures["registration"] = figures
    return Section("Registration", "meshsmith.registration.icp (§2.3.1): a noisy scan of the input with 15% "
                   "outliers, moved by 25° and 8% of the diagonal, aligned onto a second scan by trimmed "
                   "point-to-plane ICP (80% of the closest pairs). Once aligned, the trimmed pairs flip at the "
                   "trim threshold and the RMS wanders at the noise level: the stall/cycle test ends it (stop), "
                   "at the pose of least RMS. On a shape with a symmetry (the built-in torus turns onto itself "
                   "about its axis) the distance of the aligned scan to the surface is what tells the "
                   "alignment.", figures, images)
