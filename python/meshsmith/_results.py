"""Result objects: several outputs come back as one named result that also unpacks.

A NamedTuple unpacks by itself; a dataclass result derives from :class:`Unpackable`, which
iterates over its fields in declaration order (so ``a, b, *rest = result`` works) and has no
state of its own, so the result pickles as its fields (plain arrays and numbers).
"""
from __future__ import annotations

import dataclasses
from typing import Any, Iterator

__all__ = ["Unpackable"]


class Unpackable:
    """Mixin for dataclass results: ``iter(result)`` yields the fields in declaration order."""

    __slots__ = ()

    def __iter__(self) -> Iterator[Any]:
        return iter([getattr(self, field.name) for field in dataclasses.fields(self)])  # type: ignore[arg-type]
