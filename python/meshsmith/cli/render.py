"""`meshsmith render`: PNG pictures of a mesh."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import InputError, render
from .common import read_mesh


def scalar_field(name: str, V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, str]:
    """A per-vertex scalar for `--scalar`: a coordinate, the valence, or values from a .npy file."""
    if name in ("x", "y", "z"):
        return V[:, "xyz".index(name)].copy(), f"{name} coordinate"
    if name == "valence":
        return np.bincount(np.asarray(F).ravel(), minlength=len(V)).astype(float), "vertex valence"
    path = Path(name)
    if path.suffix == ".npy":
        if not path.is_file():
            raise InputError(f"scalar file {name} does not exist")
        values = np.load(path, allow_pickle=False)
        if values.ndim != 1 or len(values) != len(V):
            raise InputError(f"scalar file {name} holds shape {values.shape}: expected ({len(V)},), one value per vertex")
        return values.astype(float), path.stem
    raise InputError(f"unknown scalar '{name}': use x, y, z, valence or a .npy file of per-vertex values")


def command_render(args) -> int:
    V, F = read_mesh(args.input)
    options = dict(size=(args.width, args.height), wireframe=args.wireframe, flat=args.flat)
    if args.scalar:
        options["scalar"], options["scalar_label"] = scalar_field(args.scalar, V, F)
        options["cmap"] = args.cmap
    if args.views:
        options["views"] = args.views.split(",")
    render.render(V, F, args.output, title=args.title or Path(args.input).name, **options)
    print(f"wrote {args.output}")
    return 0


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    render = commands.add_parser("render", help="render a mesh to a PNG picture",
                                 description="Render a shaded picture of a mesh, optionally coloured by a scalar.")
    render.add_argument("input")
    render.add_argument("-o", "--output", required=True, help="output PNG")
    render.add_argument("--scalar", help="colour by x, y, z, valence, or a .npy file of per-vertex values")
    render.add_argument("--cmap", default="viridis", help="colormap for --scalar (viridis, magma, coolwarm)")
    render.add_argument("--wireframe", action="store_true", help="draw the edges")
    render.add_argument("--flat", action="store_true", help="flat shading (one normal per face)")
    render.add_argument("--views", help="comma-separated views, e.g. front,left,top,three-quarter")
    render.add_argument("--width", type=int, default=800)
    render.add_argument("--height", type=int, default=600)
    render.add_argument("--title", help="title drawn on the picture (default: the file name)")
    render.set_defaults(run=command_render)
