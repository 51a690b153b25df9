"""Demo stage of the parametrization chapter: Tutte, LSCM and stretch-minimizing maps (§5.1)."""
from __future__ import annotations

from .. import parametrization, render
from .context import DemoContext, Section


def stage_parametrization(context: DemoContext) -> Section:
    """§5.1: the input cut to a disk (§5.2.2) and flattened by Tutte's embedding, LSCM and the
    stretch-minimizing map, with pictures and distortion."""
    figures, images = {}, []
    for method in ("tutte", "lscm", "stretch"):
        result = parametrization.parametrize(context.V, context.F, method=method)
        name = f"parametrization_{method}.png"
        render.parametrization_picture(result, context.out / name, f"checkerboard through the {method} map")
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
