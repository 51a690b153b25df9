"""Depth images (§2.3): back-projection of analytic depth images of a plane and a sphere, the mesh
cut at a depth discontinuity, the 2D scanline case on a circle, and bad input."""
import numpy as np
import pytest

from meshsmith import InputError, reconstruction, topology

H, W = 48, 64
FX, FY, CX, CY = 60.0, 55.0, 31.5, 23.5


def rays():
    """Per pixel, the ray direction (x/z, y/z, 1) of the pinhole camera."""
    v, u = np.mgrid[0:H, 0:W].astype(float)
    return np.stack([(u - CX) / FX, (v - CY) / FY, np.ones_like(u)], axis=-1)


def plane_depth(normal, offset):
    """z of the plane n·X = offset seen along each ray."""
    return offset / (rays() @ normal)


def sphere_depth(centre, radius):
    """z of the first intersection of each ray with the sphere (0 where the ray misses)."""
    r = rays()
    a = (r * r).sum(-1)
    b = -2 * r @ centre
    c = centre @ centre - radius ** 2
    disc = b * b - 4 * a * c
    t = (-b - np.sqrt(np.maximum(disc, 0))) / (2 * a)
    return np.where(disc > 0, t, 0.0)      # X = t r, and r's z is 1, so z = t


def test_plane_back_projects_onto_the_plane():
    normal, offset = np.array([0.2, -0.3, 1.0]), 4.0
    depth = 1000.0 * plane_depth(normal, offset)   # millimetres
    points, pixels = reconstruction.depth_to_points(depth, FX, FY, CX, CY, depth_scale=1000.0)
    assert points.shape == (H * W, 3) and pixels.shape == (H * W, 2)
    assert np.abs(points @ normal - offset).max() < 1e-12 * offset
    # Pixel (row, column) in row-major order, and the pinhole model itself.
    assert np.array_equal(pixels[W + 3], [1, 3])
    z = depth[1, 3] / 1000.0
    assert np.allclose(points[W + 3], [(3 - CX) * z / FX, (1 - CY) * z / FY, z], rtol=0, atol=1e-15)


def test_plane_mesh_is_a_full_grid_facing_the_camera():
    depth = plane_depth(np.array([0.0, 0.1, 1.0]), 3.0)
    V, F, pixels = reconstruction.depth_to_mesh(depth, FX, FY, CX, CY)
    assert len(F) == 2 * (H - 1) * (W - 1)
    assert topology.euler_characteristic(V, F) == 1      # a disk
    normals = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    centroids = V[F].mean(axis=1)
    assert ((normals * centroids).sum(axis=1) < 0).all()   # facing the camera at the origin


def test_sphere_points_lie_on_the_sphere_and_misses_are_dropped():
    centre, radius = np.array([0.1, -0.05, 3.0]), 0.6
    depth = sphere_depth(centre, radius)
    depth[depth == 0] = np.nan            # NaN is "no measurement", as 0 is
    depth[0, 0] = 0.0
    points, pixels = reconstruction.depth_to_points(depth, FX, FY, CX, CY)
    valid = np.isfinite(depth) & (depth > 0)
    assert len(points) == valid.sum() > 100
    assert np.abs(np.linalg.norm(points - centre, axis=1) - radius).max() < 1e-12
    assert valid[pixels[:, 0], pixels[:, 1]].all()


def test_a_sphere_in_front_of_a_wall_is_cut_at_its_silhouette():
    sphere = sphere_depth(np.array([0.0, 0.0, 2.0]), 0.5)
    wall = plane_depth(np.array([0.0, 0.0, 1.0]), 6.0)
    depth = np.where(sphere > 0, sphere, wall)
    V, F, _ = reconstruction.depth_to_mesh(depth, FX, FY, CX, CY, max_jump=0.1)
    components = topology.connected_components(F, len(V))
    assert components.count == 2
    # Each triangle lies on one surface: all on the sphere or all on the wall.
    on_sphere = np.abs(np.linalg.norm(V - [0, 0, 2.0], axis=1) - 0.5) < 1e-9
    assert (on_sphere[F].all(axis=1) | (~on_sphere[F]).all(axis=1)).all()
    # Without the cut the silhouette is bridged: one component.
    V2, F2, _ = reconstruction.depth_to_mesh(depth, FX, FY, CX, CY, max_jump=float("inf"))
    assert topology.connected_components(F2, len(V2)).count == 1 and len(F2) == 2 * (H - 1) * (W - 1)


