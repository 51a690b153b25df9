"""The demo's stages in pipeline order, and the run that writes the report."""
from __future__ import annotations

import html
import json
import time
import traceback
from pathlib import Path

from .. import InputError, core, io
from .._typing import ProgressCallback
from .context import DemoContext, Section, builtin_shape
from .decimation import stage_decimation
from .deformation import stage_deformation
from .geometry import stage_curvature
from .io import stage_input
from .parametrization import stage_parametrization
from .registration import stage_registration
from .quadrangulation import stage_quadrangulation
from .reconstruction import stage_poisson
from .render import stage_pictures
from .repair import stage_clean, stage_repair
from .smoothing import stage_smoothing
from .report import html_report
from .tessellation import stage_crust, stage_tessellation

#: Every chapter's stage, in pipeline order; a new chapter adds its stage here.
STAGES = [
    stage_clean,
    stage_input,
    stage_pictures,
    stage_curvature,
    stage_tessellation,
    stage_crust,
    stage_smoothing,
    stage_deformation,
    stage_poisson,
    stage_decimation,
    stage_parametrization,
    stage_registration,
    stage_quadrangulation,
    stage_repair,
]


def run_demo(out: Path | str, input_path: str | None = None, progress: ProgressCallback = None) -> Path:
    """Run every stage and write `out/index.html`; returns its path.

    input_path: a mesh file to use instead of the built-in shape; the first stage cleans it
    (meshsmith.repair.clean) and the report says what that changed. progress: an optional
    `(fraction, stage) -> bool` callback, told at the start and end of each stage.
    A stage that raises does not stop the others: its section in the report shows the error
    (and `results.json` records it under "errors"). Ctrl-C (KeyboardInterrupt) still stops the run.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if input_path:
        V, F = io.read_mesh(input_path)
        if len(F) == 0:   # e.g. a range scan stored as PLY vertices: every stage needs triangles
            raise InputError(f"{input_path} holds no faces (a point cloud?): the demo needs a triangle mesh")
        context = DemoContext(out, Path(input_path).name, V, F)
    else:
        name, V, F, uv = builtin_shape()
        context = DemoContext(out, name, V, F, uv)
    sections, timings, errors = [], {}, {}
    for index, stage in enumerate(STAGES):
        label = stage.__name__.removeprefix("stage_")
        if progress:
            progress(index / len(STAGES), label)
        start = time.perf_counter()
        try:
            sections.append(stage(context))
        except Exception as error:  # noqa: BLE001 -- one failing stage must not lose the report
            errors[label] = f"{type(error).__name__}: {error}"
            detail = traceback.format_exception_only(type(error), error)[-1].strip()
            sections.append(Section(f"{label} (failed)", f"This stage failed: <code>{html.escape(detail)}</code>"))
        timings[label] = time.perf_counter() - start
    if progress:
        progress(1.0, "done")
    context.figures["seconds_per_stage"] = timings
    if errors:
        context.figures["errors"] = errors
    (out / "results.json").write_text(json.dumps(context.figures, indent=2, default=str))
    report = out / "index.html"
    report.write_text(html_report(context, sections, timings, core.version(), core.dependency_versions()))
    return report
