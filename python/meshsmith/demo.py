"""`meshsmith demo`: run every chapter on one mesh and write an HTML report with pictures.

Each stage is a function `stage(context) -> Section`, listed in STAGES in pipeline order; later
chapters add their stage (decimation, curvature, parametrization, ...) to that list. A stage
writes its outputs into `context.out` and returns the HTML section that shows them.
"""
from __future__ import annotations

import html
import json
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


@dataclass
class DemoContext:
    out: Path
    name: str                 # what the input is, for captions
    V: np.ndarray
    F: np.ndarray
    uv: np.ndarray | None = None   # (m, 3, 2) per-corner texture coordinates, when the shape has natural ones
    figures: dict = field(default_factory=dict)  # every stage's numbers, saved as results.json


@dataclass
class Section:
    title: str
    text: str
    table: dict[str, object] = field(default_factory=dict)
    images: list[tuple[str, str]] = field(default_factory=list)  # (file name, caption)


def builtin_shape() -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
    """The default demo input: a torus (genus 1) with its angular texture coordinates.

    The texture coordinates are per corner, (m, 3, 2): the angles wrap around twice on a torus,
    so each triangle that straddles a seam gets its corners unwrapped onto one side of it.
    """
    from . import datasets
    V, F = datasets.torus(major_radius=1.0, minor_radius=0.4, n_major=96, n_minor=48)
    around = np.arctan2(V[:, 1], V[:, 0])                       # angle around the main axis
    ring = np.hypot(V[:, 0], V[:, 1]) - 1.0
    tube = np.arctan2(V[:, 2], ring)                            # angle around the tube
    uv = np.column_stack([(around + np.pi) / (2 * np.pi), (tube + np.pi) / (2 * np.pi)])
    corners = uv[F]                                             # (m, 3, 2)
    straddles = corners.max(axis=1, keepdims=True) - corners.min(axis=1, keepdims=True) > 0.5
    corners = np.where(straddles & (corners < 0.5), corners + 1.0, corners)
    return "built-in torus (R = 1, r = 0.4)", V, F, corners


def stage_input(context: DemoContext) -> Section:
    from . import io, topology
    io.write_mesh(context.out / "input.ply", context.V, context.F)
    summary = topology.info(context.V, context.F)
    context.figures["input"] = summary.as_dict()
    table = {key: value for key, value in summary.as_dict().items()}
    return Section("Input", f"{html.escape(context.name)}, written as <code>input.ply</code>; "
                            "the figures of <code>meshsmith info</code>.", table)


def stage_pictures(context: DemoContext) -> Section:
    from . import render
    images = []
    render.render(context.V, context.F, context.out / "shaded.png",
                  views=["three-quarter", "front", "top", "left"], size=(520, 400), title=context.name)
    images.append(("shaded.png", "smooth shading from four views"))
    render.render(context.V, context.F, context.out / "wireframe.png", wireframe=True,
                  size=(900, 650), title="wireframe")
    images.append(("wireframe.png", "the triangles"))
    if context.uv is not None:
        render.render(context.V, context.F, context.out / "checkerboard.png", uv=context.uv,
                      size=(900, 650), title="texture coordinates")
        images.append(("checkerboard.png", "checkerboard texture through the shape's texture coordinates"))
    return Section("Pictures", "meshsmith.render: shaded views, wireframe, a texture.", {}, images)


def stage_curvature(context: DemoContext) -> Section:
    """§1.2.4: mean curvature from the cotan Laplacian, Gaussian curvature from the angle defect,
    with the Gauss–Bonnet check Σ K_i = 2πχ."""
    from . import geometry, render, topology
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


def stage_tessellation(context: DemoContext) -> Section:
    """§2.1.1: Delaunay refinement of a square with a square hole at 30°, and a Voronoi diagram."""
    from . import render, tessellation
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
    from . import datasets, geometry, render, tessellation, topology
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


