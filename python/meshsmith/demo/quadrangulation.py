"""Demo stage of the quadrangulation chapter: cross field → MIQ → quad extraction (§5.2.2)."""
from __future__ import annotations

import numpy as np

from .. import InputError, render
from ..quadrangulation import quadrangulate
from .context import DemoContext, Section


def stage_quadrangulation(context: DemoContext) -> Section:
    """§5.2.2: the input remeshed into about 1,000 quads, with the seamless map's grid on the input
    and the quad mesh drawn with its edges."""
    try:
        result = quadrangulate(context.V, context.F, target_faces=1000)
    except InputError as error:  # e.g. several components: what the pipeline needs, said plainly
        context.figures["quadrangulation"] = {"skipped": str(error)}
        return Section("Quadrangulation", f"meshsmith.quadrangulation (§5.2.2) needs one clean connected "
                       f"manifold; this input is not one: {error}", {"skipped": str(error)}, [])
    report = result.report
    name = "quadrangulation.png"
    pictures = [render.render(context.V, context.F, size=(480, 420), uv=result.UV, checker_size=1.0, wireframe=False,
                              title="the seamless map's unit grid"),
                render.render(result.V, result.Q, size=(480, 420), title=f"{report.quads} quads")]
    render.save_png(np.concatenate(pictures, axis=1), context.out / name)
    figures = {
        "quads": report.quads,
        "singularities": len(report.singular_vertices),
        "index sum (4χ)": int(report.singular_indices.sum()),
        "irregular vertices": report.irregular_vertices,
        "flipped triangles after MIQ": report.flipped_after,
        "complete (χ preserved)": report.extraction.complete,
        "holes (squares left out)": report.extraction.holes,
        "mean |angle - 90°|": report.mean_angle_deviation,
        "min scaled Jacobian": report.min_scaled_jacobian,
    }
    context.figures["quadrangulation"] = figures
    return Section("Quadrangulation", "meshsmith.quadrangulation (§5.2.2): a smooth cross field, its "
                   "mixed-integer seamless parametrization (MIQ), and the quad mesh of the map's integer "
                   "grid (quad extraction with exact predicates).", figures,
                   [(name, "the map's unit squares as a checkerboard on the input, and the extracted quads")])
