"""The type aliases of meshsmith's public API, defined once (numpy.typing).

Array arguments are :data:`numpy.typing.ArrayLike` (anything ``numpy.asarray`` turns into the
expected shape); array results are float64 (:data:`FloatArray`), int64 (:data:`IndexArray`) or
bool (:data:`BoolArray`) ndarrays; sparse matrices are ``scipy.sparse.csc_matrix``; a progress
callback is :data:`ProgressCallback`. Re-exported by :mod:`meshsmith.core`.
"""
from __future__ import annotations

import os
from typing import Callable, TypeAlias, Union

import numpy as np
import numpy.typing as npt

__all__ = ["ArrayLike", "FloatArray", "IndexArray", "BoolArray", "ProgressCallback", "PathLike"]

#: Any input numpy can convert to an array (lists, tuples, ndarrays of any dtype).
ArrayLike: TypeAlias = npt.ArrayLike
#: A float64 ndarray (positions, values, UVs).
FloatArray: TypeAlias = npt.NDArray[np.float64]
#: An int64 ndarray (faces, indices, labels).
IndexArray: TypeAlias = npt.NDArray[np.int64]
#: A bool ndarray (masks).
BoolArray: TypeAlias = npt.NDArray[np.bool_]
#: ``progress(fraction, stage)`` called during long work; returning False cancels
#: (:class:`meshsmith.Cancelled`), True or None goes on. None: no callback.
ProgressCallback: TypeAlias = Union[Callable[[float, str], Union[bool, None]], None]
#: A file name: ``str`` or any ``os.PathLike``.
PathLike: TypeAlias = Union[str, "os.PathLike[str]"]
