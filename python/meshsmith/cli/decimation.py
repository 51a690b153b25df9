"""`meshsmith decimate|lod`: decimation and progressive meshes (§4)."""
from __future__ import annotations

import argparse

import numpy as np

from .. import InputError, decimation, geometry, io
from .common import (
    MESH_SUFFIXES,
    ProgressBar,
    add_command,
    check_output,
    integer,
    number,
)


def _relative_hausdorff(V0: np.ndarray, F0: np.ndarray, V1: np.ndarray, F1: np.ndarray) -> tuple[float, float]:
    """Symmetric Hausdorff distance between two meshes and its ratio to the bounding-box diagonal."""
    distance = float(geometry.hausdorff_distance(V1, F1, V0, F0))
    diagonal = float(np.linalg.norm(V0.max(axis=0) - V0.min(axis=0)))
    return distance, (distance / diagonal if diagonal > 0 else 0.0)


def command_decimate(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    if args.progressive:
        check_output(args.progressive, (".pm",), "--progressive")
    V, F = io.read_mesh(args.input)
    progress = ProgressBar()
    if args.method == "cluster":
        if args.progressive:
            raise InputError("--progressive needs --method qem: clustering records no collapses")
        if args.faces is not None:
            options = dict(target_vertices=max(3, args.faces // 2))   # a closed mesh has ~2 faces per vertex
        elif args.ratio is not None:
            options = dict(target_vertices=max(3, int(round(args.ratio * len(np.unique(F))))))
        else:
            options = dict(cell_size=args.error / np.sqrt(3.0))     # a vertex moves at most a cell diagonal
        result = decimation.cluster(V, F, progress=progress, **options)
        V2, F2 = result.V, result.F
        note = f", cell size {result.cell_size:.6g}, {'manifold' if result.is_manifold else 'NOT manifold'}"
    else:
        stop = dict(target_faces=args.faces, ratio=args.ratio, max_error=args.error)
        stop = {key: value for key, value in stop.items() if value is not None}
        if args.progressive:
            pm = decimation.progressive_mesh(V, F, progress=progress, **stop)
            pm.save(args.progressive)
            pm.set_level(0)
            V2, F2 = pm.mesh()
            note = f"; progressive mesh {args.progressive}: {pm.n_splits} vertex splits back to the input"
        else:
            V2, F2 = decimation.decimate(V, F, progress=progress, **stop)
            note = ""
    if len(F2) == 0:
        raise InputError(f"{args.method}: no triangle is left; ask for more faces or a smaller error")
    io.write_mesh(args.output, V2, F2)
    distance, relative = _relative_hausdorff(V, F, V2, F2)
    print(f"wrote {args.output}: {len(F)} -> {len(F2)} faces ({len(V2)} vertices){note}")
    print(f"Hausdorff distance {distance:.6g} ({100 * relative:.4g}% of the bounding-box diagonal)")
    return 0


def command_lod(args: argparse.Namespace) -> int:
    check_output(args.output, MESH_SUFFIXES, "-o")
    pm = decimation.ProgressiveMesh.load(args.input)
    low, high = pm.face_range
    if args.faces < low:
        raise InputError(f"--faces {args.faces} is below the base mesh of {args.input} ({low} faces): "
                         f"its levels span {low}..{high} faces")
    V, F = pm.at(min(args.faces, high))       # above the finest level: the finest level itself
    io.write_mesh(args.output, V, F)
    print(f"wrote {args.output}: level {pm.level} of {pm.n_splits}, {len(F)} faces ({len(V)} vertices; "
          f"this progressive mesh spans {low}..{high} faces)")
    return 0


def register(commands: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add this chapter's commands to the `meshsmith` subparsers."""
    decimate = add_command(
        commands, "decimate", help="reduce the number of triangles (QEM or clustering)",
        description="Decimate a mesh (§4.1-4.3): greedy QEM edge collapses (default) or vertex clustering "
                    "on a grid; prints the faces before and after and the Hausdorff distance to the input.",
        examples=["meshsmith decimate mesh.off -o small.obj --faces 200",
                  "meshsmith decimate mesh.off -o half.ply --ratio 0.5",
                  "meshsmith decimate mesh.off -o coarse.off --error 0.001",
                  "meshsmith decimate mesh.off -o grid.obj --faces 150 --method cluster",
                  "meshsmith decimate mesh.off -o base.obj --faces 100 --progressive mesh.pm"])
    decimate.add_argument("input", help="mesh file (OBJ, OFF, PLY, STL)")
    decimate.add_argument("-o", "--output", required=True, help="decimated mesh file")
    stop = decimate.add_mutually_exclusive_group(required=True)
    stop.add_argument("--faces", type=integer(1), help="target number of faces (cluster: about half as many vertices)")
    stop.add_argument("--ratio", type=number(0, 1, open_low=True), help="target fraction of the faces (cluster: of the vertices), in (0, 1]")
    stop.add_argument("--error", type=number(0, open_low=True),
                      help="qem: the largest quadric error of a collapse (length^2, see decimation.decimate); "
                           "cluster: the largest distance a vertex moves (cell diagonal)")
    decimate.add_argument("--method", choices=("qem", "cluster"), default="qem", help="default: qem")
    decimate.add_argument("--progressive", metavar="OUT.pm",
                          help="also write the progressive mesh from OUTPUT (its base) back to INPUT (qem only)")
    decimate.set_defaults(run=command_decimate)

    lod = add_command(
        commands, "lod", help="extract a level of detail from a progressive mesh",
        description="Read a progressive mesh (.pm, written by `meshsmith decimate --progressive`) and write "
                    "its finest level with at most N faces (the full mesh when N is above its face count; "
                    "an error when N is below the base mesh's).",
        examples=["meshsmith lod mesh.pm --faces 250 -o level.obj",
                  "meshsmith lod mesh.pm --faces 1000000 -o full.ply"])
    lod.add_argument("input", help="progressive mesh file (.pm)")
    lod.add_argument("--faces", type=integer(1), required=True, help="at most this many faces")
    lod.add_argument("-o", "--output", required=True, help="output mesh file")
    lod.set_defaults(run=command_lod)
