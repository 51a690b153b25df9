"""Tests of meshsmith.render: pictures checked for geometry (silhouettes against analytic
projections), colour (colormap order, checkerboard, back-face tint) and layout, plus bad input.

The test meshes are built here with numpy (an icosphere by subdividing an icosahedron, a grid);
they can switch to meshsmith.datasets once that module lands.
"""
import math
import sys

import numpy as np
import pytest

from meshsmith.datasets import icosphere
import meshsmith
from meshsmith import render as R

PIL = pytest.importorskip("PIL")


# ---- test meshes ------------------------------------------------------------------------------

def grid(n: int, width: float = 2.0, height: float = 2.0):
    """An n×n-square grid in the z = 0 plane centred at the origin, normals +z. (V, F)."""
    xs, ys = np.meshgrid(np.linspace(-width / 2, width / 2, n + 1),
                         np.linspace(-height / 2, height / 2, n + 1))
    V = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)])
    index = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b = index[:-1, :-1].ravel(), index[:-1, 1:].ravel()
    c, d = index[1:, 1:].ravel(), index[1:, :-1].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return V, F


@pytest.fixture(scope="module")
def sphere():
    return icosphere(4)


def luminance(image):
    rgb = image[..., :3].astype(float)
    return 0.299 * rgb[..., 0] + 0.587 * rgb[..., 1] + 0.114 * rgb[..., 2]


# ---- size, background, coverage -----------------------------------------------------------------

def test_image_has_the_requested_size_and_png_matches(sphere, tmp_path):
    from PIL import Image
    V, F = sphere
    path = tmp_path / "sphere.png"
    image = R.render(V, F, path, size=(320, 240))
    assert image.shape == (240, 320, 3) and image.dtype == np.uint8
    with Image.open(path) as png:
        assert png.size == (320, 240)
        assert np.array_equal(np.asarray(png.convert("RGB")), image)


def test_background_where_no_mesh_and_mesh_at_the_projected_centre(sphere):
    V, F = sphere
    image = R.render(V, F, size=(200, 160), background="white")
    white = np.all(image == 255, axis=2)
    for corner in [(0, 0), (0, -1), (-1, 0), (-1, -1)]:
        assert white[corner]
    # The camera targets the sphere's centre, which projects to the image centre.
    centre = image[80, 100]
    assert not np.all(centre == 255)
    assert centre[2] > centre[0]  # gray-blue material on front faces


def test_gradient_background_runs_from_light_top_to_darker_bottom(sphere):
    V, F = sphere
    image = R.render(V, F, size=(200, 160))
    assert np.all(image[0, 0] == 255)
    assert luminance(image)[-1, 0] < luminance(image)[0, 0] - 10


def test_transparent_background_gives_coverage_alpha(sphere):
    V, F = sphere
    image = R.render(V, F, size=(200, 160), background="transparent")
    assert image.shape == (160, 200, 4)
    assert image[0, 0, 3] == 0 and image[80, 100, 3] == 255
    alpha = image[..., 3]
    assert np.any((alpha > 0) & (alpha < 255))  # anti-aliased silhouette


def test_orthographic_sphere_silhouette_matches_the_analytic_disc(sphere):
    V, F = sphere
    width, height = 400, 300
    camera = R.frame_camera(V, view="front", size=(width, height), orthographic=True)
    image = R.render(V, F, size=(width, height), camera=camera, background="transparent")
    coverage = image[..., 3].astype(float).sum() / 255.0
    pixels_per_unit = height / camera.ortho_height
    expected = math.pi * pixels_per_unit ** 2  # unit sphere
    assert coverage == pytest.approx(expected, rel=0.02)


