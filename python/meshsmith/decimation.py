"""Decimation chapter (curriculum §4.1–4.3): vertex clustering, incremental decimation by error
quadrics, and progressive meshes.

Vertices ``V`` are float64 (n, 3), faces ``F`` integer (m, 3); results come back as float64 and
int64 arrays. Bad input raises :class:`meshsmith.InputError`.
"""
from __future__ import annotations

import numpy as np

from ._core import InputError
from ._core import decimation as _core

__all__: list[str] = []

# ---------------------------------------------------------------------------------------------
# Vertex clustering (§4.1)
# ---------------------------------------------------------------------------------------------


# ---------------------------------------------------------------------------------------------
# Incremental decimation with error quadrics (§4.2)
# ---------------------------------------------------------------------------------------------


# ---------------------------------------------------------------------------------------------
# Progressive meshes (§4.3)
# ---------------------------------------------------------------------------------------------
