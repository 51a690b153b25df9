"""One set of conventions (issue 14 part 4): every multi-output result is named, unpacks in the
documented order and pickles to plain arrays; options are keyword-only (the 0.1 positional forms
warn); the argument-order rule of README's Conventions holds for every public function."""
import dataclasses
import importlib
import inspect
import numbers
import pickle
import pkgutil
import warnings

import numpy as np
import pytest

import meshsmith
from meshsmith import (
    core,
    datasets,
    decimation,
    geometry,
    io,
    parametrization,
    points,
    quadrangulation,
    reconstruction,
    registration,
    render,
    repair,
    tessellation,
    topology,
)
from meshsmith._results import Unpackable

#: Every chapter module (a new chapter is picked up by itself); cli and demo are front ends.
CHAPTERS = sorted(info.name for info in pkgutil.iter_modules(meshsmith.__path__)
                  if not info.name.startswith("_") and info.name not in ("cli", "demo"))


def disk():
    return datasets.disk(4, 16)


def sphere_with_hole():
    V, F = datasets.icosphere(1)
    return V, F[1:]


def sphere_halves():
    """(VA, FA, VB, FB): two overlapping halves of an icosphere (for zipper)."""
    V, F = datasets.icosphere(2)
    height = V[F].mean(axis=1)[:, 2]
    return V, F[height > -0.3], V, F[height < 0.3]


def square_grid_map():
    """The unit square with UV = 3·(x, y) per corner: a seamless map whose grid is 3×3 quads."""
    V, F = datasets.grid(4, 4)
    return V, F, 3 * V[F][:, :, :2]


def poked_sphere():
    V, F = datasets.icosphere(2)
    V = V.copy()
    V[0] *= -1.3      # through the centre and out of the far side: self-intersections
    return V, F


def sphere_with_unused_vertex():
    V, F = datasets.icosphere(1)
    return np.vstack([V, [[5.0, 5.0, 5.0]]]), F[:, ::-1]   # inward faces, one vertex no face uses


def circle_samples(n=40):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([2 * np.cos(t), np.sin(t)])


def square_domain():
    P = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    return P, np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def planar_grid():
    V, F = datasets.grid(4, 4)
    return V[:, :2], F


def mesh_file(tmp_path):
    V, F = datasets.icosphere(1)
    path = tmp_path / "mesh.obj"
    io.write_mesh(path, V, F)
    return path


def points_file(tmp_path):
    P, N = datasets.sphere_points(30)
    path = tmp_path / "points.xyz"
    io.write_points(path, P, N)
    return path


def range_scan_file(tmp_path):
    path = tmp_path / "scan.ply"
    path.write_text("ply\nformat ascii 1.0\nobj_info num_cols 2\nobj_info num_rows 2\nelement vertex 4\n"
                    "property float x\nproperty float y\nproperty float z\nelement range_grid 4\n"
                    "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
                    "1 0\n1 1\n1 2\n1 3\n")
    return path


def poly_file(tmp_path):
    path = tmp_path / "square.poly"
    path.write_text("4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n")
    return path


def ball_grid() -> np.ndarray:
    x = np.linspace(-1, 1, 9)
    return np.sqrt(sum(c ** 2 for c in np.meshgrid(x, x, x, indexing="ij"))) - 0.7