def test_perspective_sphere_silhouette_is_a_centred_disc_of_the_analytic_size(sphere):
    V, F = sphere
    width, height = 400, 300
    camera = R.frame_camera(V, view="front", size=(width, height))
    image = R.render(V, F, size=(width, height), camera=camera, background="transparent")
    alpha = image[..., 3].astype(float) / 255.0
    distance = np.linalg.norm(np.subtract(camera.eye, camera.target))
    focal = 0.5 * height / math.tan(math.radians(camera.fov_y_deg) / 2)
    radius_px = focal * math.tan(math.asin(1.0 / distance))  # cone tangent to the unit sphere
    assert alpha.sum() == pytest.approx(math.pi * radius_px ** 2, rel=0.03)
    # The fraction of the picture covered, and a round, centred shape.
    assert alpha.mean() == pytest.approx(math.pi * radius_px ** 2 / (width * height), rel=0.03)
    ys, xs = np.mgrid[0:height, 0:width] + 0.5
    cx, cy = (alpha * xs).sum() / alpha.sum(), (alpha * ys).sum() / alpha.sum()
    assert cx == pytest.approx(width / 2, abs=1.0) and cy == pytest.approx(height / 2, abs=1.0)
    var_x = (alpha * (xs - cx) ** 2).sum() / alpha.sum()
    var_y = (alpha * (ys - cy) ** 2).sum() / alpha.sum()
    assert var_x == pytest.approx(var_y, rel=0.02)


@pytest.mark.parametrize("view", ["three-quarter", "front", "back", "left", "right", "top",
                                  "bottom", (120.0, -40.0)])
def test_auto_framing_keeps_the_mesh_inside_with_the_margin(view):
    V, F = grid(4, width=3.0, height=1.0)
    V = V + np.array([5.0, -2.0, 1.0])
    V[:, 2] += 0.3 * V[:, 0] + 0.4 * V[:, 1]  # a tilted, off-centre plate
    width, height = 300, 200
    image = R.render(V, F, size=(width, height), view=view, background="transparent")
    rows, columns = np.nonzero(image[..., 3])
    # The framing is tight on one axis: the silhouette comes within ~margin of both sides.
    gaps = [columns.min(), width - 1 - columns.max(), rows.min(), height - 1 - rows.max()]
    assert min(gaps) >= 0
    tight_x = min(gaps[0], gaps[1]) <= 0.06 * width + 3 and abs(gaps[0] - gaps[1]) <= 3
    tight_y = min(gaps[2], gaps[3]) <= 0.06 * height + 3 and abs(gaps[2] - gaps[3]) <= 3
    assert tight_x or tight_y


def test_up_axis_z_stands_a_tall_object_upright():
    V, F = icosphere(2)
    tall_along_z = V * np.array([0.3, 0.3, 1.5])
    image = R.render(tall_along_z, F, size=(300, 300), view="front", up="z",
                     background="transparent")
    rows, columns = np.nonzero(image[..., 3] > 127)
    assert np.ptp(rows) > 3 * np.ptp(columns)


# ---- colour ---------------------------------------------------------------------------------------

def test_scalar_equal_to_x_runs_monotonically_along_the_colormap_left_to_right():
    V, F = grid(20)
    table = (R.colormap("viridis", 256) * 255.0)
    image = R.render(V, F, size=(300, 300), view="front", projection="orthographic",
                     scalar=V[:, 0], scalar_range=(-1.0, 1.0), cmap="viridis", lighting=False,
                     colorbar=False, background="white")
    row = image[150, :, :3].astype(float)
    inside = np.nonzero(np.any(image[150] != 255, axis=1))[0][3:-3]
    distances = ((row[inside, None, :] - table[None, :, :]) ** 2).sum(axis=2)
    index = distances.argmin(axis=1)
    assert distances.min(axis=1).max() < 30.0  # every pixel is a colormap colour
    assert np.all(np.diff(index) >= -1)          # monotone up to rounding
    assert index[0] < 12 and index[-1] > 243     # spans the whole colormap


def test_scalar_colours_shade_with_lighting_but_keep_the_order():
    V, F = grid(20)
    lit = R.render(V, F, size=(200, 200), view="front", scalar=V[:, 0], colorbar=False,
                   scalar_range=(-1, 1), cmap="coolwarm")
    left, right = lit[100, 40].astype(int), lit[100, 160].astype(int)
    assert left[2] > left[0] and right[0] > right[2]  # blue on the left, red on the right


