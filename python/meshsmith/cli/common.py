"""Shared pieces of the command line: the progress bar and mesh reading."""
from __future__ import annotations

import sys
import time

from .. import io


class ProgressBar:
    """A progress callback `(fraction, stage) -> True` that draws a bar on stderr.

    Draws only when stderr is a terminal (or `force`), so logs and pipes stay clean.
    """

    def __init__(self, width: int = 30, force: bool = False, stream=None):
        self.stream = stream or sys.stderr
        self.enabled = force or self.stream.isatty()
        self.width, self.start, self.last_stage = width, time.perf_counter(), None

    def __call__(self, fraction: float, stage: str) -> bool:
        if self.enabled:
            filled = int(round(fraction * self.width))
            elapsed = time.perf_counter() - self.start
            self.stream.write(f"\r{stage:<24.24} [{'#' * filled}{'.' * (self.width - filled)}] "
                              f"{100 * fraction:5.1f}%  {elapsed:6.1f}s")
            if fraction >= 1.0:
                self.stream.write("\n")
            self.stream.flush()
        return True


def read_mesh(path: str):
    return io.read_mesh(path)
