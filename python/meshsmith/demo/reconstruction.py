"""Demo stage of the reconstruction chapter: a noisy scan → normals → orientation → screened
Poisson (§2.2, §3.1)."""
from __future__ import annotations

import numpy as np

from .. import datasets, geometry, points, reconstruction, render, topology
from .context import DemoContext, Section


def stage_poisson(context: DemoContext) -> Section:
    """§2.2: 20,000 noisy samples of the input, PCA normals oriented along a spanning tree, screened
    Poisson at depth 7, and its distance to the input surface."""
    diagonal = float(np.linalg.norm(context.V.max(axis=0) - context.V.min(axis=0)))
    P, _ = datasets.sample_points(context.V, context.F, 20_000, seed=1)
    P = P + np.random.default_rng(1).normal(scale=0.001 * diagonal, size=P.shape)
    N = points.orient_normals(P, points.estimate_normals(P, k=16), k=16)
    mesh = reconstruction.poisson(P, N, depth=7)
    render.render(mesh.V, mesh.F, context.out / "poisson.png", scalar=mesh.density, scalar_label="samples nearby",
                  size=(900, 650), title="screened Poisson of 20k noisy samples, depth 7")
    figures = {"Poisson: vertices": len(mesh.V), "Poisson: triangles": len(mesh.F),
               "Poisson: closed manifold": bool(topology.is_manifold(mesh.F) and not topology.boundary_loops(mesh.F)),
               "Poisson: Euler characteristic": topology.euler_characteristic(mesh.F),
               "Poisson: mean distance / bounding-box diagonal":
                   geometry.mean_surface_distance(mesh.V, mesh.F, context.V, context.F) / diagonal,
               "Poisson: Hausdorff distance / bounding-box diagonal":
                   geometry.hausdorff_distance(mesh.V, mesh.F, context.V, context.F) / diagonal}
    context.figures["poisson"] = figures
    return Section("Screened Poisson reconstruction", "meshsmith.reconstruction (§2.2): points sampled from "
                   "the input with noise of 0.1% of its diagonal get PCA normals (meshsmith.points), oriented "
                   "along a minimum spanning tree; screened Poisson turns them into a closed surface, "
                   "coloured by the sample density that trim_by_density uses.", figures,
                   [("poisson.png", "Poisson surface, coloured by sample density")])