def test_default_scalar_range_is_robust_and_symmetric_for_diverging_maps():
    values = np.linspace(-1.0, 3.0, 101)
    values[7] = 1e6  # an outlier the percentiles ignore
    low, high = R.scalar_range(values, len(values), "viridis")
    assert low == pytest.approx(np.percentile(values, 2))
    assert high == pytest.approx(np.percentile(values, 98))
    low, high = R.scalar_range(values, len(values), "coolwarm")
    assert low == pytest.approx(-high) and high == pytest.approx(np.percentile(values, 98))
    valence = np.full(1000, 6.0)
    valence[:12] = 5.0  # percentiles coincide: the extremes are used
    assert R.scalar_range(valence, 1000, "coolwarm") == (5.0, 6.0)
    assert R.scalar_range(np.full(10, 4.0), 10, "viridis") == pytest.approx((3.6, 4.4))
    assert R.scalar_range(np.zeros(10), 10, "coolwarm") == (-1.0, 1.0)
    positive = np.linspace(3.0, 9.0, 50)  # no sign change: no symmetrisation
    assert R.scalar_range(positive, 50, "coolwarm") == pytest.approx(
        (np.percentile(positive, 2), np.percentile(positive, 98)))


def test_colormap_tables_have_the_published_end_colours():
    viridis = R.colormap("viridis", 5)
    assert viridis[0] == pytest.approx([0.267, 0.005, 0.329], abs=2e-3)
    assert viridis[-1] == pytest.approx([0.993, 0.906, 0.144], abs=2e-3)
    coolwarm = R.colormap("coolwarm", 3)
    assert coolwarm[1] == pytest.approx([0.865, 0.865, 0.865], abs=3e-3)  # neutral centre


def test_colorbar_is_drawn_inside_the_requested_size(sphere):
    V, F = sphere
    with_bar = R.render(V, F, size=(400, 300), scalar=V[:, 1], scalar_label="height", cmap="viridis",
                        background="white")
    without = R.render(V, F, size=(400, 300), scalar=V[:, 1], colorbar=False, background="white")
    assert with_bar.shape == without.shape == (300, 400, 3)
    strip = with_bar[:, 340:]
    # The bar holds the colormap's colours: both ends of viridis appear in the strip.
    table = R.colormap("viridis", 256) * 255
    colours = strip.reshape(-1, 3).astype(float)
    for end in (table[0], table[-1]):
        assert ((colours - end) ** 2).sum(axis=1).min() < 50
    assert np.all(without[:, 390:] == 255)  # no bar: only background at the right edge


def test_wireframe_increases_dark_pixels(sphere):
    V, F = icosphere(3)
    plain = R.render(V, F, size=(300, 300))
    wired = R.render(V, F, size=(300, 300), wireframe=True)
    darker = luminance(plain) - luminance(wired)
    assert (darker > 40).sum() > 3000  # lines over the whole visible half of the sphere
    assert (luminance(wired) < 90).sum() > (luminance(plain) < 90).sum() + 3000
    assert darker.min() > -1  # lines only darken


def test_wireframe_auto_depends_on_the_face_count():
    V, F = icosphere(2)  # 320 faces: readable
    assert np.array_equal(R.render(V, F, size=(300, 300), wireframe="auto"),
                          R.render(V, F, size=(300, 300), wireframe=True))
    V, F = icosphere(5)  # 20480 faces: too dense at this size
    assert np.array_equal(R.render(V, F, size=(200, 200), wireframe="auto"),
                          R.render(V, F, size=(200, 200), wireframe=False))


def test_flat_shading_is_constant_per_face():
    V, F = icosphere(1)
    flat = R.render(V, F, size=(240, 240), flat=True, background="white", supersample=1)
    smooth = R.render(V, F, size=(240, 240), background="white", supersample=1)
    distinct = lambda image: len(np.unique(image.reshape(-1, 3), axis=0))
    assert distinct(flat) <= 2 * len(F)  # one colour per visible face plus edge pixels
    assert distinct(smooth) > 5 * distinct(flat)


