"""Demo stage of the io and topology chapters: the input written and described."""
from __future__ import annotations

import html

from .. import io, topology
from .context import DemoContext, Section


def stage_input(context: DemoContext) -> Section:
    io.write_mesh(context.out / "input.ply", context.V, context.F)
    summary = topology.info(context.V, context.F)
    context.figures["input"] = summary.as_dict()
    table = {key: value for key, value in summary.as_dict().items()}
    return Section("Input", f"{html.escape(context.name)}, written as <code>input.ply</code>; "
                            "the figures of <code>meshsmith info</code>.", table)
