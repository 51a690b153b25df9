"""meshsmith: geometry processing for Python with a C++17 core.

Arrays in, arrays out: vertices ``V`` are float64 (n, 3), faces ``F`` are integer (m, 3).
Chapters are submodules (``meshsmith.io``, ``meshsmith.topology``, ...); errors are
:class:`InputError` (bad input, a ``ValueError``), :class:`SolverError` (a ``RuntimeError``)
and :class:`Cancelled` (a progress callback returned False).
"""
from . import (
               core,
               curves,
               datasets,
               decimation,
               geometry,
               io,
               parametrization,
               points,
               reconstruction,
               render,
               repair,
               tessellation,
               topology,
)
from ._core import Cancelled, InputError, SolverError

__version__ = core.version()

__all__ = ["InputError", "SolverError", "Cancelled", "core", "io", "topology", "geometry", "curves", "points", "render", "tessellation", "repair", "decimation", "parametrization",
           "reconstruction",
           "datasets",
           "__version__"]