def test_uv_checkerboard_gives_two_alternating_colours():
    V, F = grid(8)
    uv = V[:, :2] + 1.0  # [0, 2]^2
    image = R.render(V, F, size=(400, 400), view="front", projection="orthographic", uv=uv,
                     checker_size=0.5, background="white")  # 4 x 4 squares
    rows, columns = np.nonzero(np.any(image != 255, axis=2))
    top, left = rows.min(), columns.min()
    side = (rows.max() - top + 1) / 4.0
    centres = [(int(top + (i + 0.5) * side), int(left + (j + 0.5) * side))
               for i in range(4) for j in range(4)]
    colour = {(i, j): image[centres[4 * i + j]].astype(int) for i in range(4) for j in range(4)}
    a, b = colour[0, 0], colour[0, 1]
    assert np.abs(a - b).sum() > 150  # two clearly different colours
    for (i, j), c in colour.items():
        expected = a if (i + j) % 2 == 0 else b
        assert np.abs(c - expected).max() <= 2
    # Away from the checker borders only those two colours appear.
    interior = image[top + 5:rows.max() - 5, left + 5:columns.max() - 5].reshape(-1, 3).astype(int)
    near = np.minimum(np.abs(interior - a).max(axis=1), np.abs(interior - b).max(axis=1))
    assert (near <= 2).mean() > 0.9


def test_per_corner_uv_equals_per_vertex_uv():
    V, F = grid(6)
    uv = V[:, :2] * 1.7
    per_vertex = R.render(V, F, size=(160, 160), uv=uv, checker_size=0.4)
    per_corner = R.render(V, F, size=(160, 160), uv=uv[F], checker_size=0.4)
    assert np.array_equal(per_vertex, per_corner)


def test_back_faces_are_tinted_so_holes_show():
    V, F = icosphere(3)
    closed = R.render(V, F, size=(200, 200), view="front", background="white")
    keep = ~np.all(V[F][:, :, 2] > 0.5, axis=1)  # cut a hole facing the camera
    open_cup = R.render(V, F[keep], size=(200, 200), view="front", background="white")
    r, g, b = closed[100, 100].astype(int)
    assert b > r + 20  # front: gray-blue
    r, g, b = open_cup[100, 100].astype(int)
    assert r > b + 30  # seen through the hole: the inside, back faces in the warm tint


def test_grid_of_views_has_the_expected_total_size(sphere):
    V, F = sphere
    assert R.render(V, F, size=(200, 150), views=["front", "left", "top", "three-quarter"]
                    ).shape == (300, 400, 3)
    assert R.render(V, F, size=(200, 150), views=["front", "left", "top"]).shape == (150, 600, 3)
    image = R.render(V, F, size=(200, 150), views=["front", (30, 10), "top"], columns=1,
                     title="three views", scalar=V[:, 0])
    assert image.shape == (450, 200, 3)


def test_grid_panels_show_the_views():
    # A tall box along y: narrow from the front, but the top view sees its square section.
    V, F = icosphere(2)
    V = V * np.array([0.3, 2.0, 0.3])
    image = R.render(V, F, size=(200, 200), views=["front", "top"], background="transparent")
    front, top = image[:, :200, 3] > 127, image[:, 200:, 3] > 127
    front[:24, :70] = top[:24, :70] = False  # the view labels
    rows, columns = np.nonzero(front)
    assert np.ptp(rows) > 3 * np.ptp(columns)
    rows, columns = np.nonzero(top)
    assert np.ptp(rows) == pytest.approx(np.ptp(columns), rel=0.1)


def test_rendering_is_deterministic(sphere):
    V, F = sphere
    kwargs = dict(size=(320, 240), scalar=V[:, 2], wireframe=True, title="same")
    assert np.array_equal(R.render(V, F, **kwargs), R.render(V, F, **kwargs))


def test_inputs_are_not_modified(sphere):
    V, F = sphere
    V0, F0 = V.copy(), F.copy()
    scalar = V[:, 0].copy()
    R.render(V, F, size=(100, 80), scalar=scalar, uv=V[:, :2])
    assert np.array_equal(V, V0) and np.array_equal(F, F0) and np.array_equal(scalar, V[:, 0])


def test_uv_layout_shows_flipped_triangles_in_the_warm_tint(tmp_path):
    V, F = grid(4)
    uv = V[:, :2].copy()
    good = R.render_uv_layout(uv, F, tmp_path / "layout.png", size=(300, 300))
    assert good.shape == (300, 300, 3) and (tmp_path / "layout.png").stat().st_size > 1000
    warm = lambda image: ((image[..., 0].astype(int) - image[..., 2]) > 60).sum()
    assert warm(good) == 0
    folded = F.copy()
    folded[0] = folded[0, ::-1]  # one clockwise triangle: a fold-over
    assert warm(R.render_uv_layout(uv, folded, size=(300, 300))) > 100


