"""Argument checks for the Python modules' own use of an argument (before or instead of the core).

These are the bindings' conversions themselves (cpp/python/convert.cpp, through
``meshsmith._core.core``), so an array or an integer option checked here gets exactly the rule
and the message it gets in C++: InputError naming the argument for anything numpy cannot turn
into a numeric array of the right shape and dtype (ragged lists, None, objects, strings,
complex; float or bool indices), for an integer option that is not an integer in its range, and
for a float option that is not a real number (`real`, the one check made in Python only: the
bindings take float options as doubles).
Arrays come back C-contiguous (float64, int32 or bool), without a copy when they are already;
the caller's arrays are never written to.
"""
from __future__ import annotations

import functools
import inspect
from typing import Any, Callable, ParamSpec, TypeVar

import numpy as np

from ._core import Cancelled, InputError
from ._core import core as _convert
from ._typing import BoolArray, FloatArray, ProgressCallback

#: The most elements (faces, points, samples) a function makes from a count it is given: 2^26,
#: several GB of arrays, rather than exhausting memory.
MAX_ELEMENTS = 2 ** 26

P = ParamSpec("P")
R = TypeVar("R")


def numbers(value: object, name: str, elements: str = "real") -> np.ndarray:
    """`value` as an ndarray of any shape (not converted: its own dtype) whose elements are
    "real" (float or integer dtypes), "index" (integer dtypes) or "flag" (bool). Raises
    InputError naming `name`."""
    return _convert.numeric_array(value, name, elements)


def real_array(value: object, name: str, columns: int | tuple[int, int] | None = None) -> FloatArray:
    """`value` as float64 of shape (n,) (columns None), (n, columns), or (n, a) or (n, b) for
    columns=(a, b). Raises InputError naming `name`."""
    return _convert.real_array(value, name, columns)


def index_array(value: object, name: str, columns: int | None = None) -> np.ndarray:
    """`value` as int32 of shape (n,) (columns None) or (n, columns); integer dtypes only, every
    value inside the 32-bit range. Raises InputError naming `name`."""
    return _convert.index_array(value, name, columns)


def flag_array(value: object, name: str) -> BoolArray:
    """`value` as a bool array of shape (n,) (bool dtype only). Raises InputError naming `name`."""
    return _convert.flag_array(value, name)


def integer(value: object, name: str, minimum: int, maximum: int) -> int:
    """`value` (an int, a numpy integer or anything with ``__index__``; not a bool or a float) as
    an int in [minimum, maximum]. Raises InputError "name = value: expected an integer in
    [minimum, maximum]"."""
    return _convert.integer_option(value, name, minimum, maximum)


def real(value: object, name: str) -> float:
    """`value` (a Python or numpy real number: int or float, not a bool) as a float, for a float
    option before it reaches a binding (whose float parameters would raise pybind11's TypeError
    for a string, None or a list). NaN and Inf pass: each function checks its own range.
    Raises InputError "name = value: expected a real number", as `integer` words it."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        shown = repr(value)
        raise InputError(f"{name} = {shown if len(shown) <= 60 else shown[:57] + '...'}: expected a real number")
    return float(value)


def real_options(function: Callable[P, R]) -> Callable[P, R]:
    """Decorator: every parameter of `function` annotated ``float`` (or ``float | None``) goes through
    `real` before the body runs, so that a string, list, bool (or None where None is not allowed)
    given for a float option is an InputError naming the option, not pybind11's TypeError from the
    binding below. Other parameters pass untouched; a wrong call (unknown keyword) stays a TypeError."""
    signature = inspect.signature(function)
    options = {}
    for name, parameter in signature.parameters.items():
        annotation = parameter.annotation if isinstance(parameter.annotation, str) else getattr(
            parameter.annotation, "__name__", str(parameter.annotation))
        kinds = {part.strip() for part in annotation.replace("Optional[", "").rstrip("]").split("|")}
        if "float" in kinds and kinds <= {"float", "None", "int"}:
            options[name] = "None" in kinds

    @functools.wraps(function)
    def checked(*args: P.args, **kwargs: P.kwargs) -> R:
        bound = signature.bind(*args, **kwargs)
        for name, none_allowed in options.items():
            if name in bound.arguments and not (none_allowed and bound.arguments[name] is None):
                bound.arguments[name] = real(bound.arguments[name], name)
        return function(*bound.args, **bound.kwargs)

    return checked


def progress(callback: ProgressCallback) -> ProgressCallback:
    """`callback` if it is None or callable (what the bindings accept as a progress callback),
    for a function that passes it on only on some paths. Raises InputError otherwise."""
    _convert.check_progress(callback)
    return callback


def report(callback: ProgressCallback, fraction: float, stage: str) -> None:
    """Calls a progress callback (checked by `progress`) from Python code between steps, with the
    bindings' rules: False raises meshsmith.Cancelled, True or None goes on, anything else is an
    InputError naming the value; what the callback raises propagates."""
    if callback is None:
        return
    answer = callback(fraction, stage)
    if answer is None or answer is True or answer is np.True_:
        return
    if answer is False or answer is np.False_:
        raise Cancelled(f"{stage}: cancelled by the progress callback")
    shown = repr(answer)
    raise InputError(f"the progress callback returned {shown[:60]} ({type(answer).__name__}): expected True (go on), "
                     "False (cancel) or None")


def stage(callback: ProgressCallback, begin: float, end: float) -> ProgressCallback:
    """A progress callback for one stage of a longer function: it maps the stage's [0, 1] onto
    [begin, end] of `callback` (None stays None)."""
    if callback is None:
        return None
    outer: Callable[[float, str], Any] = callback

    def scaled(fraction: float, name: str) -> Any:
        return outer(begin + (end - begin) * fraction, name)
    return scaled


def finite(array: FloatArray, name: str) -> FloatArray:
    """`array` (from real_array) if it holds no NaN or Inf; else InputError naming the first."""
    bad = np.argwhere(~np.isfinite(array))
    if len(bad):
        where = ", ".join(str(i) for i in bad[0])
        raise InputError(f"{name}[{where}] is {array[tuple(bad[0])]}: expected finite numbers")
    return array

