"""Render chapter: PNG pictures of triangle meshes.

The pictures come from meshsmith's own software rasterizer (C++, ``meshsmith::render``): a
z-buffer over a supersampled image (3×3 samples per pixel by default), smooth shading from
per-vertex normals (or flat shading), a key, a fill and a rim light, back faces in a warm tint so
holes show, an optional per-vertex scalar field through a colormap, an optional checkerboard
through texture coordinates and an optional wireframe computed per pixel from the distance to
the triangle's edges. This module frames the camera, lays out several views in a grid and adds
the title and the colour bar; Pillow (``pip install 'meshsmith[viz]'``) draws the text and
writes the PNG.

    >>> image = render(V, F, "bunny.png")                        # (600, 800, 3) uint8
    >>> render(V, F, "curv.png", scalar=H, scalar_label="mean curvature")   # diverging map: H changes sign
    >>> render(V, F, "views.png", views=["front", "left", "top", "three-quarter"])

Conventions: the up axis is +y by default (``up="z"`` for CAD and scan data; any of x, y, z,
-x, -y, -z); the front view looks from +z towards -z (from -y with ``up="z"`` or ``"-z"``);
azimuth turns the camera about the up axis towards screen right (+x for y and z up: the right
view), elevation lifts it (the top view looks down the up axis).

Colours: a scalar field is drawn with a sequential map (viridis) when it has one sign and with a
diverging map centred on 0 (coolwarm) when it changes sign, unless `cmap` says otherwise. Its
range is the 2nd to 98th percentile unless `scalar_range` is given; values outside the range take
the end colours, and the colour bar then shows a triangle (an overflow arrow) at that end.
"""
from __future__ import annotations

import math
import os
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, NamedTuple, Sequence

import numpy as np

from . import _arguments
from ._core import InputError
from ._core import render as _core
from ._deprecation import positional_options
from ._typing import ArrayLike, FloatArray, PathLike

if TYPE_CHECKING:
    from .io import Polygons
    from .parametrization import Parametrization

__all__ = ["VIEWS", "COLORMAPS", "View", "Color", "Camera", "ViewAngles", "ScalarRange", "view_angles", "frame_camera", "colormap", "scalar_range",
           "default_colormap", "clipped_ends",
           "render", "render_uv_layout", "plot_planar", "parametrization_picture", "save_png"]

#: A view: a name from :data:`VIEWS` or an (azimuth, elevation) pair in degrees.
View = str | tuple[float, float]
#: A colour: a name, "#rrggbb", or an RGB triple of 0-255 ints or 0-1 floats.
Color = str | Sequence[float]


class ViewAngles(NamedTuple):
    """Result of :func:`view_angles`; unpacks as ``azimuth, elevation`` (degrees)."""

    azimuth: float
    elevation: float


class ScalarRange(NamedTuple):
    """Result of :func:`scalar_range`; unpacks as ``low, high``."""

    low: float
    high: float

#: Named views as (azimuth, elevation) in degrees.
VIEWS: dict[str, tuple[float, float]] = {
    "three-quarter": (35.0, 25.0),
    "front": (0.0, 0.0),
    "back": (180.0, 0.0),
    "left": (-90.0, 0.0),
    "right": (90.0, 0.0),
    "top": (0.0, 90.0),
    "bottom": (0.0, -90.0),
}

#: Colormap names accepted by ``cmap``.
COLORMAPS: tuple[str, ...] = tuple(_core.colormap_names())

_FRONT_COLOR = (0.60, 0.68, 0.80)      # soft gray-blue
_BACK_COLOR = (0.88, 0.56, 0.42)       # warm tint for back faces
_WIREFRAME_COLOR = (0.10, 0.11, 0.14)
_GRADIENT = ((1.0, 1.0, 1.0), (0.88, 0.90, 0.94))  # top, bottom (sRGB in [0, 1])
_TEXT_COLOR = (40, 44, 52)


@dataclass(frozen=True)
class Camera:
    """A look-at camera.

    eye, target: (3,) positions; up: (3,) approximate screen-up direction (not parallel to
    target - eye). fov_y_deg: vertical field of view of the perspective projection.
    orthographic: parallel projection whose view is ortho_height world units high.
    """

    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    up: tuple[float, float, float]
    fov_y_deg: float = 30.0
    orthographic: bool = False
    ortho_height: float = 2.0


def view_angles(view: View) -> ViewAngles:
    """(azimuth, elevation) in degrees of a view name from :data:`VIEWS` or an (az, el) pair.

    Raises InputError for an unknown name or a pair that is not two finite numbers.
    """
    if isinstance(view, str):
        if view not in VIEWS:
            raise InputError(f"unknown view '{view}': use one of {', '.join(VIEWS)} "
                             "or an (azimuth, elevation) pair in degrees")
        return ViewAngles(*VIEWS[view])
    try:
        azimuth, elevation = (float(a) for a in view)
    except (TypeError, ValueError):
        raise InputError(f"view {view!r} is neither a view name ({', '.join(VIEWS)}) "
                         "nor an (azimuth, elevation) pair") from None
    if not (math.isfinite(azimuth) and math.isfinite(elevation)):
        raise InputError(f"view {view!r}: azimuth and elevation must be finite")
    return ViewAngles(azimuth, elevation)


