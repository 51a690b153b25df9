"""`meshsmith demo`: the whole pipeline and an HTML report."""
from __future__ import annotations

import argparse
from pathlib import Path

from .. import demo
from .common import ProgressBar, add_command


def command_demo(args: argparse.Namespace) -> int:
    report = demo.run_demo(Path(args.out), input_path=args.input, progress=ProgressBar())
    print(f"demo report: {report}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    demo = add_command(
        commands, "demo", help="run the whole pipeline and write an HTML report",
        description="Run every stage of meshsmith on a built-in shape (or --input) and write outputs and an "
                    "HTML report with pictures (index.html in the output folder).",
        examples=["meshsmith demo --out report", "meshsmith demo --out report-mesh --input mesh.off"])
    demo.add_argument("--out", default="meshsmith-demo", help="output folder (default: meshsmith-demo)")
    demo.add_argument("--input", help="mesh file to use instead of the built-in shape")
    demo.set_defaults(run=command_demo)