# ---- bad input ----------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, message", [
    (dict(scalar="nan"), "NaN"),
    (dict(scalar="short"), "values but the mesh has"),
    (dict(scalar="2d"), "expected (n,)"),
    (dict(uv="3cols"), "uv has shape"),
    (dict(uv="rows"), "uv has"),
    (dict(uv="nan"), "uv row"),
    (dict(size=(0, 100)), "size"),
    (dict(size=(100, -5)), "size"),
    (dict(size=(100.5, 80)), "size"),
    (dict(view="side"), "unknown view 'side'"),
    (dict(view=(1.0, float("nan"))), "finite"),
    (dict(views=[]), "views is empty"),
    (dict(cmap="jet"), "unknown colormap 'jet'"),
    (dict(projection="fisheye"), "unknown projection"),
    (dict(background="not-a-colour"), "unknown background colour"),
    (dict(scalar_range=(2.0, 1.0), scalar="ok"), "low <= high"),
    (dict(supersample=9), "supersample"),
    (dict(up="w"), "up axis"),
    (dict(wireframe="yes"), "wireframe"),
    (dict(checker_size=-1.0, uv="ok"), "checker_size"),
])
def test_bad_arguments_raise_input_error(sphere, kwargs, message):
    V, F = icosphere(1)
    n = len(V)
    replacements = {
        ("scalar", "nan"): np.where(np.arange(n) == 5, np.nan, 1.0),
        ("scalar", "short"): np.ones(n - 1),
        ("scalar", "2d"): np.ones((n, 2)),
        ("scalar", "ok"): np.ones(n),
        ("uv", "3cols"): np.ones((n, 3)),
        ("uv", "rows"): np.ones((n + 2, 2)),
        ("uv", "nan"): np.where(np.arange(2 * n).reshape(n, 2) == 9, np.inf, 0.5),
        ("uv", "ok"): V[:, :2],
    }
    kwargs = {k: replacements.get((k, v), v) if isinstance(v, str) else v for k, v in kwargs.items()}
    with pytest.raises(meshsmith.InputError, match=None) as error:
        R.render(V, F, size=kwargs.pop("size", (64, 48)), **kwargs)
    assert isinstance(error.value, ValueError)
    assert message in str(error.value)


def test_nan_scalar_message_names_the_vertex():
    V, F = icosphere(1)
    scalar = np.ones(len(V))
    scalar[17] = np.nan
    with pytest.raises(meshsmith.InputError, match=r"scalar\[17\] is NaN"):
        R.render(V, F, scalar=scalar, size=(64, 48))


@pytest.mark.parametrize("mesh, message", [
    ("nan_vertex", "NaN"),
    ("bad_index", "index"),
    ("no_faces", "empty"),
    ("float_faces", "integer"),
])
def test_bad_meshes_raise_input_error(mesh, message):
    V, F = icosphere(1)
    if mesh == "nan_vertex":
        V = V.copy()
        V[3, 1] = np.nan
    elif mesh == "bad_index":
        F = F.copy()
        F[4, 2] = len(V) + 3
    elif mesh == "no_faces":
        F = np.zeros((0, 3), dtype=np.int64)
    else:
        F = F.astype(float)
    with pytest.raises(meshsmith.InputError) as error:
        R.render(V, F, size=(64, 48))
    assert message.lower() in str(error.value).lower()


def test_too_many_samples_is_refused_before_allocating(sphere):
    V, F = sphere
    with pytest.raises(meshsmith.InputError, match="samples"):
        R.render(V, F, size=(8000, 8000), supersample=4)


def test_camera_and_several_views_are_exclusive(sphere):
    V, F = sphere
    camera = R.frame_camera(V)
    with pytest.raises(meshsmith.InputError, match="exclusive"):
        R.render(V, F, camera=camera, views=["front", "top"])


def test_missing_pillow_gives_a_clear_import_error(sphere, tmp_path, monkeypatch):
    V, F = sphere
    for name in [m for m in sys.modules if m == "PIL" or m.startswith("PIL.")]:
        monkeypatch.setitem(sys.modules, name, None)
    monkeypatch.setitem(sys.modules, "PIL", None)
    image = R.render(V, F, size=(80, 60))  # no text and no file: numpy only
    assert image.shape == (60, 80, 3)
    with pytest.raises(ImportError, match=r"meshsmith\[viz\]"):
        R.render(V, F, tmp_path / "x.png", size=(80, 60))


