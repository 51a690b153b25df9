"""Parametrization chapter (curriculum §5, §5.1): boundary maps, harmonic and Tutte maps,
stretch-minimizing maps, least-squares conformal maps, ABF and ABF++, and the shared pieces
(cutting a mesh to a disk, checking a map is bijective).

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); UV coordinates come back as
float64 (n, 2). Bad input raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``maps``, ``cut``, ``bijectivity``, ``angle_based``, ``pipeline``.
"""
from .angle_based import AbfResult, abf, uv_from_angles
from .bijectivity import BijectivityReport, check_bijectivity, is_bijective
from .cut import CutMesh, cut_to_disk
from .maps import (
    PinnedVertices,
    StretchResult,
    default_lscm_pins,
    harmonic,
    lscm,
    lscm_spectral,
    map_boundary,
    stretch_minimizing,
)
from .pipeline import PARAMETRIZATION_METHODS, Parametrization, parametrize

__all__ = ["map_boundary", "harmonic", "StretchResult", "stretch_minimizing", "lscm", "default_lscm_pins",
           "lscm_spectral", "CutMesh", "cut_to_disk", "BijectivityReport", "check_bijectivity",
           "is_bijective", "PARAMETRIZATION_METHODS", "Parametrization", "parametrize", "AbfResult", "abf",
           "uv_from_angles", "PinnedVertices"]
