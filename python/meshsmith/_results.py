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
    """Mixin for dataclass results: ``iter(result)`` yields the fields in declaration order, or
    only those a subclass names in ``unpacks`` (a result whose leading fields are what callers
    unpack, with bookkeeping fields after them)."""

    __slots__ = ()
    unpacks: tuple[str, ...] | None = None  # class attribute, not a field: None unpacks every field

    def __iter__(self) -> Iterator[Any]:
        names = self.unpacks or [field.name for field in dataclasses.fields(self)]  # type: ignore[arg-type]
        return iter([getattr(self, name) for name in names])
