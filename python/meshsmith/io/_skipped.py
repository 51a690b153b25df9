"""The readers' warning about what a file holds and they skip (shared by the io package's modules)."""
from __future__ import annotations

import os
import warnings
from typing import Sequence

from .._typing import PathLike


class SkippedDataWarning(UserWarning):
    """A reader skipped something the file holds (an unknown OBJ statement, partial colours...)."""


SkippedDataWarning.__module__ = "meshsmith.io"  # documented and caught as meshsmith.io.SkippedDataWarning


def warn_skipped(path: PathLike, messages: Sequence[str], stacklevel: int = 3) -> None:
    """One SkippedDataWarning per message, "path: message", attributed `stacklevel` frames up."""
    for message in messages:
        warnings.warn(f"{os.fsdecode(path)}: {message}", SkippedDataWarning, stacklevel=stacklevel + 1)
