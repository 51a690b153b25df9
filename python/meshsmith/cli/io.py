"""`meshsmith convert`: between mesh formats, keeping the attributes."""
from __future__ import annotations

import argparse
import re
import sys
import warnings

from .. import InputError, io
from .common import ProgressBar, Stages, add_command

# --drop names → MeshData fields (and the corner indices that go with them).
DROPPABLE = {"normals": ("normals", "F_normal"), "uv": ("UV", "F_uv"), "colors": ("colors",),
             "face-colors": ("face_colors",)}
FLAG_OF_KEYWORD = {"normals": "normals", "UV": "uv", "colors": "colors", "face_colors": "face-colors"}


def refused_attribute(error: BaseException) -> str | None:
    """The attribute write_mesh refused in `error` ("normals", "UV", "colors", "face_colors"), or None."""
    refused = re.search(r"cannot write (\w+)", str(error))
    return refused.group(1) if refused else None


def command_convert(args: argparse.Namespace) -> int:
    stages = Stages(ProgressBar(), ["reading", "writing"])
    stages.start("reading")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", io.SkippedDataWarning)
        mesh = io.read_mesh(args.input, triangulate=False, return_attributes=True)
    if caught:
        ProgressBar.end_all()             # the warnings start their own lines
    for warning in caught:
        print(f"meshsmith: warning: {warning.message}", file=sys.stderr)
    dropped = {field: None for name in args.drop or [] for field in DROPPABLE[name]}
    kept = {name: value for name, value in mesh.attribute_arrays().items() if name not in dropped}
    binary = bool(args.binary) if args.binary or args.ascii else None
    stages.start("writing")
    try:
        io.write_mesh(args.output, mesh.V, mesh.F, binary=binary, **kept)
    except InputError as error:
        flag = FLAG_OF_KEYWORD.get(refused_attribute(error) or "")
        if flag is None:
            raise
        raise InputError(f"{error}; or pass --drop {flag} to convert without them") from None
    stages.done()
    names = [name for name in ("normals", "UV", "colors", "face_colors") if name in kept]
    print(f"wrote {args.output}: {len(mesh.V)} vertices, {len(mesh.F)} faces"
          + (f", with {', '.join(names)}" if names else "")
          + (f" (dropped {', '.join(args.drop)})" if args.drop else ""))
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    convert = add_command(
        commands, "convert", help="convert between mesh formats, keeping normals, UVs and colours",
        description="Read a mesh and write it in the format given by OUT's extension (.obj .ply "
                    ".off .stl .glb), polygons and attributes included. If OUT's format cannot "
                    "hold an attribute the input has, the command fails and names a format "
                    "that can; --drop leaves the attribute out instead.",
        examples=["meshsmith convert mesh.off mesh.ply", "meshsmith convert mesh.off mesh.stl --binary",
                  "meshsmith convert disk.obj plain.obj --drop uv"])
    convert.add_argument("input")
    convert.add_argument("output")
    encoding = convert.add_mutually_exclusive_group()
    encoding.add_argument("--binary", action="store_true", help="binary PLY/STL/OFF")
    encoding.add_argument("--ascii", action="store_true", help="ASCII PLY/STL/OFF")
    convert.add_argument("--drop", action="append", choices=sorted(DROPPABLE), metavar="ATTR",
                         help="leave out an attribute: normals, uv, colors or face-colors "
                              "(repeat for several)")
    convert.set_defaults(run=command_convert)