def stage_decimation(context: DemoContext) -> Section:
    """§4.2–4.3: QEM decimation of the input to 10% and 1% of its faces (read from one progressive
    mesh), with the Hausdorff distance of each level to the input."""
    from . import decimation, geometry, render, topology
    from . import InputError
    V, F = context.V, context.F
    diagonal = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    images, figures = [], {}
    try:
        pm = decimation.progressive_mesh(V, F, target_faces=max(4, len(F) // 100))
        pm.save(context.out / "decimation.pm")
        figures["progressive mesh: vertex splits"] = pm.n_splits
        level = lambda percent: pm.at(max(pm.face_range[0], len(F) * percent // 100))  # noqa: E731
    except InputError as error:   # e.g. a non-manifold --input: decimate each level directly
        figures["progressive mesh"] = f"not built: {error}"
        level = lambda percent: decimation.decimate(V, F, ratio=percent / 100)  # noqa: E731
    for percent in (100, 10, 1):
        Vd, Fd = level(percent)
        name = f"decimated_{percent}.png"
        distance = float(geometry.hausdorff_distance(Vd, Fd, V, F)) if percent < 100 else 0.0
        render.render(Vd, Fd, context.out / name, wireframe=True, size=(700, 520),
                      title=f"{percent}%: {len(Fd)} faces")
        images.append((name, f"{percent}% of the faces ({len(Fd)}), Hausdorff distance "
                             f"{100 * distance / diagonal:.3g}% of the bounding-box diagonal"))
        figures[f"{percent}%: faces"] = len(Fd)
        figures[f"{percent}%: Hausdorff distance / bounding-box diagonal"] = distance / diagonal
        figures[f"{percent}%: manifold, Euler characteristic"] = (topology.is_manifold(Fd),
                                                                 topology.euler_characteristic(Vd, Fd))
    context.figures["decimation"] = figures
    return Section("Decimation", "meshsmith.decimation (§4.2–4.3): greedy edge collapses ordered by error "
                   "quadrics, recorded as a progressive mesh (<code>decimation.pm</code>) from which each "
                   "level of detail is read; the Hausdorff distance is measured to the input.", figures, images)



def stage_parametrization(context: DemoContext) -> Section:
    """§5.1: the input cut to a disk (§5.2.2) and flattened by Tutte's embedding, LSCM and the
    stretch-minimizing map, with pictures and distortion."""
    from .cli import parametrization_picture
    from . import parametrization
    figures, images = {}, []
    for method in ("tutte", "lscm", "stretch"):
        result = parametrization.parametrize(context.V, context.F, method)
        name = f"parametrization_{method}.png"
        parametrization_picture(context.out / name, result, f"checkerboard through the {method} map")
        images.append((name, f"{parametrization.PARAMETRIZATION_METHODS[method]}: UV layout coloured by "
                             "angle distortion, and the surface under a checkerboard"))
        for key, value in result.summary().items():
            if key != "method":
                figures[f"{method}: {key}"] = value
    context.figures["parametrization"] = figures
    return Section("Parametrization", "meshsmith.parametrization (§5.1): the mesh is cut into a "
                   "topological disk along a spanning-tree cut graph (§5.2.2, only if it is not one "
                   "already), then flattened. Tutte's map is bijective but stretches; LSCM keeps angles; "
                   "the stretch-minimizing map evens out the area.", figures, images)


STAGES = [stage_input, stage_pictures, stage_curvature, stage_tessellation, stage_crust, stage_decimation,
          stage_parametrization]


def run_demo(out: Path, input_path: str | None = None, progress=None) -> Path:
    """Run every stage and write `out/index.html`; returns its path.

    input_path: a mesh file to use instead of the built-in shape. progress: an optional
    `(fraction, stage) -> bool` callback, told at the start and end of each stage.
    """
    from . import core, io
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if input_path:
        V, F = io.read_mesh(input_path)
        context = DemoContext(out, Path(input_path).name, V, F)
    else:
        name, V, F, uv = builtin_shape()
        context = DemoContext(out, name, V, F, uv)
    sections, timings = [], {}
    for index, stage in enumerate(STAGES):
        label = stage.__name__.removeprefix("stage_")
        if progress:
            progress(index / len(STAGES), label)
        start = time.perf_counter()
        sections.append(stage(context))
        timings[label] = time.perf_counter() - start
    if progress:
        progress(1.0, "done")
    context.figures["seconds_per_stage"] = timings
    (out / "results.json").write_text(json.dumps(context.figures, indent=2, default=str))
    report = out / "index.html"
    report.write_text(_html(context, sections, timings, core.version(), core.dependency_versions()))
    return report


def _html(context, sections, timings, version, dependencies) -> str:
    def cell(value):
        if isinstance(value, float):
            return f"{value:.6g}"
        if isinstance(value, (list, tuple)):
            return ", ".join(cell(v) for v in value)
        return html.escape(str(value))

    parts = [f"""<!doctype html><html><head><meta charset="utf-8"><title>meshsmith demo</title>
<style>body{{font-family:system-ui,sans-serif;max-width:1000px;margin:2em auto;color:#222}}
h1{{font-weight:600}} h2{{border-bottom:1px solid #ddd;padding-bottom:.2em;margin-top:2em}}
table{{border-collapse:collapse;font-size:.9em}} td{{padding:.15em .8em;border-bottom:1px solid #eee}}
td:first-child{{color:#555}} figure{{margin:1em 0}} img{{max-width:100%;border:1px solid #eee}}
figcaption{{color:#555;font-size:.9em}} .meta{{color:#777;font-size:.85em}}</style></head><body>
<h1>meshsmith demo</h1>
<p class="meta">meshsmith {html.escape(version)} &middot; input: {html.escape(context.name)} &middot;
{len(context.V)} vertices, {len(context.F)} faces &middot; built with
{html.escape(", ".join(f"{k} {v}" for k, v in dependencies.items()))}</p>"""]
    for section, seconds in zip(sections, timings.values()):
        parts.append(f"<h2>{html.escape(section.title)}</h2><p>{section.text} "
                     f"<span class='meta'>({seconds:.2f} s)</span></p>")
        if section.table:
            rows = "".join(f"<tr><td>{html.escape(str(k))}</td><td>{cell(v)}</td></tr>"
                           for k, v in section.table.items())
            parts.append(f"<table>{rows}</table>")
        for image, caption in section.images:
            parts.append(f"<figure><img src='{html.escape(image)}' alt='{html.escape(caption)}'>"
                         f"<figcaption>{html.escape(caption)}</figcaption></figure>")
    parts.append("</body></html>")
    return "\n".join(parts)
