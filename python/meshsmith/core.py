"""Core chapter: validation of (V, F) arrays, mesh defects, build information, progress.

Every public function of meshsmith validates its input through the same C++ checks; these
functions expose them directly.
"""
from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import _arguments
from ._core import core as _core
from ._deprecation import positional_options
from ._results import Unpackable
from ._typing import (
    ArrayLike,
    BoolArray,
    FloatArray,
    IndexArray,
    PathLike,
    ProgressCallback,
)

__all__ = ["validate_mesh", "Mesh", "PointCloud", "MeshDefects", "mesh_defects", "version", "dependency_versions",
           "set_num_threads", "num_threads",
           "ArrayLike", "FloatArray", "IndexArray", "BoolArray", "PathLike", "ProgressCallback"]


class Mesh(NamedTuple):
    """A triangle mesh as two arrays; unpacks as ``V, F = mesh``.

    V: (n, 3) float64 vertex positions (or (n, 2) for planar meshes). F: (m, 3) int64 triangles.
    The result of every function that returns a mesh (readers, decimation, datasets, ...).
    """

    V: FloatArray
    F: IndexArray


class PointCloud(NamedTuple):
    """Points with optional normals; unpacks as ``P, N = cloud``.

    P: (n, 3) float64 positions. N: (n, 3) float64 unit normals, or None when there are none.
    """

    P: FloatArray
    N: FloatArray | None


def validate_mesh(V: ArrayLike, F: ArrayLike) -> None:
    """Raise :class:`meshsmith.InputError` unless (V, F) is a usable triangle mesh.

    V: (n, 3) real array of vertex positions, finite. F: (m, 3) integer array of triangles,
    every index in [0, n), m >= 1. The message names the offending row.
    """
    _core.validate_mesh(V, F)


@dataclass(frozen=True)
class MeshDefects(Unpackable):
    """Defects that are not errors but that many algorithms care about (indices ascending).

    Unpacks in field order: ``degenerate, zero_area, duplicate, unreferenced, summary``.
    """

    degenerate_faces: IndexArray       # faces with a repeated vertex index
    zero_area_faces: IndexArray        # distinct indices but area <= area_tolerance
    duplicate_faces: IndexArray        # same vertex set as an earlier face (later copies listed)
    unreferenced_vertices: IndexArray  # vertices no face uses
    summary: str                       # one line per kind of defect, "" if none

    @property
    def empty(self) -> bool:
        return not self.summary


@positional_options("area_tolerance")
def mesh_defects(V: ArrayLike, F: ArrayLike, *, area_tolerance: float = 0.0) -> MeshDefects:
    """Find degenerate, zero-area and duplicate faces and unreferenced vertices of (V, F).

    Raises InputError if (V, F) fails :func:`validate_mesh`.
    """
    found = _core.find_mesh_defects(V, F, _arguments.real(area_tolerance, "area_tolerance"))
    def indices(name: str) -> IndexArray:
        return np.asarray(found[name], dtype=np.int64)

    return MeshDefects(indices("degenerate_faces"), indices("zero_area_faces"), indices("duplicate_faces"),
                       indices("unreferenced_vertices"), str(found["summary"]))


def version() -> str:
    """meshsmith's version string."""
    return _core.version()


def dependency_versions() -> dict[str, str]:
    """Versions of the C++ libraries the core is linked with (Eigen, OpenMesh, CGAL, ...)."""
    return dict(_core.dependency_versions())


THREADS_VARIABLE = "MESHSMITH_NUM_THREADS"


def set_num_threads(count: int | None) -> None:
    """Cap the threads of every later meshsmith call at ``count`` (None: no cap, all cores).

    For process pools and shared machines (DESIGN.md, "Threads"); results never depend on it. The
    environment variable ``MESHSMITH_NUM_THREADS`` sets the same cap when meshsmith is imported. A
    function's own ``threads=`` option can lower the cap for that call, never raise it.
    Raises InputError unless count is None or an integer in [1, 65536].
    """
    _core.set_thread_limit(count)


def num_threads() -> int:
    """The number of threads meshsmith's parallel work may use now (the cap, or the core count)."""
    return int(_core.thread_limit())


def _thread_cap_from_environment() -> None:
    """Apply ``MESHSMITH_NUM_THREADS`` if it is set; a value that is not a positive integer is ignored
    with a RuntimeWarning (an import must not fail on it)."""
    value = os.environ.get(THREADS_VARIABLE, "").strip()
    if not value:
        return
    try:
        set_num_threads(int(value))
    except ValueError:
        warnings.warn(f"{THREADS_VARIABLE}={value!r} is not a positive integer; meshsmith ignores it and uses "
                      "every core", RuntimeWarning, stacklevel=3)


_thread_cap_from_environment()