# ---- real meshes (../shared/data) ---------------------------------------------------------------

@pytest.mark.parametrize("name", ["nefertiti-lowres.obj", "bunny.off", "plane_holes.obj"])
def test_real_meshes_render_framed_and_shaded(data_dir, name, tmp_path):
    trimesh = pytest.importorskip("trimesh")
    path = data_dir / name
    if not path.exists():
        pytest.skip(f"{name} not in the shared data")
    mesh = trimesh.load(path, process=False, force="mesh")
    V, F = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
    image = R.render(V, F, tmp_path / "out.png", size=(400, 300), background="transparent")
    alpha = image[..., 3]
    assert image.shape == (300, 400, 4)
    covered = alpha > 127
    assert 0.05 < covered.mean() < 0.9
    rows, columns = np.nonzero(alpha)
    assert rows.min() > 0 and columns.min() > 0 and rows.max() < 299 and columns.max() < 399
    shade = luminance(image)[covered]
    assert shade.std() > 8  # shaded, not a flat silhouette


def test_colour_bar_tick_labels_use_the_precision_of_the_range():
    assert R._format_ticks([9.0, 6.0, 3.0]) == ["9", "6", "3"]
    assert R._format_ticks([0.0123, 0.0, -0.0123]) == ["0.0123", "0", "-0.0123"]
    assert R._format_ticks([2.5e6, 1.25e6, 0.0]) == ["2.5e+06", "1.25e+06", "0"]


def test_default_colour_bar_is_left_out_of_tiny_pictures_but_not_when_asked(sphere):
    V, F = sphere
    tiny = R.render(V, F, size=(120, 90), scalar=V[:, 0], background="white")
    assert tiny.shape == (90, 120, 3)
    with pytest.raises(meshsmith.InputError, match="too small"):
        R.render(V, F, size=(60, 90), scalar=V[:, 0], colorbar=True)


def test_uv_layout_rejects_uvs_that_are_not_two_columns():
    V, F = grid(2)
    with pytest.raises(meshsmith.InputError, match=r"UV has shape \(9, 3\): expected \(n, 2\)"):
        R.render_uv_layout(V, F)


def test_camera_inside_a_closed_sphere_sees_its_inside_in_the_back_tint(sphere):
    V, F = sphere
    camera = R.Camera(eye=(0.0, 0.0, 0.0), target=(0.0, 0.0, -1.0), up=(0.0, 1.0, 0.0), fov_y_deg=60)
    image = R.render(V, F, size=(160, 120), camera=camera, background="white")
    r, g, b = image[60, 80].astype(int)
    assert r > b + 30
    # Triangles crossing the plane of the eye are left out, never drawn wrapped around.
    behind = R.Camera(eye=(0.0, 0.0, 0.999), target=(0.0, 0.0, 2.0), up=(0.0, 1.0, 0.0))
    outside = R.render(V, F, size=(160, 120), camera=behind, background="white")
    assert np.all(outside == 255)


def test_degenerate_cameras_are_rejected(sphere):
    V, F = sphere
    bad = [R.Camera(eye=(0, 0, 3), target=(0, 0, 3), up=(0, 1, 0)),
           R.Camera(eye=(0, 0, 3), target=(0, 0, 0), up=(0, 0, 1)),
           R.Camera(eye=(0, 0, 3), target=(0, 0, 0), up=(0, 1, 0), fov_y_deg=180),
           R.Camera(eye=(0, 0, 3), target=(0, 0, 0), up=(0, 1, 0), orthographic=True, ortho_height=0)]
    for camera in bad:
        with pytest.raises(meshsmith.InputError, match="camera"):
            R.render(V, F, size=(40, 30), camera=camera)


