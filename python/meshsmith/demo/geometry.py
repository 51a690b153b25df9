"""Demo stage of the geometry chapter: curvature and the Gauss–Bonnet check (§1.2.4)."""
from __future__ import annotations

import numpy as np

from .. import geometry, render, topology
from .context import DemoContext, Section


def stage_curvature(context: DemoContext) -> Section:
    """§1.2.4: mean curvature from the cotan Laplacian, Gaussian curvature from the angle defect,
    with the Gauss–Bonnet check Σ K_i = 2πχ."""
    V, F = context.V, context.F
    H, _ = geometry.mean_curvature(V, F)
    K = geometry.gaussian_curvature(V, F, pointwise=True)
    total_K = float(geometry.gaussian_curvature(V, F).sum())
    chi = topology.euler_characteristic(V, F)
    render.render(V, F, context.out / "mean_curvature.png", scalar=H, scalar_label="mean curvature H",
                  cmap="coolwarm", size=(900, 650), title="mean curvature")
    render.render(V, F, context.out / "gaussian_curvature.png", scalar=K,
                  scalar_label="Gaussian curvature K", cmap="coolwarm", size=(900, 650),
                  title="Gaussian curvature")
    figures = {"mean curvature H (median)": float(np.median(H)),
               "mean curvature H (min, max)": (float(H.min()), float(H.max())),
               "Gaussian curvature K (min, max)": (float(K.min()), float(K.max())),
               "sum of angle defects": total_K, "2 pi chi": 2 * np.pi * chi,
               "Gauss-Bonnet error": abs(total_K - 2 * np.pi * chi)}
    context.figures["curvature"] = figures
    return Section("Curvature", "meshsmith.geometry (§1.2.4): mean curvature from the cotangent "
                   "Laplacian, Gaussian curvature from the angle defect; on a closed mesh the angle "
                   "defects sum to 2πχ (Gauss–Bonnet).", figures,
                   [("mean_curvature.png", "mean curvature (positive: convex)"),
                    ("gaussian_curvature.png", "Gaussian curvature (red: elliptic, blue: hyperbolic)")])