# name -> (function of tmp_path giving the result, the field names it unpacks as, in order)
RESULTS = {
    "datasets.icosphere": (lambda tmp: datasets.icosphere(1), ["V", "F"]),
    "datasets.sample_points": (lambda tmp: datasets.sample_points(*datasets.icosphere(1), 20), ["P", "N"]),
    "core.mesh_defects": (lambda tmp: core.mesh_defects(*datasets.icosphere(1)),
                          ["degenerate_faces", "zero_area_faces", "duplicate_faces", "unreferenced_vertices",
                           "summary"]),
    "io.read_mesh": (lambda tmp: io.read_mesh(mesh_file(tmp)), ["V", "F"]),
    "io.read_mesh polygons": (lambda tmp: io.read_mesh(mesh_file(tmp), triangulate=False), ["V", "F"]),
    "io.read_mesh attributes": (lambda tmp: io.read_mesh(mesh_file(tmp), return_attributes=True), ["V", "F"]),
    "io.read_points": (lambda tmp: io.read_points(points_file(tmp)), ["P", "N"]),
    "io.read_poly": (lambda tmp: io.read_poly(poly_file(tmp)), ["P", "segments", "holes"]),
    "io.read_range_scan": (lambda tmp: io.read_range_scan(range_scan_file(tmp)), ["V", "F", "grid", "spacing"]),
    "topology.connected_components": (lambda tmp: topology.connected_components(disk()[1]),
                                      ["count", "face_labels", "vertex_labels"]),
    "topology.split_non_manifold_vertices": (lambda tmp: topology.split_non_manifold_vertices(*disk()),
                                             ["V", "F", "vertex_origin"]),
    "topology.info": (lambda tmp: topology.info(*disk()),
                      [f.name for f in dataclasses.fields(topology.MeshInfo)]),
    "geometry.mean_curvature": (lambda tmp: geometry.mean_curvature(*datasets.icosphere(1)), ["H", "Hn"]),
    "geometry.principal_curvatures": (lambda tmp: geometry.principal_curvatures(*datasets.icosphere(1)),
                                      ["k1", "k2", "d1", "d2"]),
    "geometry.laplacian_eigenpairs": (lambda tmp: geometry.laplacian_eigenpairs(*datasets.icosphere(1), 3),
                                      ["values", "vectors"]),
    "geometry.triangle_distortion": (lambda tmp: geometry.triangle_distortion(*disk(), parametrization.lscm(*disk())),
                                     [f.name for f in dataclasses.fields(geometry.TriangleDistortion)]),
    "geometry.SurfaceDistance.closest_points": (
        lambda tmp: geometry.SurfaceDistance(*datasets.icosphere(1)).closest_points(np.eye(3) * 2),
        ["distance", "face", "point"]),
    "geometry.hausdorff_distance one_sided": (
        lambda tmp: geometry.hausdorff_distance(*datasets.icosphere(1), *datasets.icosphere(2), one_sided=True),
        ["symmetric", "a_to_b", "b_to_a"]),
    "geometry.mean_surface_distance one_sided": (
        lambda tmp: geometry.mean_surface_distance(*datasets.icosphere(1), *datasets.icosphere(2), one_sided=True),
        ["symmetric", "a_to_b", "b_to_a"]),
    "points.knn": (lambda tmp: points.knn(datasets.sphere_points(30).P, 4), ["indices", "distances"]),
    "points.KdTree.query_radius": (
        lambda tmp: points.KdTree(datasets.sphere_points(30).P).query_radius(np.zeros((2, 3)), 1.5),
        ["offsets", "indices", "distances"]),
    "points.estimate_normals return_variation": (
        lambda tmp: points.estimate_normals(datasets.sphere_points(30).P, k=8, return_variation=True),
        ["normals", "variation"]),
    "tessellation.delaunay": (lambda tmp: tessellation.delaunay(circle_samples()), ["F", "merged"]),
    "tessellation.constrained_delaunay": (lambda tmp: tessellation.constrained_delaunay(*square_domain()),
                                          ["V", "F"]),
    "tessellation.voronoi": (lambda tmp: tessellation.voronoi(circle_samples()),
                             ["vertices", "edges", "directions", "edge_sites", "cells", "triangles"]),
    "tessellation.flip_to_delaunay": (lambda tmp: tessellation.flip_to_delaunay(*planar_grid()), ["F", "flip_count"]),
    "tessellation.refine": (lambda tmp: tessellation.refine(*square_domain(), max_area=0.05),
                            ["V", "F", "steiner_count"]),
    "tessellation.power_diagram": (
        lambda tmp: tessellation.power_diagram(circle_samples(12), np.linspace(0, 0.1, 12)),
        ["triangulation", "cells", "hidden", "bounds"]),
    "tessellation.medial_axis": (lambda tmp: tessellation.medial_axis(circle_samples()), ["vertices", "edges"]),
    "tessellation.crust_3d": (lambda tmp: tessellation.crust_3d(datasets.sphere_points(60).P), ["V", "F"]),
    "registration.icp": (lambda tmp: registration.icp(datasets.sphere_points(40).P, datasets.sphere_points(40).P),
                         ["transform", "rms", "iterations", "converged", "inlier_fraction", "rms_history", "inliers",
                          "stop"]),
    "registration.icp_multi": (lambda tmp: registration.icp_multi([datasets.sphere_points(40).P] * 2, rounds=1),
                               ["transforms", "rms", "inlier_fraction", "scan_converged", "rounds", "converged",
                                "edges"]),
    "datasets.scan_pair": (lambda tmp: datasets.scan_pair(*datasets.icosphere(1), n_source=20, n_target=30),
                           ["source", "target", "target_normals", "motion", "n_outliers", "diagonal"]),
    "datasets.partial_views": (lambda tmp: datasets.partial_views(*datasets.icosphere(2), n_views=2, n_points=20,
                                                                  n_samples=200),
                               ["scans", "poses", "starts", "diagonal"]),
    "reconstruction.depth_to_points": (lambda tmp: reconstruction.depth_to_points(np.ones((3, 4)), 2, 2, 1, 1),
                                       ["points", "pixels"]),
    "reconstruction.depth_to_mesh": (lambda tmp: reconstruction.depth_to_mesh(np.ones((3, 4)), 2, 2, 1, 1),
                                     ["V", "F", "pixels"]),
    "reconstruction.scanline_to_points": (lambda tmp: reconstruction.scanline_to_points(np.ones(5)),
                                          ["points", "samples", "segments"]),
    "decimation.cluster": (lambda tmp: decimation.cluster(*datasets.icosphere(2), target_vertices=40),
                           ["V", "F", "vertex_cluster", "is_manifold", "cell_size"]),
    "decimation.decimate": (lambda tmp: decimation.decimate(*datasets.icosphere(2), target_faces=60), ["V", "F"]),
    "decimation.decimate return_report": (
        lambda tmp: decimation.decimate(*datasets.icosphere(2), target_faces=60, return_report=True),
        ["V", "F", "report"]),
    "decimation.DecimationReport": (
        lambda tmp: decimation.decimate(*datasets.icosphere(2), target_faces=60, return_report=True,
                                        record_collapses=True).report,
        ["vertex_origin", "max_error", "target_reached", "collapse_count", "split_vertex_origin", "collapses",
         "max_error_normalized", "max_error_exponent"]),
    "decimation.ProgressiveMesh.at": (lambda tmp: decimation.progressive_mesh(*datasets.icosphere(2)).at(100),
                                      ["V", "F"]),
    "decimation.ProgressiveMesh.face_range": (lambda tmp: decimation.progressive_mesh(*datasets.icosphere(2)).face_range,
                                              ["base", "full"]),
    "render.view_angles": (lambda tmp: render.view_angles("front"), ["azimuth", "elevation"]),
    "render.scalar_range": (lambda tmp: render.scalar_range(np.linspace(-1, 2, 50), 50), ["low", "high"]),
    "parametrization.map_boundary": (lambda tmp: parametrization.map_boundary(*disk()), ["indices", "uv"]),
    "parametrization.default_lscm_pins": (lambda tmp: parametrization.default_lscm_pins(*disk()),
                                          ["indices", "uv"]),
    "parametrization.stretch_minimizing": (lambda tmp: parametrization.stretch_minimizing(*disk(), iterations=2),
                                           ["uv", "stretch", "best_iteration"]),
    "parametrization.cut_to_disk": (
        lambda tmp: parametrization.cut_to_disk(*datasets.torus(n_major=16, n_minor=8)),
        ["V", "F", "vertex_origin", "seam_edges"]),
    "parametrization.check_bijectivity": (
        lambda tmp: parametrization.check_bijectivity(parametrization.lscm(*disk()), disk()[1]),
        ["bijective", "orientation", "degenerate_faces", "flipped_faces", "crossing_boundary_sides"]),
    "parametrization.abf": (lambda tmp: parametrization.abf(*disk()),
                            ["uv", "angles", "optimal_angles", "iterations", "residual", "residual_history"]),
    "parametrization.parametrize": (lambda tmp: parametrization.parametrize(*datasets.torus(n_major=16, n_minor=8)),
                                    ["V", "F", "uv", "cut", "method", "distortion", "bijective"]),
    "quadrangulation.cross_field": (lambda tmp: quadrangulation.cross_field(*datasets.icosphere(1)),
                                    ["theta", "directions"]),
    "quadrangulation.singularities": (
        lambda tmp: quadrangulation.singularities(*datasets.icosphere(1), quadrangulation.cross_field(*datasets.icosphere(1))),
        ["vertices", "indices"]),
    "quadrangulation.cut_graph": (
        lambda tmp: quadrangulation.cut_graph(*datasets.icosphere(1), quadrangulation.cross_field(*datasets.icosphere(1))),
        ["cut", "singularities", "combed_theta", "seam_jumps"]),
    "quadrangulation.miq": (
        lambda tmp: quadrangulation.miq(*datasets.icosphere(1), quadrangulation.cross_field(*datasets.icosphere(1))),
        ["UV", "flipped_before", "flipped_after"]),
    "repair.remove_unreferenced": (lambda tmp: repair.remove_unreferenced(*sphere_with_unused_vertex()),
                                   ["V", "F", "vertex_map"]),
    "repair.orient_faces": (lambda tmp: repair.orient_faces(*sphere_with_unused_vertex()), ["F", "flipped"]),
    "repair.clean": (lambda tmp: repair.clean(*sphere_with_unused_vertex()), ["V", "F", "report"]),
    "repair.remove_needles_and_caps": (lambda tmp: repair.remove_needles_and_caps(*datasets.icosphere(1)), ["V", "F"]),
    "repair.stitch_boundaries": (lambda tmp: repair.stitch_boundaries(*sphere_with_hole(), tolerance=1e-3), ["V", "F"]),
    "repair.volumetric_repair": (lambda tmp: repair.volumetric_repair(*datasets.icosphere(1), epsilon=0.3),
                                 ["V", "F", "report"]),
    "repair.volumetric_repair report": (lambda tmp: repair.volumetric_repair(*datasets.icosphere(1), epsilon=0.3).report,
                                        ["shape", "cell_size"]),
    "repair.fill_holes": (lambda tmp: repair.fill_holes(*sphere_with_hole()), ["V", "F", "report"]),
    "repair.zipper": (lambda tmp: repair.zipper(*sphere_halves(), tolerance=1e-6), ["V", "F", "report"]),
    "repair.zipper report": (lambda tmp: repair.zipper(*sphere_halves(), tolerance=1e-6).report,
                             ["face_source", "face_map"]),
    "repair.fill_holes report": (lambda tmp: repair.fill_holes(*sphere_with_hole()).report, ["patches", "unfilled"]),
    "repair.fill_holes patch": (lambda tmp: repair.fill_holes(*sphere_with_hole()).report.patches[0],
                                ["loop", "faces", "vertices"]),
    "repair.clean report": (lambda tmp: repair.clean(*sphere_with_unused_vertex()).report,
                            [field.name for field in dataclasses.fields(repair.CleanReport)]),
    "repair.remove_self_intersections": (lambda tmp: repair.remove_self_intersections(*poked_sphere()),
                                         ["V", "F", "report"]),
    "repair.remove_self_intersections report": (
        lambda tmp: repair.remove_self_intersections(*poked_sphere()).report, ["initial_pairs", "remaining_pairs"]),
    "repair.find_defects": (lambda tmp: repair.find_defects(*sphere_with_hole()),
                            [field.name for field in dataclasses.fields(repair.MeshDefectCounts)]),
    "quadrangulation.extract_quads": (lambda tmp: quadrangulation.extract_quads(*square_grid_map()), ["V", "Q"]),
    "quadrangulation.extract_quads report": (
        lambda tmp: quadrangulation.extract_quads(*square_grid_map()).report,
        [field.name for field in dataclasses.fields(quadrangulation.QuadExtractionReport)]),
    "quadrangulation.quadrangulate": (
        lambda tmp: quadrangulation.quadrangulate(*datasets.torus(n_major=24, n_minor=10), target_faces=60),
        ["V", "Q", "report"]),
    "quadrangulation.quadrangulate report": (
        lambda tmp: quadrangulation.quadrangulate(*datasets.torus(n_major=24, n_minor=10), target_faces=60).report,
        [field.name for field in dataclasses.fields(quadrangulation.QuadrangulationReport)]),
    "quadrangulation.morse_smale_complex": (
        lambda tmp: quadrangulation.morse_smale_complex(*datasets.icosphere(2), datasets.icosphere(2)[0][:, 2]),
        [field.name for field in dataclasses.fields(quadrangulation.MorseSmaleComplex)]),
    "quadrangulation.spectral_quadrangulate": (
        lambda tmp: quadrangulation.spectral_quadrangulate(*datasets.icosphere(3), target_faces=200),
        ["V", "Q", "report"]),
    "quadrangulation.spectral_quadrangulate report": (
        lambda tmp: quadrangulation.spectral_quadrangulate(*datasets.icosphere(3), target_faces=200).report,
        [field.name for field in dataclasses.fields(quadrangulation.SpectralQuadrangulationReport)]),
    "quadrangulation.quad_quality": (
        lambda tmp: quadrangulation.quad_quality(*quadrangulation.extract_quads(*square_grid_map())),
        [field.name for field in dataclasses.fields(quadrangulation.QuadQuality)]),
    "quadrangulation.dual_loop_layout": (
        lambda tmp: quadrangulation.dual_loop_layout(*datasets.icosphere(2), quadrangulation.cross_field(*datasets.icosphere(2))),
        ["loops", "region", "Vq", "Q", "report"]),
    "quadrangulation.dual_loop_layout report": (
        lambda tmp: quadrangulation.dual_loop_layout(*datasets.icosphere(2), quadrangulation.cross_field(*datasets.icosphere(2))).report,
        [field.name for field in dataclasses.fields(quadrangulation.DualLoopReport)]),
    "quadrangulation.DualLoopAttempt": (lambda tmp: quadrangulation.DUAL_LOOP_SCHEDULE[0],
                                        ["merge", "refine", "parallel_crossing_penalty", "max_failed_seeds"]),
    "quadrangulation.refine_field": (
        lambda tmp: quadrangulation.refine_field(*datasets.icosphere(1), np.zeros(80)), ["V", "F", "theta", "parent"]),
    "reconstruction.marching_cubes": (lambda tmp: meshsmith.reconstruction.marching_cubes(ball_grid()),
                                      ["V", "F", "centre_vertices", "blocks", "evaluations"]),
    "reconstruction.mesh_sdf": (lambda tmp: meshsmith.reconstruction.mesh_sdf(*datasets.icosphere(1), np.eye(3)),
                                ["distance", "face", "point", "winding"]),
    "reconstruction.sample_grid": (lambda tmp: meshsmith.reconstruction.sample_grid([[0, 0, 0], [1, 1, 1]], 3),
                                   ["points", "shape", "origin", "spacing"]),
    "reconstruction.poisson": (lambda tmp: meshsmith.reconstruction.poisson(*datasets.sphere_points(300), depth=4),
                               ["V", "F", "density", "iso", "level_depths", "level_unknowns", "level_iterations",
                                "level_residuals", "extraction_depth"]),
    "reconstruction.trim_by_density": (
        lambda tmp: meshsmith.reconstruction.trim_by_density(*datasets.icosphere(1), np.arange(42.0)),
        ["V", "F", "vertex_map"]),
    "reconstruction.graph_cut": (lambda tmp: meshsmith.reconstruction.graph_cut(datasets.sphere_points(400, seed=1)[0], resolution=16),
                                 ["V", "F", "shape", "origin", "voxel_size", "cut", "free_voxels", "inside_voxels"]),
    "reconstruction.max_flow": (lambda tmp: meshsmith.reconstruction.max_flow(2, [[0, 1]], [1.0], [0.0], [1.0, 0], [0, 1.0]),
                                ["flow", "source_side"]),
}