def test_mask_and_invalid_pixels_leave_holes():
    depth = np.full((10, 12), 2.0)
    mask = np.ones_like(depth, bool)
    mask[4, 5] = False
    depth[7, 7] = np.inf
    depth[2, 2] = -1.0
    V, F, pixels = reconstruction.depth_to_mesh(depth, FX, FY, CX, CY, mask=mask)
    assert len(V) == 120 - 3
    used = {tuple(p) for p in pixels[np.unique(F)]}
    assert (4, 5) not in used and (7, 7) not in used and (2, 2) not in used
    # Each removed interior pixel leaves its 4 blocks of 2×2 pixels with 3 valid pixels: one
    # triangle each instead of two (of the 2 × 9 × 11 of the grid).
    assert len(F) == 2 * 9 * 11 - 3 * 4


def test_scanline_of_a_circle_lies_on_the_circle():
    n, centre, radius = 200, np.array([0.3, 5.0]), 1.5
    alpha = np.radians(40.0)
    h = 0.5 / np.tan(alpha / 2)
    x = (np.arange(n) + 0.5) / n
    v, v_perp = np.array([0.0, 1.0]), np.array([1.0, 0.0])   # (v_y, -v_x)
    ray = h * v + (x - 0.5)[:, None] * v_perp
    ray /= np.linalg.norm(ray, axis=1)[:, None]
    b = ray @ centre
    disc = b * b - (centre @ centre - radius ** 2)
    depths = np.where(disc > 0, b - np.sqrt(np.maximum(disc, 0)), 0.0)
    points, samples, segments = reconstruction.scanline_to_points(depths, direction=[0, 2.0], opening_angle=alpha)
    assert len(points) == (depths > 0).sum() > 50
    assert np.abs(np.linalg.norm(points - centre, axis=1) - radius).max() < 1e-12
    assert np.array_equal(samples, np.flatnonzero(depths > 0))
    # A jump (an occluder at half the distance) splits the polyline in two.
    depths_cut = depths.copy()
    middle = samples[len(samples) // 2]
    depths_cut[middle:] = np.where(depths_cut[middle:] > 0, 0.5 * depths_cut[middle:], 0)
    _, _, cut = reconstruction.scanline_to_points(depths_cut, direction=[0, 1.0], opening_angle=alpha)
    assert len(cut) == len(segments) - 1


@pytest.mark.parametrize("call, words", [
    (lambda: reconstruction.depth_to_points(np.zeros((0, 5)), 1, 1, 0, 0), "non-empty"),
    (lambda: reconstruction.depth_to_points(np.ones(5), 1, 1, 0, 0), "\\(h, w\\)"),
    (lambda: reconstruction.depth_to_points(np.ones((2, 3, 4)), 1, 1, 0, 0), "\\(h, w\\)"),
    (lambda: reconstruction.depth_to_points(np.ones((4, 4)), 0, 1, 0, 0), "fx"),
    (lambda: reconstruction.depth_to_points(np.ones((4, 4)), 1, np.nan, 0, 0), "fy"),
    (lambda: reconstruction.depth_to_points(np.ones((4, 4)), 1, 1, np.inf, 0), "cx"),
    (lambda: reconstruction.depth_to_points(np.ones((4, 4)), 1, 1, 0, 0, depth_scale=0), "depth_scale"),
    (lambda: reconstruction.depth_to_points(np.ones((4, 4)), 1, 1, 0, 0, mask=np.ones((4, 5), bool)), "mask"),
    (lambda: reconstruction.depth_to_points(np.ones((4, 4)), 1, 1, 0, 0, mask=np.ones((4, 4))), "mask"),
    (lambda: reconstruction.depth_to_points([["a"]], 1, 1, 0, 0), "depth"),
    (lambda: reconstruction.depth_to_mesh(np.ones((4, 4)), 1, 1, 0, 0, max_jump=-1), "max_jump"),
    (lambda: reconstruction.scanline_to_points(np.ones(0)), "empty"),
    (lambda: reconstruction.scanline_to_points(np.ones(4), direction=[0, 0]), "direction"),
    (lambda: reconstruction.scanline_to_points(np.ones(4), center=[0, 0, 0]), "center"),
    (lambda: reconstruction.scanline_to_points(np.ones(4), opening_angle=np.pi), "opening_angle"),
])
def test_bad_input_is_an_input_error(call, words):
    with pytest.raises(InputError, match=words):
        call()
