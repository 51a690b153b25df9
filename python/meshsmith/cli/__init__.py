"""The `meshsmith` command line: one subcommand per task, mirroring the chapters.

    meshsmith info FILE
    meshsmith clean IN -o OUT [--merge-tolerance D] [--min-component-faces N] [--no-orient] ...
    meshsmith convert IN OUT [--binary | --ascii]
    meshsmith render IN -o out.png [--scalar x|y|z|valence|FILE.npy] [--range MIN MAX] [--cmap C]
                                   [--up x|y|z|-x|-y|-z] [--wireframe] [--views ...]
    meshsmith curvature IN --kind mean|gaussian|k1|k2 [--pointwise] -o out.png|out.npy [--range MIN MAX] [--up ...]
    meshsmith normals IN.xyz -o OUT.xyz [--k 16] [--orient]
    meshsmith register SOURCE TARGET -o T.txt [--apply OUT] [--method point_to_point|point_to_plane] [--trim f] ...
    meshsmith triangulate IN.poly --min-angle 30 [--max-area A] [--max-steiner-points N] -o OUT.obj [--picture P.png]
    meshsmith voronoi IN -o cells.png;  meshsmith power IN -o cells.png;  meshsmith crust IN -o OUT
    meshsmith decimate IN -o OUT (--faces N | --ratio r | --error eps) [--method qem|cluster] [--progressive OUT.pm]
    meshsmith lod IN.pm --faces N -o OUT
    meshsmith smooth IN -o OUT [--method laplacian|taubin] [--iterations N] [--epsilon E [--slab]] ...
    meshsmith parametrize IN --method tutte|harmonic|stretch|lscm|abf|abf++ -o OUT.obj [--picture P.png]
    meshsmith demo [--out DIR] [--input FILE]

Every command has --help, ending with examples that tests/test_cli_examples.py runs. No traceback
reaches the user: an error is one line `meshsmith: error: ...` on stderr, in the command line's
words (flags, not Python parameters), and the exit status says what went wrong: 2 for a malformed
command line (a flag out of range included), 1 for bad input (a file, its contents, a failed
solve), 130 for Ctrl-C. A closed pipe (`meshsmith info FILE | head -2`) ends quietly. Set
MESHSMITH_DEBUG=1 to see the traceback of an unexpected error.

One module per chapter registers its commands (``register(commands)``); :data:`CHAPTERS` is the
table, in the order of ``meshsmith --help``.
"""
from __future__ import annotations

import argparse
import os
import sys
import threading

from .. import Cancelled, InputError, SolverError
from ..core import version
from . import (
    decimation,
    deformation,
    demo,
    geometry,
    io,
    parametrization,
    points,
    registration,
    quadrangulation,
    reconstruction,
    render,
    repair,
    smoothing,
    tessellation,
    topology,
)
from .common import ArgumentParser, ProgressBar, UsageError, user_message

__all__ = ["main", "build_parser", "ProgressBar", "CHAPTERS"]

#: The chapters' command modules, in the order their commands appear in ``meshsmith --help``.
CHAPTERS = (
    topology,
    repair,
    io,
    render,
    geometry,
    points,
    registration,
    tessellation,
    smoothing,
    decimation,
    parametrization,
    deformation,
    quadrangulation,
    reconstruction,
    demo,
)


def build_parser() -> argparse.ArgumentParser:
    parser = ArgumentParser(prog="meshsmith", description="Geometry processing: the classic curriculum.")
    parser.add_argument("--version", action="version", version=f"meshsmith {_version()}")
    commands = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for chapter in CHAPTERS:
        chapter.register(commands)
    return parser


def _version() -> str:
    return version()


def main(argv: list[str] | None = None) -> int:
    """Run one `meshsmith` command; returns the exit status (0, 1 bad input, 2 usage, 130 Ctrl-C).

    Called with no argv (as the `meshsmith` program), the command runs in a worker thread while
    the main thread waits for it, so that Ctrl-C ends the process within a fraction of a second
    even inside a long C++ step that cannot check for it (a sparse factorization): the main thread
    prints one line and exits with status 130. Called with an argv (from Python), it runs in the
    caller's thread and Ctrl-C arrives as the library raises it."""
    if argv is not None:
        return _run(list(argv))
    outcome: list[int] = []
    worker = threading.Thread(target=lambda: outcome.append(_run(sys.argv[1:])), name="meshsmith", daemon=True)
    try:
        worker.start()
        while worker.is_alive():
            worker.join(0.05)
    except KeyboardInterrupt:
        status = _fail("interrupted", 130, error=False)
        _flush_quietly()
        os._exit(status)               # the worker may be inside C++ that cannot be stopped
    return outcome[0] if outcome else 1


def _run(argv: list[str]) -> int:
    command = None
    try:
        args = build_parser().parse_args(_attach_axis_values(argv))
        command = args.command
        status = args.run(args)
        sys.stdout.flush()               # a closed pipe shows here, not at interpreter exit
        return status
    except SystemExit as exit:           # argparse: --help, --version, usage errors (already printed)
        return exit.code if isinstance(exit.code, int) else 2
    except BrokenPipeError:
        return _closed_pipe()
    except (Cancelled, KeyboardInterrupt):
        return _fail("interrupted", 130, error=False)
    except ImportError as error:         # an optional dependency (Pillow) is missing: the message says which
        return _fail(user_message(error, command), 1)
    except UsageError as error:
        return _fail(f"{command}: {error} (see meshsmith {command} --help)", 2)
    except MemoryError:
        return _fail(f"{command}: out of memory (try a smaller input or smaller sizes)", 1)
    except (InputError, SolverError, OSError) as error:
        return _fail(user_message(error, command), 1)
    except Exception as error:           # a bug: still one line, with the way to see more
        if os.environ.get("MESHSMITH_DEBUG"):
            raise
        return _fail(f"internal error in {command or 'meshsmith'}: {type(error).__name__}: "
                     f"{user_message(error, command)} (rerun with MESHSMITH_DEBUG=1 for the traceback, "
                     "and please report it)", 1)


def _flush_quietly() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass


def _attach_axis_values(argv: list[str]) -> list[str]:
    """`--up -z` as `--up=-z`: argparse would take the negative axis for an option."""
    out: list[str] = []
    for word in argv:
        if out and out[-1] == "--up" and word in ("-x", "-y", "-z"):
            out[-1] = f"--up={word}"
        else:
            out.append(word)
    return out


def _fail(message: str, status: int, *, error: bool = True) -> int:
    ProgressBar.end_all()
    try:
        print(f"meshsmith: {'error: ' if error else ''}{message}", file=sys.stderr)
        sys.stderr.flush()
    except (BrokenPipeError, ValueError):
        pass
    return status


def _closed_pipe() -> int:
    """The reader of stdout went away (`| head`): stop quietly, as Unix tools do (status 128 + SIGPIPE)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())    # Python's final flush must not fail again
    except (OSError, ValueError):
        pass
    return 128 + 13
