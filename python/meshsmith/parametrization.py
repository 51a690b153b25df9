"""Parametrization chapter (curriculum §5, §5.1): boundary maps, harmonic and Tutte maps,
stretch-minimizing maps, least-squares conformal maps, ABF and ABF++, and the shared pieces
(cutting a mesh to a disk, checking a map is bijective).

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); UV coordinates come back as
float64 (n, 2). Bad input raises :class:`meshsmith.InputError`.
"""
from __future__ import annotations

import numpy as np

from ._core import InputError
from ._core import parametrization as _core

__all__: list[str] = []

# ---------------------------------------------------------------------------------------------
# Boundary maps, harmonic maps, stretch-minimizing maps, LSCM, cut to disk, bijectivity (§5.1.1–2)
# ---------------------------------------------------------------------------------------------


# ---------------------------------------------------------------------------------------------
# ABF and ABF++ (§5.1.3)
# ---------------------------------------------------------------------------------------------
