"""`meshsmith render`: PNG pictures of a mesh."""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from .. import InputError, io, render
from .common import (
    ProgressBar,
    Stages,
    UsageError,
    add_command,
    add_picture_size,
    check_output,
    number,
    read_faces,
)

#: Values of --up: the world axis that points up in the picture.
UP_AXES = ("x", "y", "z", "-x", "-y", "-z")


def scalar_field(name: str, V: np.ndarray, F: np.ndarray | io.Polygons) -> tuple[np.ndarray, str]:
    """A per-vertex scalar for `--scalar`: a coordinate, the valence, or values from a .npy file."""
    if name in ("x", "y", "z"):
        return V[:, "xyz".index(name)].copy(), f"{name} coordinate"
    if name == "valence":
        corners = F.indices if isinstance(F, io.Polygons) else np.asarray(F).ravel()
        return np.bincount(corners, minlength=len(V)).astype(float), "vertex valence"
    path = Path(name)
    if path.suffix == ".npy":
        if not path.is_file():
            raise InputError(f"scalar file {name} does not exist")
        values = np.load(path, allow_pickle=False)
        if values.ndim != 1 or len(values) != len(V):
            raise InputError(f"scalar file {name} holds shape {values.shape}: expected ({len(V)},), one value per vertex")
        return values.astype(float), path.stem
    raise InputError(f"unknown scalar '{name}': use x, y, z, valence or a .npy file of per-vertex values")


def add_colour_options(parser: argparse.ArgumentParser) -> None:
    """--cmap and --range, shared by the commands that colour a mesh by a scalar field."""
    parser.add_argument("--cmap", choices=render.COLORMAPS,
                        help="colour map (default: coolwarm, centred on 0, for values of both signs; "
                             "viridis for values of one sign)")
    parser.add_argument("--range", nargs=2, type=number(), metavar=("MIN", "MAX"),
                        help="values mapped onto the ends of the colour map (default: the 2nd and 98th "
                             "percentiles); values outside get the end colours and an arrow on the bar")
    parser.add_argument("--up", choices=UP_AXES, default="y",
                        help="world axis that points up in the picture (default y; z for CAD and scans)")


def colour_range(args: argparse.Namespace, values: np.ndarray) -> tuple[str, tuple[float, float]]:
    """(colour map, (low, high)) that `render` will use for `values` under --cmap and --range."""
    cmap = args.cmap or render.default_colormap(values)
    if args.range is None:
        return cmap, render.scalar_range(values, len(values), cmap)
    low, high = args.range
    if not low < high:
        raise UsageError(f"--range {low:g} {high:g}: MIN must be below MAX")
    return cmap, (low, high)


def describe_range(values: np.ndarray, low: float, high: float) -> str:
    """The printed line about the colours: the values' range and the colour bar's, with what was clipped."""
    below, above = render.clipped_ends(values, low, high)
    clipped = [f"{int(np.sum(values < low))} below" if below else "",
               f"{int(np.sum(values > high))} above" if above else ""]
    clipped = [part for part in clipped if part]
    note = f"; {' and '.join(clipped)} drawn in the end colours (arrows on the bar)" if clipped else ""
    return (f"values in [{values.min():.6g}, {values.max():.6g}], colour bar [{low:.6g}, {high:.6g}]{note}")


def command_render(args: argparse.Namespace) -> int:
    check_output(args.output, (".png",), "-o")
    stages = Stages(ProgressBar(), ["reading"] + (["scalar field"] if args.scalar else []) + ["rendering"])
    stages.start("reading")
    V, F = read_faces(args.input)  # quad meshes are drawn with their edges
    options = dict(size=(args.width, args.height), wireframe=args.wireframe or None, flat=args.flat, up=args.up)
    line = ""
    if args.scalar:
        stages.start("scalar field")
        values, options["scalar_label"] = scalar_field(args.scalar, V, F)
        options["cmap"], options["scalar_range"] = colour_range(args, values)
        options["scalar"] = values
        line = f": {options['scalar_label']}, {describe_range(values, *options['scalar_range'])}"
    elif args.range is not None or args.cmap is not None:
        raise UsageError("--range and --cmap colour a --scalar; give --scalar too")
    if args.views:
        options["views"] = [view.strip() for view in args.views.split(",")]
    stages.start("rendering")
    render.render(V, F, args.output, title=args.title or Path(args.input).name, **options)
    stages.done()
    print(f"wrote {args.output}{line}")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    parser = add_command(
        commands, "render", help="render a mesh to a PNG picture",
        description="Render a shaded picture of a mesh, optionally coloured by a per-vertex scalar.",
        examples=["meshsmith render mesh.off -o mesh.png",
                  "meshsmith render mesh.off -o height.png --scalar z --up z",
                  "meshsmith render mesh.off -o views.png --views front,left,top,three-quarter --wireframe",
                  "meshsmith render mesh.off -o x.png --scalar x --range -0.5 0.5 --cmap coolwarm"])
    parser.add_argument("input", help="mesh file (OBJ, OFF, PLY, STL)")
    parser.add_argument("-o", "--output", required=True, help="output PNG")
    parser.add_argument("--scalar", help="colour by x, y, z, valence, or a .npy file of per-vertex values")
    add_colour_options(parser)
    parser.add_argument("--wireframe", action="store_true", help="draw the edges")
    parser.add_argument("--flat", action="store_true", help="flat shading (one normal per face)")
    parser.add_argument("--views", help="comma-separated views: " + ", ".join(render.VIEWS))
    add_picture_size(parser)
    parser.add_argument("--title", help="title drawn on the picture (default: the file name)")
    parser.set_defaults(run=command_render)
