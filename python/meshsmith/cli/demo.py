"""`meshsmith demo`: the whole pipeline and an HTML report."""
from __future__ import annotations

from pathlib import Path

from .. import demo
from .common import ProgressBar


def command_demo(args) -> int:
    report = demo.run_demo(Path(args.out), input_path=args.input, progress=ProgressBar())
    print(f"demo report: {report}")
    return 0


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    demo = commands.add_parser("demo", help="run the whole pipeline and write an HTML report",
                               description="Run every stage of meshsmith on a built-in shape (or --input) "
                                           "and write outputs and an HTML report with pictures.")
    demo.add_argument("--out", default="meshsmith-demo", help="output folder (default: meshsmith-demo)")
    demo.add_argument("--input", help="mesh file to use instead of the built-in shape")
    demo.set_defaults(run=command_demo)