@pytest.mark.parametrize("view, axis, sign, up", [
    ("front", 2, +1, "y"), ("back", 2, -1, "y"), ("right", 0, +1, "y"), ("left", 0, -1, "y"),
    ("top", 1, +1, "y"), ("bottom", 1, -1, "y"),
    ("front", 1, -1, "z"), ("right", 0, +1, "z"), ("top", 2, +1, "z"),
    ("front", 2, +1, "x"), ("right", 1, -1, "x"), ("top", 0, +1, "x"),
    ("front", 2, +1, "-x"), ("top", 0, -1, "-x"), ("front", 2, +1, "-y"), ("top", 1, -1, "-y"),
    ("right", 0, -1, "-y"), ("front", 1, -1, "-z"), ("top", 2, -1, "-z"), ("right", 0, -1, "-z"),
])
def test_named_views_look_from_the_documented_side(sphere, view, axis, sign, up):
    V, F = sphere
    # Colour by the coordinate along the axis the view should look from: the nearest point of
    # the sphere (the image centre) must take the colormap's top colour.
    image = R.render(V, F, size=(120, 90), view=view, up=up, scalar=sign * V[:, axis],
                     scalar_range=(-1, 1), cmap="viridis", lighting=False, colorbar=False)
    top_colour = R.colormap("viridis", 2)[-1] * 255
    assert np.abs(image[45, 60].astype(float) - top_colour).max() < 12


def test_silhouette_bounding_box_matches_an_independent_projection():
    V, F = icosphere(3)
    V = V * np.array([1.5, 0.7, 1.0]) + 0.2 * np.sin(3 * V[:, [1, 2, 0]])  # a lumpy blob
    width, height = 320, 240
    camera = R.frame_camera(V, view=(30, 20), size=(width, height))
    image = R.render(V, F, size=(width, height), camera=camera, background="transparent",
                     supersample=4)
    forward = np.subtract(camera.target, camera.eye)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, camera.up)
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    relative = V - np.asarray(camera.eye)
    depth = relative @ forward
    focal = 0.5 * height / math.tan(math.radians(camera.fov_y_deg) / 2)
    x = width / 2 + focal * (relative @ right) / depth
    y = height / 2 - focal * (relative @ up) / depth
    rows, columns = np.nonzero(image[..., 3] >= 128)  # pixels at least half covered
    assert columns.min() == pytest.approx(x.min(), abs=1.5)
    assert columns.max() + 1 == pytest.approx(x.max(), abs=1.5)
    assert rows.min() == pytest.approx(y.min(), abs=1.5)
    assert rows.max() + 1 == pytest.approx(y.max(), abs=1.5)


def test_thicker_wireframe_lines_cover_more_pixels():
    V, F = icosphere(2)
    thin = R.render(V, F, size=(300, 300), wireframe=True, wireframe_width=1.0)
    thick = R.render(V, F, size=(300, 300), wireframe=True, wireframe_width=3.0)
    dark = lambda image: (luminance(image) < 80).sum()
    assert dark(thick) > 2 * dark(thin)
    with pytest.raises(meshsmith.InputError, match="wireframe_width"):
        R.render(V, F, size=(60, 60), wireframe=True, wireframe_width=0.0)
    with pytest.raises(meshsmith.InputError, match="supersample"):
        R.render(V, F, size=(60, 60), supersample=2.5)


def test_no_cracks_between_adjacent_triangles():
    V, F = icosphere(5)  # 20480 small triangles sharing edges
    width, height = 300, 300
    camera = R.frame_camera(V, view=(17.0, 11.0), size=(width, height), orthographic=True)
    for supersample in (1, 2):
        image = R.render(V, F, size=(width, height), camera=camera, background="transparent",
                         supersample=supersample)
        ys, xs = np.mgrid[0:height, 0:width] + 0.5
        radius_px = height / camera.ortho_height
        inside = (xs - width / 2) ** 2 + (ys - height / 2) ** 2 < (radius_px - 2) ** 2
        assert np.all(image[..., 3][inside] == 255)


def cube():
    V = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])
    F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return V, F


def test_smooth_shading_keeps_sharp_edges_crisp_below_the_crease_angle():
    V, F = cube()
    assert np.all(np.einsum("ij,ij->i", np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]),
                            V[F].mean(axis=1)) > 0)  # outward, counter-clockwise faces
    kwargs = dict(size=(200, 200), background="white", supersample=1)
    crisp = R.render(V, F, **kwargs)                      # 90-degree edges > 60: split
    rounded = R.render(V, F, crease_angle=180, **kwargs)  # one normal per vertex
    flat = R.render(V, F, flat=True, **kwargs)
    distinct = lambda image: len(np.unique(image.reshape(-1, 3), axis=0))
    assert np.abs(crisp.astype(int) - flat).max() <= 1  # planar cube faces: crisp equals flat
    assert distinct(rounded) > 20 * distinct(crisp)
    with pytest.raises(meshsmith.InputError, match="crease_angle"):
        R.render(V, F, crease_angle=-5, size=(40, 40))


