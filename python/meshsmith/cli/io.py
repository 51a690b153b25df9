"""`meshsmith convert`: between mesh formats."""
from __future__ import annotations

from .. import io


def command_convert(args) -> int:
    V, F = io.read_mesh(args.input)
    options = {}
    if args.binary or args.ascii:
        options["binary"] = bool(args.binary)
    io.write_mesh(args.output, V, F, **options)
    print(f"wrote {args.output}: {len(V)} vertices, {len(F)} faces")
    return 0


def register(commands) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    convert = commands.add_parser("convert", help="convert between mesh formats",
                                  description="Read a mesh and write it in the format given by OUT's extension.")
    convert.add_argument("input")
    convert.add_argument("output")
    encoding = convert.add_mutually_exclusive_group()
    encoding.add_argument("--binary", action="store_true", help="binary PLY/STL/OFF")
    encoding.add_argument("--ascii", action="store_true", help="ASCII PLY/STL/OFF")
    convert.set_defaults(run=command_convert)