def plain(value, where="result"):
    """Assert that value is made of arrays, numbers, strings, None and containers or named results of
    those: what a batch engine can move (no handle to a C++ object)."""
    if value is None or isinstance(value, (str, bool, numbers.Number, np.generic)):
        return
    if isinstance(value, np.ndarray):
        assert value.dtype != object, f"{where}: object array"
        return
    if isinstance(value, dict):
        for key, item in value.items():
            plain(item, f"{where}[{key!r}]")
        return
    if isinstance(value, (list, tuple)):
        for index, item in enumerate(value):
            plain(item, f"{where}[{index}]")
        return
    if dataclasses.is_dataclass(value):
        for field in dataclasses.fields(value):
            plain(getattr(value, field.name), f"{where}.{field.name}")
        return
    pytest.fail(f"{where} is a {type(value).__module__}.{type(value).__name__}, not plain data")


def same(a, b):
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)) or dataclasses.is_dataclass(a):
        return type(a) is type(b) and len(list(a)) == len(list(b)) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and np.isnan(a):
        return isinstance(b, float) and np.isnan(b)
    return a == b


@pytest.mark.parametrize("name", sorted(RESULTS))
def test_result_is_named_unpacks_in_order_and_pickles_to_plain_arrays(name, tmp_path):
    make, names = RESULTS[name]
    result = make(tmp_path)
    assert isinstance(result, (tuple, Unpackable)), f"{name} returns a {type(result).__name__}"
    unpacked = tuple(result)
    assert len(unpacked) == len(names)
    for value, field in zip(unpacked, names):
        assert value is getattr(result, field), f"{name}: position of {field}"
    plain(result)
    restored = pickle.loads(pickle.dumps(result))
    assert type(restored) is type(result) and same(result, restored)