def test_crease_angle_leaves_smooth_surfaces_smooth():
    V, F = icosphere(3)  # neighbouring faces differ by ~ 7 degrees
    assert np.array_equal(R.render(V, F, size=(160, 120)),
                          R.render(V, F, size=(160, 120), crease_angle=180))


# ---- colour maps and overflow arrows (issue 14: pictures mislead) ----------------------------------

def _bar_strip(image, layout):
    """The columns of the colour bar, above the bar (top arrow) and below it (bottom arrow)."""
    columns = slice(layout.x, layout.x + layout.thickness)
    above = image[layout.y - 2 - layout.arrow:layout.y - 2, columns, :3].astype(float)
    below = image[layout.y + layout.height + 2:layout.y + layout.height + 2 + layout.arrow, columns, :3].astype(float)
    return above, below


def _holds(region, colour, tolerance=20.0):
    return int((np.abs(region - np.asarray(colour, dtype=float)).max(axis=-1) < tolerance).sum())


@pytest.mark.parametrize("scalar_range, top, bottom", [
    ((-1.0, 1.0), False, False), ((-0.5, 1.0), False, True), ((-1.0, 0.5), True, False), ((-0.5, 0.5), True, True),
])
def test_overflow_arrows_show_exactly_the_clipped_ends(sphere, scalar_range, top, bottom):
    V, F = sphere
    size = (400, 300)
    image = R.render(V, F, size=size, scalar=V[:, 1], scalar_range=scalar_range, cmap="viridis",
                     background="white")
    layout = R._colorbar_layout(size[0], size[1], max(64, round(0.14 * size[0])), 0)
    above, below = _bar_strip(image, layout)
    table = R.colormap("viridis", 256) * 255
    # An arrow is a triangle in the end colour: many pixels of that colour; no arrow, none at all.
    assert (_holds(above, table[-1]) > layout.thickness) == top
    assert (_holds(below, table[0]) > layout.thickness) == bottom
    assert np.all(above == 255) != top and np.all(below == 255) != bottom
    assert R.clipped_ends(V[:, 1], *scalar_range) == (bottom, top)


def test_default_colormap_is_sequential_for_one_sign_and_diverging_about_zero_otherwise(sphere):
    V, F = sphere
    assert R.default_colormap(V[:, 1] + 2.0) == "viridis" and R.default_colormap(V[:, 1]) == "coolwarm"
    assert R.default_colormap(-V[:, 1] - 2.0) == "viridis" and R.default_colormap(np.zeros(5)) == "viridis"
    size = (400, 300)
    layout = R._colorbar_layout(size[0], size[1], max(64, round(0.14 * size[0])), 0)
    columns = slice(layout.x + 2, layout.x + layout.thickness - 2)
    for values, name in ((V[:, 1] + 2.0, "viridis"), (V[:, 1], "coolwarm")):
        image = R.render(V, F, size=size, scalar=values, background="white")
        bar = image[layout.y + 1:layout.y + layout.height - 1, columns, :3].astype(float).mean(axis=1)
        table = R.colormap(name, len(bar))[::-1] * 255
        assert np.abs(bar - table).max() < 6, name                # the bar is drawn in that map
        on_mesh = image[100:200, 100:250, :3].reshape(-1, 3).astype(float)
        nearest = ((on_mesh[:, None, :] - R.colormap(name, 64)[None] * 255) ** 2).sum(axis=2).min(axis=1)
        assert np.median(nearest) < 2000, name                   # and so is the surface (lit)
    # Two-signed data: the range is symmetric, so 0 is the neutral middle colour.
    low, high = R.scalar_range(V[:, 1] + 0.3, len(V))
    assert low == -high


def test_save_png_refuses_other_extensions(tmp_path):
    with pytest.raises(meshsmith.InputError, match=r"\.png"):
        R.save_png(np.zeros((4, 4, 3), dtype=np.uint8), tmp_path / "x.jpg")
