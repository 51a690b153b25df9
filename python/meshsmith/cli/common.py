"""Shared pieces of the command line: the argument parser, flag types, error messages in the
command line's own words, the progress bar and input reading."""
from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path
from typing import Callable, NoReturn, TextIO

import numpy as np

from .. import InputError, io
from ..core import Mesh

#: The extensions of the mesh formats the commands write.
MESH_SUFFIXES = (".obj", ".off", ".ply", ".stl")

#: The largest picture side the commands accept, in pixels (the renderer supersamples 3×3).
MAX_PICTURE_SIDE = 8192


class UsageError(InputError):
    """A command line that cannot be run as given (exit status 2), found after argparse: a flag
    combination or an output file name that does not fit."""


class ArgumentParser(argparse.ArgumentParser):
    """argparse, with a usage error reported as one line `meshsmith: error: ...` (exit status 2)."""

    def error(self, message: str) -> NoReturn:
        command = self.prog.split()[-1] if " " in self.prog else None
        where = f"{command}: " if command else ""
        hint = f"meshsmith {command} --help" if command else "meshsmith --help"
        self.exit(2, f"meshsmith: error: {where}{message} (see {hint})\n")


class Formatter(argparse.RawDescriptionHelpFormatter):
    """Descriptions and the examples epilog keep their line breaks."""


def add_command(commands: argparse._SubParsersAction[argparse.ArgumentParser], name: str, *, help: str,
                description: str, examples: list[str]) -> argparse.ArgumentParser:
    """A subcommand whose --help ends with its examples (each one is run by tests/test_cli_examples.py).

    examples: command lines that start with ``meshsmith NAME``."""
    parser = commands.add_parser(name, help=help, description=description, formatter_class=Formatter)
    set_examples(parser, name, examples)
    return parser


def set_examples(parser: argparse.ArgumentParser, name: str, examples: list[str]) -> None:
    """Give a command's parser its examples: the epilog of its --help, and `parser.examples`."""
    for example in examples:
        if not example.startswith(f"meshsmith {name} "):
            raise ValueError(f"example {example!r} of command {name} must start with 'meshsmith {name} '")
    parser.epilog = "examples:\n" + "\n".join(f"  {example}" for example in examples)
    parser.formatter_class = Formatter
    setattr(parser, "examples", list(examples))   # read by tests/test_cli_examples.py


# ---- flag types: a value out of range is a usage error (exit status 2), caught before any work ----

def integer(low: int | None = None, high: int | None = None) -> Callable[[str], int]:
    """An argparse type: an integer in [low, high]."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if (low is not None and value < low) or (high is not None and value > high):
            raise argparse.ArgumentTypeError(f"expected an integer {_bounds(low, high)}, got {value}")
        return value
    parse.__name__ = "integer"
    return parse


def number(low: float | None = None, high: float | None = None, *, open_low: bool = False,
           open_high: bool = False) -> Callable[[str], float]:
    """An argparse type: a finite number in [low, high] (open at an end with open_low / open_high)."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
        if not np.isfinite(value):
            raise argparse.ArgumentTypeError(f"expected a finite number, got {text}")
        if ((low is not None and (value < low or (open_low and value == low)))
                or (high is not None and (value > high or (open_high and value == high)))):
            raise argparse.ArgumentTypeError(f"expected a number {_bounds(low, high, open_low, open_high)}, "
                                             f"got {text}")
        return value
    parse.__name__ = "number"
    return parse


def _bounds(low: float | None, high: float | None, open_low: bool = False, open_high: bool = False) -> str:
    if low is not None and high is not None:
        return f"in {'(' if open_low else '['}{low:g}, {high:g}{')' if open_high else ']'}"
    if low is not None:
        return f"{'>' if open_low else '>='} {low:g}"
    return f"{'<' if open_high else '<='} {high:g}"


