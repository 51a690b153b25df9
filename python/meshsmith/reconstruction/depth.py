"""Depth images (§2.3): pinhole back-projection, pixel-grid meshes cut at depth discontinuities,
and the 2D scanline case; binding cpp/python/reconstruction_depth.cpp."""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .. import _arguments
from .._core import InputError
from .._core import reconstruction as _core
from .._typing import ArrayLike, FloatArray, IndexArray

__all__ = ["DepthPoints", "DepthMesh", "ScanlinePoints", "depth_to_points", "depth_to_mesh", "scanline_to_points"]


class DepthPoints(NamedTuple):
    """Result of :func:`depth_to_points`; unpacks as ``points, pixels``."""

    points: FloatArray  #: (n, 3) camera-frame positions of the valid pixels, row-major pixel order
    pixels: IndexArray  #: (n, 2) int64 (row, column) of each point


class DepthMesh(NamedTuple):
    """Result of :func:`depth_to_mesh`; unpacks as ``V, F, pixels``."""

    V: FloatArray       #: (n, 3) the points of :func:`depth_to_points` (every valid pixel)
    F: IndexArray       #: (m, 3) int64 triangles, normals facing the camera
    pixels: IndexArray  #: (n, 2) int64 (row, column) of each vertex


class ScanlinePoints(NamedTuple):
    """Result of :func:`scanline_to_points`; unpacks as ``points, samples, segments``."""

    points: FloatArray    #: (k, 2) positions of the valid samples
    samples: IndexArray   #: (k,) int64 index of each point's sample
    segments: IndexArray  #: (s, 2) int64 rows of points joined (neighbours without a depth jump)


@_arguments.real_options
def depth_to_points(depth: ArrayLike, fx: float, fy: float, cx: float, cy: float, *,
                    mask: ArrayLike | None = None, depth_scale: float = 1.0) -> DepthPoints:
    """Back-project a depth image through a pinhole camera (§2.3).

    depth: (h, w) array, row = image v, column = image u. Pixel (v, u) of depth d goes to
    z = d / depth_scale, x = (u − cx) z / fx, y = (v − cy) z / fy (the OpenCV / Open3D
    convention: camera at the origin looking along +z, y down; depth_scale = stored units per
    output unit, e.g. 1000 for millimetres to metres). Pixels whose depth is 0, negative, NaN or
    infinite (no measurement) are skipped, and so are those where mask (an (h, w) bool array) is
    False.

    Returns a :class:`DepthPoints` (points (n, 3), pixels (n, 2)). Raises InputError for an
    empty image or one that is not 2-D, a zero or non-finite focal length, a non-finite
    principal point, a depth_scale that is not positive, or a mask of another shape.
    """
    image, flags = _image_and_mask(depth, mask)
    return DepthPoints(*_core.depth_to_points(image, fx, fy, cx, cy, flags, depth_scale))


@_arguments.real_options
def depth_to_mesh(depth: ArrayLike, fx: float, fy: float, cx: float, cy: float, *,
                  mask: ArrayLike | None = None, depth_scale: float = 1.0, max_jump: float = 0.05) -> DepthMesh:
    """A triangle mesh of a depth image: neighbouring pixels joined except across depth
    discontinuities (§2.3).

    Arguments as :func:`depth_to_points`. Each 2×2 block of valid pixels gives two triangles
    (split along the diagonal of the smaller depth difference), three valid pixels give one. A
    triangle is dropped if one of its edges joins depths z_i, z_j with
    |z_i − z_j| > max_jump · min(z_i, z_j) (relative, so the cut does not depend on the unit or
    the distance; ``float("inf")`` keeps every triangle), which separates an object from the
    background behind it.

    Returns a :class:`DepthMesh` (V, F, pixels); V holds every valid pixel, so a pixel with no
    valid neighbour is an unreferenced vertex. Raises InputError as :func:`depth_to_points`, or
    for a negative or NaN max_jump.
    """
    image, flags = _image_and_mask(depth, mask)
    return DepthMesh(*_core.depth_to_mesh(image, fx, fy, cx, cy, flags, depth_scale, max_jump))


@_arguments.real_options
def scanline_to_points(depths: ArrayLike, *, center: ArrayLike = (0.0, 0.0), direction: ArrayLike = (0.0, 1.0),
                       opening_angle: float = np.pi / 3, max_jump: float = 0.05) -> ScanlinePoints:
    """The 2D case of §2.3: a 1D depth camera at ``center`` looking along ``direction`` with
    opening angle ``opening_angle`` (radians, in (0, π)) measured distances ``depths`` (n,)
    along its n rays.

    The image line lies at h = 1 / (2 tan(α/2)) in front of the centre and sample i at relative
    position x_i = (i + ½)/n on it, so s_i = c + h v + (x_i − ½) v⊥ with v⊥ = (v_y, −v_x), and
    p_i = c + d_i (s_i − c) / ‖s_i − c‖ (d_i is a distance along the ray, not a z). Samples
    whose depth is not finite or <= 0 are skipped; consecutive valid samples are joined by a
    segment unless |d_i − d_j| > max_jump · min(d_i, d_j).

    Returns a :class:`ScanlinePoints` (points (k, 2), samples (k,), segments (s, 2)). Raises
    InputError for empty depths, a center or direction that is not a finite 2-vector, a zero
    direction, an opening angle outside (0, π), or a negative max_jump.
    """
    return ScanlinePoints(*_core.scanline_to_points(depths, center, direction, opening_angle, max_jump))


def _image_and_mask(depth: ArrayLike, mask: ArrayLike | None) -> tuple[np.ndarray, "np.ndarray | None"]:
    image = _arguments.numbers(depth, "depth")
    if image.ndim != 2:
        raise InputError(f"depth has shape {image.shape}: expected an (h, w) image")
    if mask is None:
        return image, None
    flags = _arguments.numbers(mask, "mask", "flag")
    if flags.shape != image.shape:
        raise InputError(f"mask has shape {flags.shape}: expected the depth image's shape {image.shape}")
    return image, np.ascontiguousarray(flags).reshape(-1)
