"""Child process of tests/test_fuzz_inputs.py: runs a batch of calls of meshsmith's public API.

Reads a pickled list of :class:`Call` from standard input and writes, for each call, a line
``start <id>`` before it and ``done <id> <json outcome>`` after it, flushed at once: a call
that kills the process (a signal) or never returns (a hang) is the last one started, and the
parent names it. Outcomes say whether the call returned or raised (which exception), whether
the result holds a NaN, whether an argument was modified, and, where a reference call is given,
whether the result differs from the reference's.
"""
from __future__ import annotations

import copy
import dataclasses
import faulthandler
import importlib
import json
import math
import pickle
import sys
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np


class CallbackFailure(Exception):
    """Raised by a :class:`RaisingCallback`; must reach the caller as itself."""


class BadReturnCallback:
    """A progress callback that returns `value` (something other than bool or None)."""

    def __init__(self, value):
        self.value = value
        self.calls = 0

    def __call__(self, fraction, stage):
        self.calls += 1
        return self.value

    def __repr__(self):
        return f"<progress callback returning {self.value!r}>"


class RaisingCallback:
    """A progress callback that raises CallbackFailure."""

    def __init__(self):
        self.calls = 0

    def __call__(self, fraction, stage):
        self.calls += 1
        raise CallbackFailure("raised by the progress callback")

    def __repr__(self):
        return "<progress callback raising CallbackFailure>"


class CrashingCallback:
    """A progress callback that kills its process with SIGSEGV (a check of the parent's harness)."""

    calls = 0

    def __call__(self, fraction, stage):
        import os
        import signal
        os.kill(os.getpid(), signal.SIGSEGV)


class SleepingCallback:
    """A progress callback that never returns in time (a check of the parent's hang detection)."""

    calls = 0

    def __call__(self, fraction, stage):
        import time
        time.sleep(3600)


@dataclass
class Call:
    """One call: ``meshsmith.<target>(*args, **kwargs)``. With an `owner` (factory target, args),
    the target "module.Class.method" is called on a fresh ``factory(*args)``. `reference`: (args,
    kwargs) whose result the call must reproduce (non-contiguous, read-only or nested-list forms
    of valid arrays). `nan_allowed`: result fields documented to hold NaN."""

    id: int
    target: str
    args: tuple = ()
    kwargs: dict = field(default_factory=dict)
    owner: tuple | None = None
    reference: tuple | None = None
    nan_allowed: tuple = ()


def lookup(target: str):
    module_name, _, rest = target.partition(".")
    obj = importlib.import_module(f"meshsmith.{module_name}")
    for part in rest.split("."):
        obj = getattr(obj, part)
    return obj


def resolve(target: str, owner):
    if owner is None:
        return lookup(target)
    factory, args = owner
    return getattr(lookup(factory)(*args), target.rpartition(".")[2])


