"""Old call forms that keep working for one release, with a DeprecationWarning (CHANGELOG.md)."""
from __future__ import annotations

import functools
import inspect
import warnings
from typing import Any, Callable, TypeVar, cast

__all__ = ["positional_options"]

_Function = TypeVar("_Function", bound=Callable[..., Any])


def positional_options(*names: str) -> Callable[[_Function], _Function]:
    """Accept, with a DeprecationWarning, options passed by position after they became keyword-only.

    names: the options that used to follow the positional parameters, in their old order. The
    decorated function keeps its new signature (``inspect.signature`` and type checkers see it);
    a call with extra positional values maps them onto ``names`` and warns once per call site.
    """

    def decorate(function: _Function) -> _Function:
        positional = sum(parameter.kind in (parameter.POSITIONAL_ONLY, parameter.POSITIONAL_OR_KEYWORD)
                         for parameter in inspect.signature(function).parameters.values())
        name = function.__qualname__

        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            if len(args) > positional:
                extra = args[positional:]
                if len(extra) > len(names):
                    raise TypeError(f"{name}() takes at most {positional + len(names)} positional arguments "
                                    f"({positional} from 0.2.0 on), {len(args)} were given")
                moved = dict(zip(names, extra))
                for key in moved:
                    if key in kwargs:
                        raise TypeError(f"{name}() got multiple values for argument '{key}'")
                warnings.warn(f"{name}(): pass {', '.join(f'{key}=' for key in moved)} by keyword; "
                              "options given by position are deprecated since meshsmith 0.2.0",
                              DeprecationWarning, stacklevel=2)
                kwargs.update(moved)
                args = args[:positional]
            return function(*args, **kwargs)

        return cast(_Function, wrapper)

    return decorate
