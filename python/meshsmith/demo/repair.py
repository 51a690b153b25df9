"""Demo stage of the repair chapter: the input cleaned before every other stage (§2.4)."""
from __future__ import annotations

from .. import repair
from .context import DemoContext, Section


def stage_clean(context: DemoContext) -> Section:
    """§2.4: :func:`meshsmith.repair.clean` with its defaults; the later stages see the cleaned mesh.
    Per-corner texture coordinates follow their faces (and a flipped face's corners)."""
    V, F, report = repair.clean(context.V, context.F)
    if report.changed:
        if context.uv is not None:
            uv = context.uv[report.face_map]
            uv[report.flipped] = uv[report.flipped][:, [0, 2, 1]]
            context.uv = uv
        before = f"{len(context.V):,} vertices, {len(context.F):,} faces"
        context.V, context.F = V, F
        text = (f"meshsmith.repair.clean (§2.4) changed the input ({before}) into {len(V):,} vertices, "
                f"{len(F):,} faces; the stages below use the cleaned mesh.")
    else:
        text = "meshsmith.repair.clean (§2.4) found nothing to change: the input is clean."
    figures: dict[str, object] = dict(report.counts())
    context.figures["clean"] = figures
    return Section("Cleaning", text + " Counts of each kind of change:", figures)
