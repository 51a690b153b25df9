"""Demo stages of the tessellation chapter: refinement, Voronoi, crusts (§2.1)."""
from __future__ import annotations

import numpy as np

from .. import datasets, geometry, render, tessellation, topology
from .context import DemoContext, Section


def stage_tessellation(context: DemoContext) -> Section:
    """§2.1.1: Delaunay refinement of a square with a square hole at 30°, and a Voronoi diagram."""
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]], float)
    segments = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
    V2, F, steiner = tessellation.refine(corners, segments, holes=[[0.5, 0.5]], min_angle=30.0, max_area=0.002)
    angles = tessellation.triangle_angles(V2, F)
    render.plot_planar(context.out / "refinement.png", triangles=(V2, F), highlight=V2[len(corners):],
                       size=(650, 650), title=f"refinement at 30°: {steiner} Steiner points")
    sites = np.random.default_rng(7).random((80, 2))
    diagram = tessellation.voronoi(sites)
    render.plot_planar(context.out / "voronoi.png", polygons=diagram.cells, points=sites, size=(650, 650),
                       title="Voronoi diagram of 80 random sites")
    figures = {"refinement: triangles": len(F), "refinement: Steiner points": int(steiner),
               "refinement: smallest angle (degrees)": float(np.min(angles)),
               "Voronoi: vertices": len(diagram.vertices)}
    context.figures["tessellation"] = figures
    return Section("Tessellation", "meshsmith.tessellation (§2.1.1): Ruppert/Chew refinement of a "
                   "square with a hole to a 30° minimum angle (Steiner points in red), and a Voronoi "
                   "diagram clipped to the sites' enlarged bounding box.", figures,
                   [("refinement.png", "quality triangulation, every angle ≥ 30°"),
                    ("voronoi.png", "Voronoi cells")])


def stage_crust(context: DemoContext) -> Section:
    """§2.1.3: the crust of samples of a closed curve, and the Cocone crust of surface samples of
    the input mesh, with its distance to the input surface."""
    t = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)
    radius = 1.0 + 0.35 * np.cos(5 * t)
    curve = np.column_stack([radius * np.cos(t), radius * np.sin(t)])
    edges = tessellation.crust(curve)
    render.plot_planar(context.out / "crust_2d.png", segments=(curve, edges), points=curve, size=(650, 650),
                       title=f"crust of {len(curve)} samples of a star")
    samples, _ = datasets.sample_points(context.V, context.F, 4000, seed=0)
    V, F = tessellation.crust_3d(samples)
    render.render(V, F, context.out / "crust_3d.png", wireframe=True, size=(900, 650),
                  title="Cocone crust of 4000 surface samples")
    distance = geometry.hausdorff_distance(V, F, context.V, context.F)
    diagonal = float(np.linalg.norm(context.V.max(axis=0) - context.V.min(axis=0)))
    figures = {"2D crust: edges (samples)": f"{len(edges)} ({len(curve)})",
               "3D crust: triangles": len(F), "3D crust: manifold": topology.is_manifold(F),
               "3D crust: Euler characteristic": topology.euler_characteristic(V, F),
               "3D crust: Hausdorff distance / bounding-box diagonal": distance / diagonal}
    context.figures["crust"] = figures
    return Section("Reconstruction by Voronoi filtering", "meshsmith.tessellation (§2.1.3): the crust "
                   "joins each sample of a curve to its two neighbours; in 3D the Cocone crust rebuilds "
                   "a surface from points sampled on the input mesh.", figures,
                   [("crust_2d.png", "2D crust"), ("crust_3d.png", "3D Cocone crust")])