def test_every_result_class_of_the_api_unpacks_and_is_exercised_above(tmp_path):
    # Every NamedTuple or dataclass a chapter exports is a result and must unpack (DESIGN.md:
    # "Results"), except io.Polygons (a face container: it iterates over its polygons) and
    # render.Camera (an input of render, one value).
    classes = {}
    for chapter in CHAPTERS:
        module = importlib.import_module(f"meshsmith.{chapter}")
        for name in module.__all__:
            value = getattr(module, name)
            if inspect.isclass(value) and (dataclasses.is_dataclass(value) or issubclass(value, tuple)):
                classes[f"{chapter}.{name}"] = value
    assert len(classes) >= 35
    classes.pop("io.Polygons")
    classes.pop("render.Camera")
    not_unpacking = [name for name, cls in classes.items() if not issubclass(cls, (tuple, Unpackable))]
    assert not not_unpacking, not_unpacking
    # every one of them is exercised by the test above, so it is known to unpack and pickle
    covered = {type(make(tmp_path)) for make, _ in RESULTS.values()}
    assert not set(classes.values()) - covered, set(classes.values()) - covered


def test_progressive_mesh_pickles_with_its_level():
    pm = decimation.progressive_mesh(*datasets.icosphere(2))
    pm.set_level(pm.n_splits // 2)
    restored = pickle.loads(pickle.dumps(pm))
    assert restored.level == pm.level and restored.n_splits == pm.n_splits
    assert same(tuple(restored.mesh()), tuple(pm.mesh()))
    restored.set_level(restored.n_splits)
    pm.set_level(pm.n_splits)
    assert same(tuple(restored.mesh()), tuple(pm.mesh()))


# ------------------------------------------------------------------- argument order

GEOMETRY_FIRST = {"V", "F", "P", "UV", "samples", "points", "VA", "first", "V_or_F", "path", "result"}


def public_functions():
    for chapter in CHAPTERS:
        module = importlib.import_module(f"meshsmith.{chapter}")
        for name in module.__all__:
            value = getattr(module, name)
            if inspect.isfunction(value):
                yield f"{chapter}.{name}", value
            elif inspect.isclass(value):
                for attribute, member in vars(value).items():
                    if inspect.isfunction(member) and (not attribute.startswith("_") or attribute == "__init__"):
                        yield f"{chapter}.{name}.{attribute}", member


def test_options_are_keyword_only_after_the_geometry():
    """The rule of README's Conventions: geometry (or the path) first, then required inputs and
    optional inputs (default None), then keyword-only options. Functions without geometry (the
    datasets generators, colormap) are not concerned."""
    checked, breaking = 0, {}
    for name, function in public_functions():
        parameters = [p for p in inspect.signature(function).parameters.values() if p.name not in ("self", "cls")]
        if not parameters or parameters[0].name not in GEOMETRY_FIRST:
            continue
        checked += 1
        positional_options = [p.name for p in parameters if p.kind is p.POSITIONAL_OR_KEYWORD
                              and p.default is not p.empty and p.default is not None]
        if positional_options:
            breaking[name] = positional_options
    assert checked > 80
    assert not breaking, breaking


def test_io_takes_the_path_first_and_everything_else_the_geometry_first():
    for function in (io.read_mesh, io.write_mesh, io.read_points, io.write_points, io.read_poly, io.read_range_scan):
        assert next(iter(inspect.signature(function).parameters)) == "path"
    assert list(inspect.signature(render.render).parameters)[:3] == ["V", "F", "path"]
    assert list(inspect.signature(render.parametrization_picture).parameters)[:2] == ["result", "path"]


OLD_FORMS = [
    ("vertex_normals(V, F, 'area')", lambda V, F: geometry.vertex_normals(V, F, "area"),
     lambda V, F: geometry.vertex_normals(V, F, weighting="area")),
    ("mass_matrix(V, F, 'barycentric')", lambda V, F: geometry.mass_matrix(V, F, "barycentric").toarray(),
     lambda V, F: geometry.mass_matrix(V, F, kind="barycentric").toarray()),
    ("estimate_normals(P, 8)", lambda V, F: points.estimate_normals(V, 8),
     lambda V, F: points.estimate_normals(V, k=8)),
    ("genus(F, True)", lambda V, F: topology.genus(F, True), lambda V, F: topology.genus(F, per_component=True)),
    ("noisy(V, F, 0.05, 3)", lambda V, F: tuple(datasets.noisy(V, F, 0.05, 3)),
     lambda V, F: tuple(datasets.noisy(V, F, sigma=0.05, seed=3))),
    ("frame_camera(V, 'front')", lambda V, F: render.frame_camera(V, "front"),
     lambda V, F: render.frame_camera(V, view="front")),
]


@pytest.mark.parametrize("label, old, new", OLD_FORMS, ids=[form[0] for form in OLD_FORMS])
def test_old_positional_options_still_work_with_a_deprecation_warning(label, old, new):
    V, F = datasets.icosphere(1)
    with pytest.warns(DeprecationWarning, match="by keyword"):
        before = old(V, F)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        after = new(V, F)
    assert same(before, after) if not dataclasses.is_dataclass(before) else before == after


def test_old_map_boundary_and_curve_forms_warn_and_agree():
    from meshsmith import curves
    V, F = disk()
    with pytest.warns(DeprecationWarning, match="shape="):
        old = parametrization.map_boundary(V, F, "square")
    assert same(tuple(old), tuple(parametrization.map_boundary(V, F, shape="square")))
    P = circle_samples()
    with pytest.warns(DeprecationWarning, match="closed=, method="):
        old = curves.curvature(P, True, "osculating_circle")
    np.testing.assert_array_equal(old, curves.curvature(P, closed=True, method="osculating_circle"))
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)   # the ellipse (2 cos t, sin t)
    np.testing.assert_allclose(old, 2 / (4 * np.sin(t) ** 2 + np.cos(t) ** 2) ** 1.5, rtol=0.1)


def test_too_many_positional_values_and_duplicates_are_type_errors():
    V, F = datasets.icosphere(1)
    with pytest.raises(TypeError, match="at most"):
        geometry.vertex_normals(V, F, "area", "extra")
    with pytest.raises(TypeError, match="multiple values"):
        geometry.vertex_normals(V, F, "area", weighting="angle")