def same(a, b) -> bool:
    """Equality of nested results and arguments (NaN equals NaN, dtypes and shapes must match)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        if not (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)):
            return False
        if a.dtype != b.dtype or a.shape != b.shape:
            return False
        if a.dtype.kind == "O":
            return all(same(x, y) for x, y in zip(a.ravel(), b.ravel()))
        return bool(np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))
    if hasattr(a, "tocsc") and hasattr(b, "tocsc"):  # scipy.sparse
        return same(a.toarray(), b.toarray())
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if dataclasses.is_dataclass(a) and dataclasses.is_dataclass(b):
        return type(a) is type(b) and all(same(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    if isinstance(a, (int, str, bool, type(None))) or isinstance(b, (int, str, bool, type(None))):
        return a == b
    return True  # opaque objects (a KdTree, a ProgressiveMesh): compared through their methods


def nan_location(value, path="result", allowed=()) -> str | None:
    """Where the first NaN of a nested result is, or None ("result" in `allowed`: NaN anywhere)."""
    if path in allowed:
        return None
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc" and np.isnan(value).any():
            return path
        if value.dtype.kind == "O":
            for k, item in enumerate(value.ravel()):
                found = nan_location(item, f"{path}.flat[{k}]", allowed)
                if found:
                    return found
        return None
    if hasattr(value, "tocsc") and hasattr(value, "data"):
        return nan_location(np.asarray(value.data), f"{path}.data", allowed)
    if isinstance(value, float):
        return path if math.isnan(value) else None
    if isinstance(value, (list, tuple)):
        names = getattr(value, "_fields", None)
        for k, item in enumerate(value):
            name = names[k] if names else None
            if name in allowed:
                continue
            found = nan_location(item, f"{path}.{name}" if name else f"{path}[{k}]", allowed)
            if found:
                return found
        return None
    if isinstance(value, dict):
        for key, item in value.items():
            if key not in allowed:
                found = nan_location(item, f"{path}[{key!r}]", allowed)
                if found:
                    return found
        return None
    if dataclasses.is_dataclass(value):
        for f in dataclasses.fields(value):
            if f.name not in allowed:
                found = nan_location(getattr(value, f.name), f"{path}.{f.name}", allowed)
                if found:
                    return found
    return None


def callbacks_in(values):
    return [v for v in values if isinstance(v, (BadReturnCallback, RaisingCallback))]


def run(call: Call, reference_cache: dict) -> dict[str, Any]:
    outcome: dict[str, Any] = {}
    try:
        function = resolve(call.target, call.owner)
    except Exception as error:  # the valid owner could not be built: a table error in the test
        return {"setup_error": f"{type(error).__name__}: {error}"}
    callbacks = callbacks_in([*call.args, *call.kwargs.values()])
    calls_before = sum(c.calls for c in callbacks)
    before = copy.deepcopy((call.args, call.kwargs))
    flags = [(k, a.flags.writeable) for k, a in enumerate(call.args) if isinstance(a, np.ndarray)]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = function(*call.args, **call.kwargs)
    except BaseException as error:  # noqa: BLE001 (reported to the parent, which judges it)
        from meshsmith import InputError
        outcome.update(raised=f"{type(error).__module__}.{type(error).__qualname__}",
                       message=str(error)[:400], input_error=isinstance(error, InputError),
                       callback_failure=isinstance(error, CallbackFailure))
        result = None
    else:
        outcome["returned"] = True
        outcome["nan"] = nan_location(result, allowed=call.nan_allowed)
        if call.reference is not None:
            key = call.target  # the reference is the target's valid call: one per target
            if key not in reference_cache:
                reference_args, reference_kwargs = call.reference
                try:
                    reference_function = resolve(call.target, call.owner)
                    reference_cache[key] = ("result", reference_function(*reference_args, **reference_kwargs))
                except Exception as error:  # the valid call itself fails: reported by its own case
                    reference_cache[key] = ("error", f"{type(error).__name__}: {error}")
            kind, reference = reference_cache[key]
            if kind == "error":
                outcome["reference_error"] = reference
            else:
                outcome["differs"] = not same(result, reference)
    after = (call.args, call.kwargs)
    modified = [str(k) for k, (x, y) in enumerate(zip(before[0], after[0])) if not same(x, y)]
    modified += [k for k in before[1] if not same(before[1][k], after[1][k])]
    modified += [str(k) for k, writeable in flags if call.args[k].flags.writeable != writeable]
    outcome["modified"] = modified
    outcome["callback_calls"] = sum(c.calls for c in callbacks) - calls_before
    return outcome


def main() -> None:
    faulthandler.enable(file=sys.stderr)
    # The parent pickled the callbacks as fuzz_worker.*: make that name this module, or the
    # isinstance checks would compare against a second copy of it.
    sys.modules.setdefault("fuzz_worker", sys.modules[__name__])
    calls: list[Call] = pickle.load(sys.stdin.buffer)
    import meshsmith  # noqa: F401  (imported before the first "start": an import failure is no call's)
    reference_cache: dict = {}
    out = sys.stdout
    for call in calls:
        out.write(f"start {call.id}\n")
        out.flush()
        outcome = run(call, reference_cache)
        out.write(f"done {call.id} {json.dumps(outcome)}\n")
        out.flush()


if __name__ == "__main__":
    main()