@positional_options("view")
def frame_camera(V: ArrayLike, *, view: View = "three-quarter", size: tuple[int, int] = (800, 600),
                 up: str = "y", fov: float = 30.0, orthographic: bool = False, margin: float = 0.06) -> Camera:
    """The camera that frames the vertices V from a view, as tightly as `margin` allows.

    V: (n, 3) float array. view: a name from :data:`VIEWS` or (azimuth, elevation) in degrees.
    size: (width, height) of the picture (its aspect ratio matters). up: the world axis that
    points up: "y", "z", "x", "-x", "-y" or "-z". fov: vertical field of view in degrees (perspective). margin: free
    border on the tight side as a fraction of the picture size, in [0, 0.45).
    The perspective distance and the lateral offset are solved exactly so every vertex is in
    view and the silhouette is centred. Raises InputError for bad arguments.
    """
    width, height = _check_size(size)
    azimuth, elevation = view_angles(view)
    found = _core.frame_camera(V, azimuth, elevation, up=up, aspect=width / height,
                               fov_y_deg=_arguments.real(fov, "fov"), orthographic=bool(orthographic),
                               margin=_arguments.real(margin, "margin"))
    return Camera(eye=tuple(found["eye"]), target=tuple(found["target"]), up=tuple(found["up"]),
                  fov_y_deg=found["fov_y_deg"], orthographic=found["orthographic"],
                  ortho_height=found["ortho_height"])


def colormap(name: str, steps: int = 256) -> FloatArray:
    """(steps, 3) float array: sRGB colours in [0, 1] of colormap `name` (viridis, magma, coolwarm)."""
    return _core.colormap_table(name, steps)


def scalar_range(scalar: ArrayLike, vertex_count: int, cmap: str | None = None) -> ScalarRange:
    """The default colouring range of a per-vertex field: its 2nd and 98th percentiles.

    For a diverging colormap (coolwarm; the default for a field that changes sign, see
    :func:`default_colormap`) and a field whose range contains zero, the range is made
    symmetric, [-m, m], so zero is the neutral colour. scalar: (vertex_count,) finite floats.
    Raises InputError for a wrong length or a NaN/Inf (naming the first one).
    """
    return _robust_range(scalar, vertex_count, default_colormap(scalar) if cmap is None else cmap)


def default_colormap(scalar: ArrayLike) -> str:
    """The colormap :func:`render` uses for a field when `cmap` is not given: "coolwarm"
    (diverging, centred on 0) when the values change sign, else "viridis" (sequential)."""
    values = _finite_scalar(scalar)
    return "coolwarm" if values.size and values.min() < 0.0 < values.max() else "viridis"


def clipped_ends(scalar: ArrayLike, low: float, high: float) -> tuple[bool, bool]:
    """(some value < low, some value > high): which ends of the colour bar get an overflow arrow."""
    values = _finite_scalar(scalar)
    low, high = _arguments.real(low, "low"), _arguments.real(high, "high")
    return bool(values.size and values.min() < low), bool(values.size and values.max() > high)


def _robust_range(scalar: ArrayLike, vertex_count: int, cmap: str) -> ScalarRange:
    diverging = _core.colormap_is_diverging(cmap)
    low, high = _core.scalar_range(scalar, vertex_count, diverging)
    return ScalarRange(float(low), float(high))


