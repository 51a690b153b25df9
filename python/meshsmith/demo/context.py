"""The demo's input and what each stage returns: the context stages share and a report section."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import datasets


@dataclass
class DemoContext:
    out: Path
    name: str                 # what the input is, for captions
    V: np.ndarray
    F: np.ndarray
    uv: np.ndarray | None = None   # (m, 3, 2) per-corner texture coordinates, when the shape has natural ones
    figures: dict[str, Any] = field(default_factory=dict)  # every stage's numbers, saved as results.json


@dataclass
class Section:
    title: str
    text: str
    table: dict[str, Any] = field(default_factory=dict)
    images: list[tuple[str, str]] = field(default_factory=list)  # (file name, caption)


def builtin_shape() -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
    """The default demo input: a torus (genus 1) with its angular texture coordinates.

    The texture coordinates are per corner, (m, 3, 2): the angles wrap around twice on a torus,
    so each triangle that straddles a seam gets its corners unwrapped onto one side of it.
    """
    V, F = datasets.torus(major_radius=1.0, minor_radius=0.4, n_major=96, n_minor=48)
    around = np.arctan2(V[:, 1], V[:, 0])                       # angle around the main axis
    ring = np.hypot(V[:, 0], V[:, 1]) - 1.0
    tube = np.arctan2(V[:, 2], ring)                            # angle around the tube
    uv = np.column_stack([(around + np.pi) / (2 * np.pi), (tube + np.pi) / (2 * np.pi)])
    corners = uv[F]                                             # (m, 3, 2)
    straddles = corners.max(axis=1, keepdims=True) - corners.min(axis=1, keepdims=True) > 0.5
    corners = np.where(straddles & (corners < 0.5), corners + 1.0, corners)
    return "built-in torus (R = 1, r = 0.4)", V, F, corners
