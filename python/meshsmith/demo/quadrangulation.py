"""Demo stage of the quadrangulation chapter: cross field → MIQ → quad extraction (§5.2.2), and the
dual-loop layout of the field (§5.3)."""
from __future__ import annotations

from typing import Any

import numpy as np

from .. import InputError, render
from ..quadrangulation import cross_field, dual_loop_layout, field_picture, quadrangulate, regions_picture
from .context import DemoContext, Section


def stage_quadrangulation(context: DemoContext) -> Section:
    """§5.2.2: the input remeshed into about 1,000 quads, with its cross field and singularities, the
    seamless map's grid on the input and the quad mesh drawn with its edges; §5.3: the smooth
    field's dual loops (the singularities merged first), their regions and the coarse layout."""
    try:
        result = quadrangulate(context.V, context.F, target_faces=1000)
    except InputError as error:  # e.g. several components: what the pipeline needs, said plainly
        context.figures["quadrangulation"] = {"skipped": str(error)}
        return Section("Quadrangulation", f"meshsmith.quadrangulation (§5.2.2) needs one clean connected "
                       f"manifold; this input is not one: {error}", {"skipped": str(error)}, [])
    report = result.report
    name = "quadrangulation.png"
    field = cross_field(context.V, context.F)
    pictures = [field_picture(context.V, context.F, field, size=(480, 420), title="cross field and singularities"),
                render.render(context.V, context.F, size=(480, 420), uv=result.UV, checker_size=1.0, wireframe=False,
                              title="the seamless map's unit grid"),
                render.render(result.V, result.Q, size=(480, 420), title=f"{report.quads} quads")]
    render.save_png(np.concatenate(pictures, axis=1), context.out / name)
    figures: dict[str, Any] = {
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
    images = [(name, "the cross field (crosses, cones coloured by index), the map's unit squares as a "
                     "checkerboard on the input, and the extracted quads")]
    # §5.3: dual loops of the same field with dual_loop_layout's defaults (singularities merged, then
    # its schedule of attempts); they are traced on closed meshes only (an open input, e.g. a scan with
    # holes, is said so in the figures).
    try:
        layout = dual_loop_layout(context.V, context.F, field)
    except InputError as error:
        figures["dual loops skipped"] = str(error)
    else:
        panels = [field_picture(layout.V_traced, layout.F_traced, layout.theta, size=(480, 420),
                                title=f"{len(layout.singular_vertices)} singularities after merging"),
                  regions_picture(layout.V_traced, layout.F_traced, layout.region, size=(480, 420),
                                  marked=layout.Vq_vertex,
                                  title=f"{layout.report.loops} loops, {layout.report.regions} regions")]
        if len(layout.Q):   # no quad when no two loops crossed (decimated-knight): the report says why
            panels.append(render.render(layout.Vq, layout.Q, size=(480, 420), title=f"{len(layout.Q)} layout quads"))
        else:
            figures["dual loops failure"] = layout.report.failure
        loops_name = "dual_loops.png"
        render.save_png(np.concatenate(panels, axis=1), context.out / loops_name)
        figures.update({"dual loops": layout.report.loops, "dual-loop layout quads": len(layout.Q),
                        "dual-loop layout complete": layout.report.complete})
        images.append((loops_name, "the dual loops' regions (one colour each, the layout vertices marked) and the "
                                   "coarse layout"))
    context.figures["quadrangulation"] = figures
    return Section("Quadrangulation", "meshsmith.quadrangulation (§5.2.2): a smooth cross field, its "
                   "mixed-integer seamless parametrization (MIQ), and the quad mesh of the map's integer "
                   "grid (quad extraction with exact predicates); §5.3: loops along the field, selected "
                   "until every region is a disk with at most one singularity, and their dual as a "
                   "coarse quad layout.", figures, images)