def render(V: ArrayLike, F: ArrayLike | Polygons, path: PathLike | None = None, *, size: tuple[int, int] = (800, 600),
           view: View = "three-quarter", views: Sequence[View] | None = None, columns: int | None = None,
           camera: Camera | None = None, up: str = "y", projection: str = "perspective", fov: float = 30.0,
           scalar: ArrayLike | None = None, cmap: str | None = None, scalar_range: tuple[float, float] | None = None,
           scalar_label: str | None = None, colorbar: bool | None = None,
           wireframe: bool | Literal["auto"] | None = None, wireframe_width: float = 1.0,
           uv: ArrayLike | None = None,
           checker_size: float | None = None, flat: bool = False, crease_angle: float = 60.0,
           lighting: bool = True, color: Sequence[float] = _FRONT_COLOR, back_color: Sequence[float] = _BACK_COLOR,
           title: str | None = None, background: Color | tuple[Color, Color] = "gradient",
           supersample: int = 3) -> np.ndarray:
    """Render a shaded picture of the mesh (V, F); write it as a PNG if `path` is given.

    V: (n, 3) float array of vertex positions. F: (m, 3) integer array of triangles, (m, s) of
    polygons with s > 3 corners (e.g. (k, 4) quads) or :class:`meshsmith.io.Polygons`; polygons are
    drawn as fans of triangles whose wireframe shows the polygons' edges only.
    path: PNG file to write (str or Path), or None to only return the image.
    size: (width, height) in pixels of the picture, or of each panel when `views` is given.
    view: a name from :data:`VIEWS` ("three-quarter", "front", "back", "left", "right", "top",
        "bottom") or an (azimuth, elevation) pair in degrees.
    views: a list of such views: one panel per view in a grid of `columns` columns (default:
        all in one row up to 3 views, else ceil(sqrt(k))); the picture is then exactly
        (columns * width, rows * height) and each panel is labelled with its view.
    camera: a :class:`Camera` to use instead of framing `view` automatically (single view only).
    up: the world axis that points up: "y" (default), "z", "x", "-x", "-y" or "-z".
    projection: "perspective" or "orthographic".
    fov: vertical field of view in degrees of the perspective camera.
    scalar: (n,) float array, one finite value per vertex, interpolated per pixel and coloured
        through `cmap` ("viridis", "magma" or "coolwarm"; default: :func:`default_colormap`,
        coolwarm centred on 0 when the values change sign, else viridis).
    scalar_range: (low, high) mapped onto the ends of the colormap; default: the 2nd and 98th
        percentiles, symmetric about 0 for coolwarm when the values change sign. Values
        outside take the end colours.
    scalar_label: text above the colour bar. colorbar: draw the colour bar (default: when
        `scalar` is given and the picture is wide enough); it shows the low, middle and high
        values of the range, and an overflow arrow (a triangle in the end colour) at each end
        beyond which some values were clipped.
    wireframe: True draws every face edge (thin dark lines, anti-aliased); "auto" draws
        them when there are few enough faces to read (#F <= width * height / 100); None
        (default): True for polygon meshes (quads), False for triangles.
        wireframe_width: line width in pixels (lines of triangles only a few pixels high fade).
    uv: texture coordinates shown as a checkerboard, (n, 2) per vertex or (m, 3, 2) per
        corner. checker_size: side of a checker square in UV units (default: an eighth of the
        larger UV extent).
    flat: one normal per face (faceted look) instead of smooth per-vertex normals.
    crease_angle: smooth shading keeps edges whose dihedral angle exceeds this (degrees)
        crisp, as on CAD parts; 180 smooths everything.
    lighting: False draws unlit colours (exact colormap colours).
    color, back_color: sRGB triples in [0, 1] of the front and back faces' material.
    title: text drawn at the top of the picture.
    background: "gradient" (white to light gray-blue), "white", "transparent" (RGBA output,
        alpha = coverage), a colour (a name, "#rrggbb", or an RGB triple of 0-255 ints or
        0-1 floats) or a (top, bottom) pair of colours for a vertical gradient.
    supersample: samples per pixel along each axis (1 to 4) for anti-aliasing.

    Returns the picture as a uint8 array of shape (height, width, 3), or (height, width, 4)
    with a transparent background. Raises InputError (a ValueError) for an invalid mesh, a
    scalar of the wrong length or with NaN/Inf, UVs of the wrong shape, a size <= 0, an unknown
    view, colormap, projection or background; ImportError when Pillow is needed (a title, a
    colour bar, view labels or a path) and missing.
    """
    width, height = _check_size(size)
    view_list = list(views) if views is not None else [view]
    if not view_list:
        raise InputError("views is empty: give at least one view")
    angles = [view_angles(v) for v in view_list]
    if camera is not None and len(view_list) > 1:
        raise InputError("camera and several views are exclusive: give one or the other")
    if projection not in ("perspective", "orthographic"):
        raise InputError(f"unknown projection '{projection}': use 'perspective' or 'orthographic'")
    if cmap is None:
        cmap = "viridis" if scalar is None else default_colormap(scalar)
    if cmap not in COLORMAPS:
        raise InputError(f"unknown colormap '{cmap}': use one of {', '.join(COLORMAPS)}")
    if wireframe not in (True, False, "auto", None):
        raise InputError(f"wireframe must be True, False, 'auto' or None, got {wireframe!r}")
    F, wireframe_edges, uv = _as_triangles(F, uv)
    if wireframe is None:
        wireframe = wireframe_edges is not None
    supersample = _arguments.integer(supersample, "supersample", 1, 4)
    gradient, transparent = _background(background)
    n_vertices, n_faces = _validated_counts(V, F)

    low = high = None
    clipped = (False, False)
    colorbar_requested = bool(colorbar)
    if scalar is not None:
        if scalar_range is None:
            low, high = _robust_range(scalar, n_vertices, cmap)
        else:
            low, high = _check_range(scalar_range)
        clipped = clipped_ends(scalar, low, high)
        if colorbar is None:
            colorbar = True
    colorbar = bool(colorbar) and scalar is not None

    count = len(view_list)
    if columns is None:
        columns = count if count <= 3 else math.ceil(math.sqrt(count))
    columns = min(_arguments.integer(columns, "columns", 1, _core.max_image_side), count)
    rows = math.ceil(count / columns)
    total_width, total_height = columns * width, rows * height

    # Layout: a title band on top, a colour bar strip on the right, panels in the rest.
    title_height = max(22, round(0.065 * total_height)) if title else 0
    bar_width = max(64, round(0.14 * total_width)) if colorbar else 0
    if colorbar and not colorbar_requested and bar_width > total_width // 3:
        colorbar, bar_width = False, 0  # the default colour bar is left out of tiny pictures
    grid_width, grid_height = total_width - bar_width, total_height - title_height
    if grid_width < columns or grid_height < rows:
        raise InputError(f"size {size} is too small for the title and the colour bar")

    canvas = _background_canvas(total_width, total_height, gradient, transparent)
    wire = wireframe
    if wireframe == "auto":
        wire = n_faces <= (grid_width // columns) * (grid_height // rows) / 100
    options = dict(
        width=0, height=0, supersample=supersample, smooth_shading=not flat,
        crease_angle_deg=_arguments.real(crease_angle, "crease_angle"),
        lighting=bool(lighting), wireframe=bool(wire), wireframe_width=_arguments.real(wireframe_width, "wireframe_width"),
        front_color=_unit_color(color, "color"), back_color=_unit_color(back_color, "back_color"),
        wireframe_color=_WIREFRAME_COLOR, transparent_background=transparent,
        scalar=scalar, scalar_min=0.0 if low is None else float(low),
        scalar_max=1.0 if high is None else float(high), colormap=cmap, uv=uv,
        checker_size=0.0 if checker_size is None else _arguments.real(checker_size, "checker_size"),
        wireframe_edges=wireframe_edges)

    labels = []
    for index, (azimuth, elevation) in enumerate(angles):
        row, column = divmod(index, columns)
        x0, x1 = column * grid_width // columns, (column + 1) * grid_width // columns
        y0 = title_height + row * grid_height // rows
        y1 = title_height + (row + 1) * grid_height // rows
        panel_width, panel_height = x1 - x0, y1 - y0
        cam = camera if camera is not None else frame_camera(
            V, view=(azimuth, elevation), size=(panel_width, panel_height), up=up, fov=fov,
            orthographic=projection == "orthographic")
        top = _gradient_at(gradient, y0, total_height)
        bottom = _gradient_at(gradient, y1 - 1, total_height)
        options.update(width=panel_width, height=panel_height,
                       background_top=top, background_bottom=bottom)
        panel = _core.render_mesh(V, F, eye=cam.eye, target=cam.target, up=cam.up,
                                  fov_y_deg=cam.fov_y_deg, orthographic=cam.orthographic,
                                  ortho_height=cam.ortho_height, **options)
        canvas[y0:y1, x0:x1] = panel if transparent else panel[..., :3]
        if count > 1:
            labels.append(((x0, y0), view_list[index]))

    if title or colorbar or labels:
        canvas = _annotate(canvas, title=title, title_height=title_height, labels=labels,
                           colorbar=(cmap, low, high, scalar_label, bar_width, clipped) if colorbar else None,
                           transparent=transparent)
    if path is not None:
        save_png(canvas, path)
    return canvas


def render_uv_layout(UV: ArrayLike, F: ArrayLike, path: PathLike | None = None, *, size: tuple[int, int] = (800, 800),
                     scalar: ArrayLike | None = None, cmap: str | None = None,
                     scalar_range: tuple[float, float] | None = None, scalar_label: str | None = None,
                     title: str | None = None, background: Color | tuple[Color, Color] = "white",
                     supersample: int = 3) -> np.ndarray:
    """Draw a 2D parametrization: the triangles of F laid out at their texture coordinates.

    UV: (n, 2) float array of per-vertex texture coordinates. F: (m, 3) integer triangles.
    Triangles are filled light blue with dark edges; flipped triangles (clockwise in UV, i.e.
    fold-overs) are filled in the warm back-face tint so they stand out. An optional per-vertex
    `scalar` (n,) colours the layout instead (e.g. a distortion measure), with a colour bar.
    The layout keeps its aspect ratio (orthographic view). Other arguments as in
    :func:`render`. Returns the (height, width, 3) uint8 picture; writes a PNG if `path` is given.
    Raises InputError for a UV array that is not (n, 2), bad faces, or bad arguments.
    """
    V = _core.uv_layout_vertices(UV)  # checks UV: (n, 2) real numbers
    return render(V, F, path, size=size, view="front", projection="orthographic",
                  scalar=scalar, cmap=cmap, scalar_range=scalar_range, scalar_label=scalar_label,
                  wireframe=True, lighting=False, color=(0.80, 0.87, 0.96),
                  back_color=(0.95, 0.45, 0.35), title=title, background=background,
                  supersample=supersample)


def plot_planar(path: PathLike | None = None, *, points: ArrayLike | None = None,
                triangles: tuple[ArrayLike, ArrayLike] | None = None,
                segments: tuple[ArrayLike, ArrayLike] | None = None, polygons: Sequence[FloatArray] | None = None,
                highlight: ArrayLike | None = None, size: tuple[int, int] = (800, 800), title: str | None = None,
                supersample: int = 3) -> np.ndarray:
    """Draw planar (2D) geometry: triangulations, curves, cells and points, for the tessellation
    chapter's pictures.

    points: (n, 2) array drawn as dots. triangles: (V (k, 2), F (m, 3)) drawn filled light blue
    with dark edges. segments: (P (k, 2), E (e, 2)) drawn as thick dark lines (e.g. a
    reconstructed curve). polygons: a list of (j, 2) arrays (e.g. Voronoi or power cells) drawn
    as outlines, each filled with a pale colour of its own. highlight: (h, 2) points drawn larger
    in red (e.g. Steiner points or medial-axis vertices). All layers share one view that keeps
    the aspect ratio and frames everything given. Returns the (height, width, 3) uint8 picture;
    writes a PNG if `path` is given. Raises InputError for bad shapes or nothing to draw.
    """
    Image, ImageDraw, _ = _pillow()
    width, height = _check_size(size)
    scale_factor = _arguments.integer(supersample, "supersample", 1, 4)

    def planar(array: ArrayLike, name: str) -> FloatArray:
        return _arguments.finite(_arguments.real_array(array, name, 2), name)

    def pair(value: Any, name: str) -> tuple[Any, Any]:
        try:
            first, second = value
        except (TypeError, ValueError):
            raise InputError(f"{name} must be a pair (points, indices), got {type(value).__name__}") from None
        return first, second

    layers = []
    if triangles is not None:
        TV, TF = pair(triangles, "triangles")
        TV, TF = planar(TV, "triangles vertices"), _arguments.index_array(TF, "triangles faces", 3)
        if TF.size and (TF.min() < 0 or TF.max() >= len(TV)):
            raise InputError("triangles faces must be (m, 3) indices into the triangle vertices")
        layers.append(TV)
    if segments is not None:
        SP, SE = pair(segments, "segments")
        SP, SE = planar(SP, "segment points"), _arguments.index_array(SE, "segments edges", 2)
        if SE.size and (SE.min() < 0 or SE.max() >= len(SP)):
            raise InputError("segments edges must be (e, 2) indices into the segment points")
        layers.append(SP[np.unique(SE)] if SE.size else SP[:0])
    cells = [planar(cell, f"polygons[{i}]") for i, cell in enumerate([] if polygons is None else polygons)
             if not (isinstance(cell, (list, tuple, np.ndarray)) and len(cell) == 0)]  # empty cells: nothing
    layers.extend(cells)
    if points is not None:
        points = planar(points, "points")
        layers.append(points)
    if highlight is not None:
        highlight = planar(highlight, "highlight")
        layers.append(highlight)
    everything = np.vstack([layer for layer in layers if len(layer)]) if any(len(l) for l in layers) else None
    if everything is None:
        raise InputError("plot_planar: nothing to draw")

    title_height = 44 if title else 0
    low, high = everything.min(axis=0), everything.max(axis=0)
    extent = np.maximum(high - low, 1e-12 * max(1.0, float(np.abs(everything).max())))
    margin = 24
    usable = np.array([width - 2 * margin, height - title_height - 2 * margin], dtype=float)
    scale = float(np.min(usable / extent))
    offset = np.array([margin, title_height + margin]) + 0.5 * (usable - extent * scale)

    def to_pixels(xy: FloatArray) -> FloatArray:
        pixel = (xy - low) * scale + offset
        pixel[:, 1] = height - pixel[:, 1] + title_height  # y up
        return pixel * scale_factor

    image = Image.new("RGB", (width * scale_factor, height * scale_factor), (255, 255, 255))
    draw = ImageDraw.Draw(image)
    line = max(1, scale_factor)
    palette = [(221, 232, 247), (250, 228, 214), (224, 240, 221), (244, 224, 240), (250, 242, 204),
               (222, 238, 240)]
    for index, cell in enumerate(cells):
        corners = [tuple(p) for p in to_pixels(cell)]
        if len(corners) >= 3:
            draw.polygon(corners, fill=palette[index % len(palette)], outline=(60, 70, 90))
            draw.line(corners + [corners[0]], fill=(60, 70, 90), width=line)
    if triangles is not None:
        pixels = to_pixels(TV)
        for face in TF:
            corners = [tuple(pixels[i]) for i in face]
            draw.polygon(corners, fill=(204, 222, 245))
            draw.line(corners + [corners[0]], fill=(45, 55, 75), width=line)
    if segments is not None and SE.size:
        pixels = to_pixels(SP)
        for a, b in SE:
            draw.line([tuple(pixels[a]), tuple(pixels[b])], fill=(20, 30, 50), width=3 * line)
    for dots, radius, colour in ((points, 2.2, (30, 60, 140)), (highlight, 3.5, (205, 50, 40))):
        if dots is None:
            continue
        r = radius * scale_factor
        for x, y in to_pixels(dots):
            draw.ellipse([x - r, y - r, x + r, y + r], fill=colour)
    image = image.resize((width, height), Image.LANCZOS)
    if title:
        ImageDraw.Draw(image).text((width / 2, 22), title, fill=(40, 40, 48), font=_font(20), anchor="mm")
    canvas = np.asarray(image, dtype=np.uint8).copy()
    if path is not None:
        save_png(canvas, path)
    return canvas


def parametrization_picture(result: Parametrization, path: PathLike, title: str) -> None:
    """One PNG: the UV layout (coloured by angle distortion) beside the surface under a checkerboard.

    result: a :class:`meshsmith.parametrization.Parametrization`; path: the PNG to write; title:
    drawn over the surface. The 0.1 order ``(path, result, title)`` still works, with a
    DeprecationWarning.
    """
    if isinstance(result, (str, os.PathLike)):
        warnings.warn("parametrization_picture(): pass the result first, then the path (since meshsmith 0.2.0)",
                      DeprecationWarning, stacklevel=2)
        result, path = path, result  # type: ignore[assignment]
    corners = result.uv[result.F]  # per corner, so seams cut by cut_to_disk show in the texture
    V, F = (result.cut.V, result.F) if result.cut is not None else (result.V, result.F)
    uv = np.where(np.isnan(result.uv), corners[0, 0], result.uv)  # unreferenced vertices' NaN rows: out of the way
    conformal = np.nan_to_num(result.distortion.vertex_conformal, nan=1.0)  # NaN: a vertex with no face
    layout = render_uv_layout(uv, result.F, size=(640, 640), scalar=conformal,
                                     scalar_range=(1.0, 2.0), scalar_label="angle distortion σ1/σ2",
                                     title=f"UV layout ({result.method})")
    checker = float(np.ptp(uv, axis=0).max()) / 24
    surface = render(V, F, uv=corners, checker_size=checker, size=(640, 640), title=title)
    save_png(np.concatenate([layout, surface], axis=1), path)


# ---- helpers ----------------------------------------------------------------------------------

def _check_size(size: Any) -> tuple[int, int]:
    try:
        width, height = size
    except (TypeError, ValueError):
        raise InputError(f"size must be (width, height) with positive integers, got {size!r}") from None
    return (_arguments.integer(width, "size[0] (width)", 1, _core.max_image_side),
            _arguments.integer(height, "size[1] (height)", 1, _core.max_image_side))


def _finite_scalar(scalar: ArrayLike) -> np.ndarray:
    """The finite values of a (n,) scalar, for choosing the colormap (the core checks it fully later)."""
    values = _arguments.real_array(scalar, "scalar")
    return values[np.isfinite(values)]


def _check_range(value: Any) -> tuple[float, float]:
    try:
        low, high = (float(v) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"scalar_range must be a (low, high) pair, got {value!r}") from None
    if not (math.isfinite(low) and math.isfinite(high) and low <= high):
        raise InputError(f"scalar_range must be finite with low <= high, got {value!r}")
    return low, high


def _as_triangles(F: Any, uv: Any) -> tuple[Any, Any, Any]:
    """(triangles, wireframe edge masks or None, uv) for the rasterizer: polygon faces ((m, s > 3)
    arrays, Polygons) as their fans, whose diagonals the wireframe leaves out; per-corner uv of
    (m, s, 2) follows the fan's corners. Triangles pass through unchanged."""
    from .io import Polygons
    if not isinstance(F, Polygons):
        faces = _arguments.numbers(F, "F", "index")
        if faces.ndim != 2 or faces.shape[1] <= 3:
            return F, None, uv
        F = Polygons.from_array(faces)
    triangles, masks, _ = F.fan_triangles()
    if uv is not None and np.ndim(uv) == 3:
        corners = _arguments.numbers(uv, "uv")
        sizes = set(F.sizes.tolist())
        size = sizes.pop() if len(sizes) == 1 else -1
        if corners.shape != (len(F), size, 2):
            raise InputError(f"uv has shape {corners.shape}: expected (#V, 2) per vertex or (#F, {size}, 2) per "
                             "corner (polygons of one size)")
        first = np.repeat(np.arange(len(F)), size - 2)
        step = np.tile(np.arange(1, size - 1), len(F))
        uv = np.stack([corners[first, 0], corners[first, step], corners[first, step + 1]], 1)
    return triangles, masks, uv


def _validated_counts(V: Any, F: Any) -> tuple[int, int]:
    """(#V, #F) after the core's checks of the mesh (dtype, shape, NaN/Inf, index range)."""
    from ._core import core as _core_checks
    _core_checks.validate_mesh(V, F)
    return len(V), len(F)


def _unit_color(value: Any, name: str) -> tuple[float, ...]:
    try:
        rgb = tuple(float(c) for c in value)
    except (TypeError, ValueError):
        rgb = ()
    if len(rgb) != 3 or not all(0.0 <= c <= 1.0 for c in rgb):
        raise InputError(f"{name} must be an sRGB triple in [0, 1], got {value!r}")
    return rgb


def _parse_color(value: Any) -> tuple[float, ...]:
    """A colour name, '#rrggbb', or a triple of 0-255 ints / 0-1 floats → sRGB in [0, 1]."""
    rgb: tuple[Any, ...]
    if isinstance(value, str):
        named = {"white": (255, 255, 255), "black": (0, 0, 0)}
        if value in named:
            rgb = named[value]
        else:
            try:
                from PIL import ImageColor
                rgb = ImageColor.getrgb(value)[:3]
            except ImportError:
                raise ImportError(_PILLOW_MISSING) from None
            except ValueError:
                raise InputError(f"unknown background colour '{value}'") from None
        return tuple(c / 255.0 for c in rgb)
    try:
        rgb = tuple(value)
    except TypeError:
        raise InputError(f"background colour {value!r} is not a colour") from None
    if len(rgb) != 3:
        raise InputError(f"background colour {value!r} must have 3 components")
    if all(isinstance(c, (int, np.integer)) for c in rgb):
        if not all(0 <= c <= 255 for c in rgb):
            raise InputError(f"background colour {value!r}: integers must be in 0..255")
        return tuple(c / 255.0 for c in rgb)
    rgb = tuple(float(c) for c in rgb)
    if not all(0.0 <= c <= 1.0 for c in rgb):
        raise InputError(f"background colour {value!r}: floats must be in [0, 1]")
    return rgb


def _background(background: Any) -> tuple[tuple[Any, Any], bool]:
    """(gradient (top, bottom) in [0, 1], transparent?) for the `background` argument."""
    if isinstance(background, str) and background == "gradient":
        return _GRADIENT, False
    if isinstance(background, str) and background == "transparent":
        return ((1.0, 1.0, 1.0), (1.0, 1.0, 1.0)), True
    if (isinstance(background, (tuple, list)) and len(background) == 2
            and not isinstance(background[0], (int, float, np.number))):
        return (_parse_color(background[0]), _parse_color(background[1])), False
    color = _parse_color(background)
    return (color, color), False


def _gradient_at(gradient: Any, row: int, total_rows: int) -> tuple[float, ...]:
    t = row / (total_rows - 1) if total_rows > 1 else 0.0
    top, bottom = np.asarray(gradient[0]), np.asarray(gradient[1])
    return tuple(float(c) for c in (1.0 - t) * top + t * bottom)


def _background_canvas(width: int, height: int, gradient: Any, transparent: bool) -> np.ndarray:
    if transparent:
        return np.zeros((height, width, 4), dtype=np.uint8)
    t = np.linspace(0.0, 1.0, height)[:, None] if height > 1 else np.zeros((1, 1))
    rows = (1.0 - t) * np.asarray(gradient[0])[None, :] + t * np.asarray(gradient[1])[None, :]
    rows = np.clip(np.rint(rows * 255.0), 0, 255).astype(np.uint8)
    return np.ascontiguousarray(np.broadcast_to(rows[:, None, :], (height, width, 3)))


_PILLOW_MISSING = ("meshsmith.render needs Pillow for PNG files, titles and colour bars: "
                   "pip install 'meshsmith[viz]' (or pip install pillow)")


def _pillow() -> tuple[Any, Any, Any]:
    try:
        from PIL import Image, ImageDraw, ImageFont
    except ImportError:
        raise ImportError(_PILLOW_MISSING) from None
    return Image, ImageDraw, ImageFont


def _font(size: int) -> Any:
    _, _, ImageFont = _pillow()
    for name in ("DejaVuSans.ttf", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                 "Arial.ttf", "LiberationSans-Regular.ttf"):
        try:
            return ImageFont.truetype(name, size)
        except OSError:
            continue
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1 has only the fixed bitmap font
        return ImageFont.load_default()


def _format_ticks(values: Sequence[float]) -> list[str]:
    """Labels for the colour bar's ticks, with the precision their spread needs."""
    low, high = min(values), max(values)
    magnitude = max(abs(low), abs(high))
    if magnitude == 0.0:
        return ["0" for _ in values]
    if magnitude >= 1e5 or magnitude < 1e-3:
        return [f"{v:.3g}" for v in values]
    if all(float(v).is_integer() for v in values):
        return [f"{int(v)}" for v in values]
    span = high - low
    digits = max(0, 2 - int(math.floor(math.log10(span)))) if span > 0 else 3
    return ["0" if v == 0.0 else f"{v:.{min(digits, 6)}f}" for v in values]


def _annotate(canvas: np.ndarray, *, title: str | None, title_height: int, labels: list[Any], colorbar: Any,
              transparent: bool) -> np.ndarray:
    """Title, view labels and the colour bar, drawn with Pillow."""
    Image, ImageDraw, _ = _pillow()
    image = Image.fromarray(canvas, "RGBA" if transparent else "RGB")
    draw = ImageDraw.Draw(image)
    width, height = image.size
    text_fill = _TEXT_COLOR + ((255,) if transparent else ())
    if title:
        font = _font(max(12, int(title_height * 0.55)))
        draw.text((width // 2, title_height // 2 + 2), str(title), fill=text_fill, font=font,
                  anchor="mm")
    if labels:
        font = _font(max(10, min(18, height // 40)))
        for (x, y), name in labels:
            text = name if isinstance(name, str) else f"az {name[0]:g}°, el {name[1]:g}°"
            draw.text((x + 8, y + 6), text, fill=text_fill, font=font)
    if colorbar is not None:
        cmap, low, high, label, bar_width, clipped = colorbar
        _draw_colorbar(image, draw, cmap, low, high, label, bar_width, title_height, text_fill, clipped)
    return np.asarray(image).copy()


@dataclass(frozen=True)
class _ColorbarLayout:
    """Where the colour bar goes in a picture: the bar's left x, top y, thickness and height in
    pixels, the height of the overflow arrows drawn above and below it, and the font size."""

    x: int
    y: int
    thickness: int
    height: int
    arrow: int
    font_size: int


def _colorbar_layout(width: int, height: int, bar_width: int, top_offset: int) -> _ColorbarLayout:
    """The colour bar's place in a (width, height) picture whose rightmost `bar_width` columns
    below `top_offset` (the title band) hold it."""
    strip_x = width - bar_width
    available = height - top_offset
    thickness = max(10, min(22, bar_width // 5))
    arrow = max(6, thickness * 3 // 4)
    bar_height = max(10, int(available * 0.62) - 2 * arrow)
    font_size = max(10, min(16, bar_width // 6, available // 22))
    x = strip_x + max(6, bar_width // 8)
    y = top_offset + (available - bar_height) // 2 + font_size // 2
    return _ColorbarLayout(x, y, thickness, bar_height, arrow, font_size)


def _draw_colorbar(image, draw, cmap, low, high, label, bar_width, top_offset, text_fill, clipped):
    Image, _, _ = _pillow()
    width, height = image.size
    strip_x = width - bar_width
    layout = _colorbar_layout(width, height, bar_width, top_offset)
    bar_x, bar_y, bar_thickness, bar_height = layout.x, layout.y, layout.thickness, layout.height
    font_size = layout.font_size
    font = _font(font_size)
    table = colormap(cmap, bar_height)[::-1]  # high values on top
    pixels = np.clip(np.rint(table * 255.0), 0, 255).astype(np.uint8)
    bar = np.broadcast_to(pixels[:, None, :], (bar_height, bar_thickness, 3))
    mode = image.mode
    bar_image = Image.fromarray(np.ascontiguousarray(bar), "RGB").convert(mode)
    image.paste(bar_image, (bar_x, bar_y))
    outline = (90, 94, 102) + ((255,) if mode == "RGBA" else ())
    draw.rectangle([bar_x - 1, bar_y - 1, bar_x + bar_thickness, bar_y + bar_height], outline=outline)
    # Overflow arrows: a triangle in the end colour where values beyond the range were clipped.
    alpha = (255,) if mode == "RGBA" else ()
    below, above = clipped
    if above:
        top = bar_y - 2
        draw.polygon([(bar_x - 1, top), (bar_x + bar_thickness, top),
                      ((2 * bar_x + bar_thickness - 1) / 2, top - layout.arrow)],
                     fill=tuple(int(c) for c in pixels[0]) + alpha, outline=outline)
    if below:
        bottom = bar_y + bar_height + 1
        draw.polygon([(bar_x - 1, bottom), (bar_x + bar_thickness, bottom),
                      ((2 * bar_x + bar_thickness - 1) / 2, bottom + layout.arrow)],
                     fill=tuple(int(c) for c in pixels[-1]) + alpha, outline=outline)
    values = [high, (low + high) / 2.0, low]
    positions = [bar_y, bar_y + bar_height // 2, bar_y + bar_height - 1]
    for text, y in zip(_format_ticks(values), positions):
        draw.line([bar_x + bar_thickness, y, bar_x + bar_thickness + 4, y], fill=outline)
        draw.text((bar_x + bar_thickness + 7, y), text, fill=text_fill, font=font, anchor="lm")
    if label:
        # Fit the label over the strip: a smaller font first, then one word per line.
        room = bar_width - 6
        size = font_size
        while size > 9 and draw.textlength(str(label), font=_font(size)) > room:
            size -= 1
        label_font = _font(size)
        lines = [str(label)]
        if draw.textlength(str(label), font=label_font) > room:
            lines = str(label).split()
        for k, line in enumerate(reversed(lines)):
            draw.text((strip_x + bar_width // 2, bar_y - layout.arrow - font_size // 2 - 6 - k * (size + 3)), line,
                      fill=text_fill, font=label_font, anchor="ms")


def save_png(canvas: np.ndarray, path: PathLike) -> None:
    """Write an (h, w, 3|4) uint8 canvas (as returned by `render`/`render_uv_layout` with no path) to a PNG.

    Raises InputError for a canvas that is not such an array, a file name that does not end in
    .png, or when the folder does not exist."""
    if not (isinstance(canvas, np.ndarray) and canvas.dtype == np.uint8 and canvas.ndim == 3
            and canvas.shape[2] in (3, 4) and canvas.size):
        shape = getattr(canvas, "shape", None)
        raise InputError(f"canvas must be a non-empty (height, width, 3 or 4) uint8 array (a picture from render), "
                         f"got {type(canvas).__name__}" + (f" {canvas.dtype} {shape}" if shape is not None else ""))
    Image, _, _ = _pillow()
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise InputError(f"cannot write {path}: pictures are written as PNG; name the file .png")
    if path.parent and not path.parent.exists():
        raise InputError(f"cannot write {path}: folder {path.parent} does not exist")
    Image.fromarray(canvas, "RGBA" if canvas.shape[2] == 4 else "RGB").save(path, optimize=False)
