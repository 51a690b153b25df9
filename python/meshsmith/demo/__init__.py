"""`meshsmith demo`: run every chapter on one mesh and write an HTML report with pictures.

Each stage is a function `stage(context) -> Section`, listed in STAGES (``demo.pipeline``) in
pipeline order, one module per chapter (``demo/<chapter>.py``); a new chapter adds its stage there. A stage
writes its outputs into `context.out` and returns the HTML section that shows them.
"""
from .context import DemoContext, Section, builtin_shape
from .decimation import stage_decimation
from .deformation import stage_deformation
from .geometry import stage_curvature
from .io import stage_input
from .parametrization import stage_parametrization
from .pipeline import STAGES, run_demo
from .registration import stage_registration
from .render import stage_pictures
from .repair import stage_clean, stage_repair
from .smoothing import stage_smoothing
from .report import html_report
from .tessellation import stage_crust, stage_tessellation

__all__ = [
    "run_demo",
    "STAGES",
    "DemoContext",
    "Section",
    "builtin_shape",
    "html_report",
    "stage_clean",
    "stage_repair",
    "stage_input",
    "stage_pictures",
    "stage_curvature",
    "stage_tessellation",
    "stage_crust",
    "stage_decimation",
    "stage_parametrization",
    "stage_smoothing",
    "stage_registration",
    "stage_deformation",
]