def add_picture_size(parser: argparse.ArgumentParser, width: int = 800, height: int = 600) -> None:
    """--width and --height, range-checked (1 to MAX_PICTURE_SIDE pixels)."""
    side = integer(16, MAX_PICTURE_SIDE)
    parser.add_argument("--width", type=side, default=width, metavar="PIXELS",
                        help=f"picture width, 16 to {MAX_PICTURE_SIDE} (default {width})")
    parser.add_argument("--height", type=side, default=height, metavar="PIXELS",
                        help=f"picture height, 16 to {MAX_PICTURE_SIDE} (default {height})")


# ---- the library's words → the command line's -------------------------------------------------

#: Per command: the library's parameter names and the flags that set them.
FLAGS: dict[str, dict[str, str]] = {
    "decimate": {"target_faces": "--faces", "max_error": "--error", "ratio": "--ratio",
                 "target_vertices": "--faces", "cell_size": "--error"},
    "triangulate": {"min_angle": "--min-angle", "max_area": "--max-area",
                    "max_steiner_points": "--max-steiner-points"},
    "normals": {"radius": "--radius"},
    "render": {"scalar_range": "--range", "size": "--width/--height", "views": "--views", "up": "--up"},
    "curvature": {"scalar_range": "--range", "size": "--width/--height"},
    "lod": {"n_faces": "--faces"},
    "parametrize": {"method": "--method"},
    "smooth": {"lam": "--lambda", "mu": "--mu", "epsilon_ball": "--epsilon", "error_slab": "--epsilon"},
}

#: Advice in the library's messages that names Python calls, and what the command line says instead.
PHRASES: tuple[tuple[str, str], ...] = (
    (" (pass format=...)", " (name the file .obj, .off, .ply, .stl or .xyz)"),
    (", or pass format=...)", ")"),
    ("(use read_points)", "(give it to a point-cloud command: meshsmith normals or meshsmith crust)"),
    ("(use write_points for point clouds)", "(point clouds are written as .xyz or .ply)"),
    ("raise the limit", "raise --max-steiner-points"),
    ("cut it first with cut_to_disk", "meshsmith parametrize cuts closed meshes itself"),
)


def user_message(error: BaseException, command: str | None) -> str:
    """The first line of an error's message, with the library's parameter names replaced by the
    command's flags and Python advice by command-line advice."""
    text = str(error).splitlines()[0] if str(error) else type(error).__name__
    for library, cli in PHRASES:
        text = text.replace(library, cli)
    for parameter, flag in FLAGS.get(command or "", {}).items():
        text = re.sub(rf"(?<![\w-]){re.escape(parameter)}(?![\w-])", flag, text)
    return text


# ---- progress --------------------------------------------------------------------------------

class ProgressBar:
    """A progress callback `(fraction, stage) -> True` that draws a bar on stderr.

    Draws only when stderr is a terminal (or `force`), so logs and pipes stay clean. A bar left
    mid-line (an error, Ctrl-C) is ended by :meth:`end_all` before the error line is printed.
    """

    _drawing: list["ProgressBar"] = []

    def __init__(self, width: int = 30, force: bool = False, stream: TextIO | None = None) -> None:
        self.stream = stream or sys.stderr
        self.enabled = force or self.stream.isatty()
        self.width, self.start, self.last_stage = width, time.perf_counter(), None
        self.mid_line = False

    def __call__(self, fraction: float, stage: str) -> bool:
        if self.enabled:
            fraction = min(max(float(fraction), 0.0), 1.0)
            filled = int(round(fraction * self.width))
            elapsed = time.perf_counter() - self.start
            self.stream.write(f"\r{stage:<36.36} [{'#' * filled}{'.' * (self.width - filled)}] "
                              f"{100 * fraction:5.1f}%  {elapsed:6.1f}s")
            if fraction >= 1.0:
                self.stream.write("\n")
                self._set_mid_line(False)
            else:
                self._set_mid_line(True)
            self.stream.flush()
        return True

    def _set_mid_line(self, value: bool) -> None:
        if value and not self.mid_line:
            ProgressBar._drawing.append(self)
        elif not value and self.mid_line:
            ProgressBar._drawing.remove(self)
        self.mid_line = value

    @classmethod
    def end_all(cls) -> None:
        """End the line of every bar still drawing, so the next message starts on its own line."""
        for bar in list(cls._drawing):
            bar.stream.write("\n")
            bar.stream.flush()
            bar._set_mid_line(False)


