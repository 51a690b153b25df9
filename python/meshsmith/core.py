"""Core chapter: validation of (V, F) arrays, mesh defects, build information, progress.

Every public function of meshsmith validates its input through the same C++ checks; these
functions expose them directly.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._core import core as _core

__all__ = ["validate_mesh", "MeshDefects", "mesh_defects", "version", "dependency_versions"]


def validate_mesh(V, F) -> None:
    """Raise :class:`meshsmith.InputError` unless (V, F) is a usable triangle mesh.

    V: (n, 3) real array of vertex positions, finite. F: (m, 3) integer array of triangles,
    every index in [0, n), m >= 1. The message names the offending row.
    """
    _core.validate_mesh(V, F)


@dataclass(frozen=True)
class MeshDefects:
    """Defects that are not errors but that many algorithms care about (indices ascending)."""

    degenerate_faces: np.ndarray       # faces with a repeated vertex index
    zero_area_faces: np.ndarray        # distinct indices but area <= area_tolerance
    duplicate_faces: np.ndarray        # same vertex set as an earlier face (later copies listed)
    unreferenced_vertices: np.ndarray  # vertices no face uses
    summary: str                       # one line per kind of defect, "" if none

    @property
    def empty(self) -> bool:
        return not self.summary


def mesh_defects(V, F, area_tolerance: float = 0.0) -> MeshDefects:
    """Find degenerate, zero-area and duplicate faces and unreferenced vertices of (V, F).

    Raises InputError if (V, F) fails :func:`validate_mesh`.
    """
    found = _core.find_mesh_defects(V, F, float(area_tolerance))
    return MeshDefects(**{k: (np.asarray(v, dtype=np.int64) if k != "summary" else v)
                          for k, v in found.items()})


def version() -> str:
    """meshsmith's version string."""
    return _core.version()


def dependency_versions() -> dict[str, str]:
    """Versions of the C++ libraries the core is linked with (Eigen, OpenMesh, CGAL, ...)."""
    return dict(_core.dependency_versions())
