"""The `meshsmith` command line: one subcommand per task, mirroring the chapters.

    meshsmith info FILE
    meshsmith clean IN -o OUT [--merge-tolerance D] [--min-component-faces N] [--no-orient] ...
    meshsmith convert IN OUT [--binary | --ascii]
    meshsmith render IN -o out.png [--scalar x|y|z|valence|FILE.npy] [--wireframe] [--views ...]
    meshsmith curvature IN --kind mean|gaussian|k1|k2 -o out.png|out.npy
    meshsmith normals IN.xyz -o OUT.xyz [--k 16] [--orient]
    meshsmith triangulate IN.poly --min-angle 30 [--max-area A] -o OUT.obj [--picture P.png]
    meshsmith voronoi IN -o cells.png;  meshsmith power IN -o cells.png;  meshsmith crust IN -o OUT
    meshsmith decimate IN -o OUT (--faces N | --ratio r | --error eps) [--method qem|cluster] [--progressive OUT.pm]
    meshsmith lod IN.pm --faces N -o OUT
    meshsmith parametrize IN --method tutte|harmonic|stretch|lscm|abf|abf++ -o OUT.obj [--picture P.png]
    meshsmith demo [--out DIR] [--input FILE]

Every command has --help. Bad input prints one line `meshsmith: error: ...` on stderr and exits
with status 1 (status 2 for a malformed command line, as argparse does).

One module per chapter registers its commands (``register(commands)``); :data:`CHAPTERS` is the
table, in the order of ``meshsmith --help``.
"""
from __future__ import annotations

import argparse
import sys

from .. import Cancelled, InputError, SolverError
from ..core import version
from . import (
    decimation,
    demo,
    geometry,
    io,
    parametrization,
    points,
    render,
    repair,
    tessellation,
    topology,
)
from .common import ProgressBar

__all__ = ["main", "build_parser", "ProgressBar", "CHAPTERS"]

#: The chapters' command modules, in the order their commands appear in ``meshsmith --help``.
CHAPTERS = (topology, repair, io, render, geometry, points, tessellation, decimation, parametrization, demo)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="meshsmith", description="Geometry processing: the classic curriculum.")
    parser.add_argument("--version", action="version", version=f"meshsmith {_version()}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for chapter in CHAPTERS:
        chapter.register(commands)
    return parser


def _version() -> str:
    return version()


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except (InputError, SolverError, OSError) as error:
        message = str(error).splitlines()[0] if str(error) else type(error).__name__
        print(f"meshsmith: error: {message}", file=sys.stderr)
        return 1
    except (Cancelled, KeyboardInterrupt):
        print("meshsmith: cancelled", file=sys.stderr)
        return 130