class Stages:
    """Stage progress for a command whose steps report none of their own (read → compute → write):
    ``stages = Stages(ProgressBar(), ["reading", "computing", "writing"])``, then
    ``stages.start("reading")`` before each step and ``stages.done()`` at the end. Each stage takes
    an equal share of the bar; :meth:`part` gives a step that takes ``progress=`` a callback
    within its stage's share. The bar draws as `bar` does (stderr, a terminal only)."""

    def __init__(self, bar: Callable[[float, str], object], names: list[str]) -> None:
        if not names:
            raise ValueError("Stages needs at least one stage name")
        self.bar, self.names, self.current = bar, list(names), -1

    def start(self, name: str) -> None:
        """Enter stage `name` (one of the names, in order)."""
        self.current = self.names.index(name, max(self.current, 0))
        self.bar(self.current / len(self.names), name)

    def part(self) -> Callable[[float, str], bool]:
        """A progress callback for the current stage's step: its fractions fill the stage's share."""
        index = max(self.current, 0)

        def report(fraction: float, stage: str) -> bool:
            self.bar(min((index + min(max(float(fraction), 0.0), 1.0)) / len(self.names), 1.0 - 1e-9),
                     f"{self.names[index]}: {stage}")
            return True
        return report

    def done(self) -> None:
        """The last stage finished: the bar reaches 100% (and ends its line)."""
        self.bar(1.0, self.names[-1])


# ---- input -----------------------------------------------------------------------------------

def read_mesh(path: str) -> Mesh:
    return io.read_mesh(path)


def read_faces(path: str) -> tuple[np.ndarray, np.ndarray | io.Polygons]:
    """(V, faces) of a mesh file with its polygons kept: an (m, s) array when every face has s
    corners ((m, 3) triangles, (m, 4) quads), else :class:`meshsmith.io.Polygons` (for the
    commands that take any faces: info, render)."""
    V, P = io.read_mesh(path, triangulate=False)
    if not len(P):
        return V, np.zeros((0, 3), dtype=np.int64)
    if (P.sizes == P.sizes[0]).all():
        return V, P.to_array()
    return V, P


#: Extensions read as point clouds (their own normals kept); other mesh formats give their vertices.
POINT_CLOUD_SUFFIXES = (".xyz", ".ply")


def read_point_cloud(path: str) -> np.ndarray:
    """The points of a point-cloud file (XYZ, PLY), or the vertices of a mesh file (OBJ, OFF, STL)."""
    lower = str(path).lower()
    if lower.endswith(POINT_CLOUD_SUFFIXES):
        return io.read_points(path)[0]
    if lower.endswith((".obj", ".off", ".stl")):
        return io.read_mesh(path)[0]
    raise InputError(f"{path}: a point cloud must be an .xyz or .ply file (or a mesh file: .obj, .off, .stl)")


def check_output(path: str, suffixes: tuple[str, ...], what: str) -> str:
    """Check an output path before any work: its extension is one of `suffixes` and its folder exists.

    what: how the message names the file ("-o", "--picture"). Raises UsageError for the extension,
    InputError for the folder."""
    target = Path(path)
    if target.suffix.lower() not in suffixes:
        given = f"ends in '{target.suffix}'" if target.suffix else "has no extension"
        expected = ", ".join(suffixes[:-1]) + f" or {suffixes[-1]}" if len(suffixes) > 1 else suffixes[0]
        raise UsageError(f"{what} {path} {given}: expected a {expected} file")
    if not target.parent.exists():
        raise InputError(f"{what} {path}: folder {target.parent} does not exist")
    return path
