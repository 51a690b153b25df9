"""Every public function of meshsmith against bad arguments (issue 14 part 1), property-based.

The functions are enumerated from the ``__all__`` of every module that ``meshsmith.__all__``
lists (and the public methods of its classes), so a new function is fuzzed as soon as it is
exported: its valid arguments come from VALID_BY_NAME (by parameter name) and VALID (per
function), and a function neither can call fails the test by name.

For every array argument, integer option, float option and progress callback of every function,
hypothesis draws a profile (where the NaN goes, which row is ragged, which dtype, which layout,
...) and each call gets one variant: ragged lists and tuples, object arrays, None, strings,
complex, bool, float indices, 0-d and wrong-dimensional arrays, wrong column counts, empty
arrays, NaN, Inf, indices outside the mesh and the 32-bit range; lossless other forms of the
valid array (non-contiguous, read-only, big-endian, nested lists and tuples, other index dtypes);
integers 2^31, 2^63, 2^70, -1, NaN, 1.5, strings and lists for integer options; NaN, Inf, negative
values, strings, lists, bools and None (where None is not a documented value) for float options,
also for the numeric options a valid call leaves at their defaults; callbacks that return something other than a bool or None, raise, or
are not callable. Each example is one profile applied to every function (about 4,800 calls); the
default 4 examples are the same on every run (MESHSMITH_FUZZ_RANDOM=1 draws new ones,
MESHSMITH_FUZZ_EXAMPLES=n more of them). The calls run in child processes
(tests/fuzz_worker.py), batched, so a segfault or a hang is caught and names its call. Each call must raise InputError (for the
variants that are not an array of the right shape and dtype), or InputError / SolverError / a
result without NaN (for values that are valid arrays: NaN, Inf, empty, out-of-range), or give
the same result as the valid call (for the lossless forms); no call may modify its arguments.
"""
from __future__ import annotations

import copy
import dataclasses
import inspect
import json
import os
import pickle
import re
import select
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

import meshsmith
from meshsmith import datasets

import fuzz_worker as worker

WORKER = Path(worker.__file__).resolve()
CALL_TIMEOUT = 20.0  # seconds for one call before it counts as a hang

# ---- valid arguments ----------------------------------------------------------------------

SPHERE_V, SPHERE_F = datasets.icosphere(1)                 # 42 vertices, 80 faces, closed
DISK_V, DISK_F = datasets.disk(3, 12)                      # 25 vertices, 36 faces, one boundary loop
DISK_LOOP = np.array([13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24], dtype=np.int64)
_angle = 2 * np.pi * np.arange(len(DISK_LOOP)) / len(DISK_LOOP)
DISK_LOOP_UV = np.stack([np.cos(_angle), np.sin(_angle)], 1)
DISK_UV = DISK_V[:, :2].copy()                             # the flat disk is its own map
UNREFERENCED_V = np.vstack([SPHERE_V[:5], [[9.0, 9.0, 9.0]], SPHERE_V[5:]])  # vertex 5 unused
UNREFERENCED_V_FACES = np.where(SPHERE_F >= 5, SPHERE_F + 1, SPHERE_F)
POINTS, NORMALS = datasets.sphere_points(60, seed=1)
QUERIES = 1.1 * POINTS[:5]
PLANAR = np.random.default_rng(0).random((30, 2))
SQUARE = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.3, 0.4], [0.6, 0.7]], dtype=np.float64)
SQUARE_SEGMENTS = np.array([[0, 1], [1, 2], [2, 3], [3, 0]], dtype=np.int64)
_grid_V, GRID_F = datasets.grid(3, 3)
GRID_V = _grid_V[:, :2].copy()                             # a planar triangulation
_t = 2 * np.pi * np.arange(40) / 40
CIRCLE = np.stack([np.cos(_t), 1.5 * np.sin(_t)], 1)       # dense samples of a closed curve
CURVE = CIRCLE[::2].copy()
_x = np.linspace(-1, 1, 6)
BALL_VALUES = np.sqrt(sum(c ** 2 for c in np.meshgrid(_x, _x, _x, indexing="ij"))) - 0.7  # a 6³ grid


def ball_field(P: np.ndarray) -> np.ndarray:
    """The signed distance to a ball of radius 2 (a field for marching_cubes_sparse)."""
    return np.linalg.norm(P, axis=1) - 2.0


def _disk_angles() -> np.ndarray:
    """The corner angles of the flat disk: they satisfy ABF's conditions exactly."""
    corners = DISK_V[DISK_F]
    angles = np.empty(DISK_F.shape)
    for c in range(3):
        a, b = corners[:, (c + 1) % 3] - corners[:, c], corners[:, (c + 2) % 3] - corners[:, c]
        angles[:, c] = np.arccos(np.einsum("ij,ij->i", a, b) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1))
    return angles


def files(folder: Path) -> dict[str, str]:
    """Small valid input files for the readers."""
    obj = folder / "in.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in SPHERE_V)
                   + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in SPHERE_F))
    xyz = folder / "in.xyz"
    xyz.write_text("".join(f"{x} {y} {z}\n" for x, y, z in POINTS))
    poly = folder / "in.poly"
    poly.write_text("4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 0\n0\n")
    scan = folder / "scan.ply"   # a 2 × 2 range grid
    scan.write_text("ply\nformat ascii 1.0\nobj_info num_cols 2\nobj_info num_rows 2\nelement vertex 4\n"
                    "property float x\nproperty float y\nproperty float z\nelement range_grid 4\n"
                    "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n"
                    "1 0\n1 1\n1 2\n1 3\n")
    return {"obj": str(obj), "xyz": str(xyz), "poly": str(poly), "scan": str(scan), "out": str(folder / "out")}


#: Valid values by parameter name, for every function unless VALID overrides them (by chapter
#: first: "tessellation.P" beats "P").
VALID_BY_NAME = {
    "V": SPHERE_V, "F": SPHERE_F, "P": POINTS, "Q": QUERIES, "N": NORMALS, "k": 4,
    "VA": SPHERE_V, "FA": SPHERE_F, "VB": 1.05 * SPHERE_V, "FB": SPHERE_F,
    "samples": CIRCLE, "points": POINTS,
    "parametrization.V": DISK_V, "parametrization.F": DISK_F,
    "tessellation.P": PLANAR, "tessellation.V": GRID_V, "tessellation.F": GRID_F,
    "curves.P": CURVE,
}

#: Per-function valid arguments (merged over VALID_BY_NAME). Callables get the files dict.
#: "owner": (factory target, args) building the object whose method is called.
VALID = {
    "core.mesh_defects": {},
    "core.set_num_threads": {"count": 2},
    "io.read_mesh": lambda f: {"path": f["obj"]},
    "io.write_mesh": lambda f: {"path": f["out"] + ".obj", "UV": SPHERE_V[:, :2].copy(), "F_uv": SPHERE_F,
                                "normals": SPHERE_V, "F_normal": SPHERE_F},
    "io.read_points": lambda f: {"path": f["xyz"]},
    "io.write_points": lambda f: {"path": f["out"] + ".ply"},
    "io.read_poly": lambda f: {"path": f["poly"]},
    "io.read_range_scan": lambda f: {"path": f["scan"]},
    "io.Polygons.from_triangles": {},
    "io.Polygons.from_list": {"faces": [[0, 1, 2, 3], [3, 2, 4]]},
    "io.Polygons.triangulate": {"owner": ("io.Polygons", (np.array([0, 4, 7]), np.array([0, 1, 2, 3, 3, 2, 4])))},
    "topology.connected_components": {"n_vertices": 42},
    "topology.euler_characteristic": {"V_or_F": SPHERE_V, "F": SPHERE_F},
    "geometry.uniform_laplacian": {"first": SPHERE_F, "second": 42},
    "geometry.laplacian_eigenpairs": {"k": 3},
    "geometry.triangle_distortion": {"V": DISK_V, "F": DISK_F, "UV": DISK_UV},
    "geometry.SurfaceDistance": {"leaf_size": 4},
    "geometry.SurfaceDistance.closest_points": {"owner": ("geometry.SurfaceDistance", (SPHERE_V, SPHERE_F))},
    "geometry.SurfaceDistance.distances": {"owner": ("geometry.SurfaceDistance", (SPHERE_V, SPHERE_F))},
    "geometry.hausdorff_distance": {"sampled": True, "samples_per_face": 2, "seed": 3},
    "geometry.mean_surface_distance": {"sampled": True, "samples_per_face": 2, "seed": 3},
    "curves.arc_length_parametrization": {"n": 10},
    "points.KdTree": {"leaf_size": 8},
    "points.KdTree.query": {"owner": ("points.KdTree", (POINTS,)), "k": 3},
    "points.KdTree.query_radius": {"owner": ("points.KdTree", (POINTS,)), "radius": 0.5},
    "points.KdTree.estimate_normals": {"owner": ("points.KdTree", (POINTS,)), "k": 5},
    "points.knn": {"k": 3},
    "points.estimate_normals": {"k": 5, "radius": 0.6},
    "points.orient_normals": {"k": 5, "axis": 2},
    "render.view_angles": None,            # no array, integer or callback argument
    "render.frame_camera": {"size": (64, 48)},
    "render.colormap": {"name": "viridis", "steps": 16},
    "render.scalar_range": {"scalar": SPHERE_V[:, 0].copy(), "vertex_count": 42},
    "render.default_colormap": {"scalar": SPHERE_V[:, 0].copy()},
    "render.clipped_ends": {"scalar": SPHERE_V[:, 0].copy(), "low": -0.5, "high": 0.5},
    "render.render": {"size": (40, 30), "scalar": SPHERE_V[:, 2].copy(), "uv": SPHERE_V[:, :2].copy(),
                      "supersample": 1, "columns": 1, "checker_size": 0.2},
    "render.render_uv_layout": {"UV": DISK_UV, "F": DISK_F, "size": (40, 40), "scalar": DISK_V[:, 0].copy(),
                                "supersample": 1},
    "render.plot_planar": {"points": PLANAR, "triangles": (GRID_V, GRID_F), "segments": (SQUARE, SQUARE_SEGMENTS),
                           "highlight": PLANAR[:3], "size": (40, 40), "supersample": 1},
    "render.parametrization_picture": None,  # a picture of a Parametrization: no array argument
    "render.save_png": lambda f: {"canvas": np.zeros((4, 5, 3), np.uint8), "path": f["out"] + ".png"},
    "tessellation.constrained_delaunay": {"P": SQUARE, "segments": SQUARE_SEGMENTS, "holes": np.array([[5.0, 5.0]])},
    "tessellation.voronoi": {"bounds": np.array([-1.0, -1.0, 2.0, 2.0])},
    "tessellation.refine": {"P": SQUARE, "segments": SQUARE_SEGMENTS, "max_area": 0.05, "max_steiner_points": 2000},
    "tessellation.power_diagram": {"weights": np.zeros(len(PLANAR)), "bounds": np.array([-1.0, -1.0, 2.0, 2.0])},
    "tessellation.is_r_sample": {"R": 0.5},
    "tessellation.crust_3d": {"max_hole_edges": 8},
    "decimation.cluster": {"target_vertices": 20},
    "decimation.decimate": {"target_faces": 40, "candidates": 4, "max_valence": 9, "seed": 1,
                            "max_normal_deviation": 90.0, "min_quality": 0.01},
    "decimation.progressive_mesh": {},
    "decimation.ProgressiveMesh": None,     # built by progressive_mesh (its methods are fuzzed below)
    "decimation.ProgressiveMesh.load": None,  # a path only
    "decimation.ProgressiveMesh.save": None,  # a path only
    "decimation.ProgressiveMesh.mesh": None,  # no argument
    "decimation.ProgressiveMesh.face_count": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "level": 3},
    "decimation.ProgressiveMesh.set_level": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "level": 3},
    "decimation.ProgressiveMesh.refine": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "steps": 2},
    "decimation.ProgressiveMesh.coarsen": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "steps": 2},
    "decimation.ProgressiveMesh.level_for_face_count": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "n_faces": 40},
    "decimation.ProgressiveMesh.at": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "n_faces": 40},
    "decimation.ProgressiveMesh.refine_where": {"owner": ("decimation.progressive_mesh", (SPHERE_V, SPHERE_F)), "near": np.array([0.0, 0.0, 1.0]), "radius": 0.5},
    "parametrization.map_boundary": {"boundary": DISK_LOOP},
    "parametrization.harmonic": {"boundary": DISK_LOOP, "boundary_uv": DISK_LOOP_UV},
    "parametrization.stretch_minimizing": {"iterations": 2},
    "parametrization.lscm": {"pinned": np.array([13, 19]), "pinned_uv": np.array([[0.0, 0.0], [1.0, 0.0]])},
    "parametrization.check_bijectivity": {"UV": DISK_UV},
    "parametrization.is_bijective": {"UV": DISK_UV},
    "parametrization.abf": {"max_iterations": 30},
    "parametrization.uv_from_angles": {"angles": _disk_angles(), "n_vertices": 25,
                                       "pinned": np.array([DISK_F[0, 0], DISK_F[0, 1]]),
                                       "pinned_uv": np.array([[0.0, 0.0], [1.0, 0.0]])},
    "repair.fill_holes": {"F": SPHERE_F[1:], "holes": [0]},
    "repair.stitch_boundaries": {"F": SPHERE_F[1:], "tolerance": 1e-3},
    "repair.volumetric_repair": {"epsilon": 0.3},
    "repair.zipper": {"VA": SPHERE_V, "FA": SPHERE_F[SPHERE_V[SPHERE_F].mean(axis=1)[:, 2] > -0.3],
                      "VB": SPHERE_V, "FB": SPHERE_F[SPHERE_V[SPHERE_F].mean(axis=1)[:, 2] < 0.3], "tolerance": 1e-6},
    "repair.ReferencedMesh.to_input_rows": {"owner": ("repair.remove_unreferenced", (UNREFERENCED_V, UNREFERENCED_V_FACES)),
                                            "values": SPHERE_V[:, :2].copy()},
    "repair.ReferencedMesh.to_input_indices": {"owner": ("repair.remove_unreferenced", (UNREFERENCED_V, UNREFERENCED_V_FACES)),
                                               "indices": np.array([0, 5, 41])},
    "repair.ReferencedMesh.from_input_indices": {"owner": ("repair.remove_unreferenced", (UNREFERENCED_V, UNREFERENCED_V_FACES)),
                                                 "indices": np.array([0, 6, 42])},
    "deformation.harmonic": {"b": np.array([0, 5, 9]), "bc": np.array([[0.0], [1.0], [2.0]]), "order": 2},
    "deformation.Deformer": {"handle": np.array([0, 1]), "fixed": np.array([30, 31]), "order": 2},
    "deformation.Deformer.deform": {"owner": ("deformation.Deformer", (SPHERE_V, SPHERE_F, np.array([0, 1]), np.array([30, 31]))),
                                    "handle_positions": SPHERE_V[[0, 1]] + 0.1},
    "deformation.Deformer.transform": {"owner": ("deformation.Deformer", (SPHERE_V, SPHERE_F, np.array([0, 1]), np.array([30, 31]))),
                                       "T": np.eye(4)},
    "deformation.ArapDeformer": {"handles": np.array([0, 1, 30])},
    "deformation.ArapDeformer.solve": {"owner": ("deformation.ArapDeformer", (SPHERE_V, SPHERE_F, np.array([0, 1, 30]))),
                                       "positions": SPHERE_V[[0, 1, 30]] + 0.1, "iterations": 2},
    "deformation.ArapDeformer.energy": {"owner": ("deformation.ArapDeformer", (SPHERE_V, SPHERE_F, np.array([0, 1, 30]))),
                                        "U": 1.1 * SPHERE_V},
    "deformation.arap": {"handles": np.array([0, 1, 30]), "positions": SPHERE_V[[0, 1, 30]] + 0.1, "iterations": 2},
    "deformation.arap_energy": {"U": 1.1 * SPHERE_V},
    "smoothing.bilaplacian": {"fixed": np.array([0, 5, 9])},
    "deformation.poisson_edit": {"handle": np.array([0, 1]), "fixed": np.array([30, 31]),
                                 "handle_positions": SPHERE_V[[0, 1]] + 0.1},
    "deformation.multiresolution_edit": {"fixed": np.array([0, 1, 30]), "base_edit": 1.1 * SPHERE_V},
    "smoothing.laplacian": {"fixed": np.array([0, 3]), "epsilon_ball": 0.05},
    "smoothing.taubin": {"fixed": np.array([1]), "error_slab": 0.05},
    "smoothing.smooth_curve": {"P": CURVE, "fixed": np.array([2]), "epsilon_ball": 0.1},
    "smoothing.transfer_function": {"k": np.linspace(0.0, 2.0, 5)},
    "registration.align": {"A": POINTS, "B": POINTS[:, [1, 2, 0]] + 1.0, "weights": np.ones(len(POINTS))},
    "registration.apply_transform": {"T": np.eye(4)},
    "registration.rotation_angle": {"T": np.eye(4)},
    "registration.icp": {"source": POINTS + 0.01, "target": POINTS, "max_iterations": 3, "normal_neighbours": 5,
                         "initial": np.eye(4), "threads": 1, "max_distance": 1.0, "target_normals": NORMALS,
                         "normal_angle": 60.0, "source_normals": NORMALS, "relative_rmse": 1e-6,
                         "relative_fitness": 1e-6, "patience": 5},
    "registration.icp_multi": {"scans": (POINTS + 0.01, POINTS), "max_iterations": 3, "normal_neighbours": 5,
                               "initial": np.stack([np.eye(4), np.eye(4)]), "rounds": 1, "threads": 1,
                               "max_distance": 1.0, "normal_angle": 60.0, "strategy": "pose_graph",
                               "overlap_distance": 0.1, "min_overlap": 0.2, "edge_samples": 50, "patience": 5},
    "registration.voxel_downsample": {"voxel_size": 0.2},
    "reconstruction.depth_to_points": {"depth": np.full((6, 7), 2.0), "fx": 5.0, "fy": 5.0, "cx": 3.0, "cy": 3.0,
                                       "mask": np.ones((6, 7), bool)},
    "reconstruction.depth_to_mesh": {"depth": np.full((6, 7), 2.0), "fx": 5.0, "fy": 5.0, "cx": 3.0, "cy": 3.0,
                                     "mask": np.ones((6, 7), bool)},
    "reconstruction.scanline_to_points": {"depths": np.ones(10), "center": np.zeros(2), "direction": np.ones(2)},
    "quadrangulation.field_angles": {"field": np.tile([1.0, 0.0, 0.0], (len(SPHERE_F), 1))},
    "quadrangulation.singularities": {"field": np.linspace(0.0, 1.0, len(SPHERE_F))},
    "quadrangulation.cut_graph": {"field": np.linspace(0.0, 1.0, len(SPHERE_F))},
    "quadrangulation.miq": {"field": np.linspace(0.0, 1.0, len(SPHERE_F)), "target_quads": 50},
    "quadrangulation.extract_quads": {"UV": 4 * SPHERE_V[SPHERE_F][:, :, :2]},
    "quadrangulation.quadrangulate": {"target_faces": 40},
    "quadrangulation.dual_loop_layout": {"field": np.linspace(0.0, 1.0, len(SPHERE_F)), "spacing": 0.5, "max_loops": 8,
                                         "max_failed_seeds": 20},
    "quadrangulation.refine_field": {"field": np.linspace(0.0, 1.0, len(SPHERE_F))},
    "quadrangulation.field_glyphs": {"field": np.linspace(0.0, 1.0, len(SPHERE_F)), "max_crosses": 30},
    "quadrangulation.field_picture": {"field": np.linspace(0.0, 1.0, len(SPHERE_F)), "size": (40, 30)},
    "quadrangulation.regions_picture": {"region": np.arange(len(SPHERE_F)) % 3, "size": (40, 30),
                                        "marked": np.array([0, 5])},
    "quadrangulation.merge_singularities": {"field": meshsmith.quadrangulation.cross_field(SPHERE_V, SPHERE_F), "distance": 0.8},
    "quadrangulation.morse_smale_complex": {"f": SPHERE_V[:, 2] + 0.1 * SPHERE_V[:, 0]},
    "quadrangulation.spectral_quadrangulate": {"target_faces": 40},
    "quadrangulation.quad_quality": {"V": np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]], float),
                                     "Q": np.array([[0, 1, 2, 3], [1, 4, 5, 2]])},
    "reconstruction.marching_cubes": {"values": BALL_VALUES},
    "reconstruction.marching_cubes_sparse": {"field": ball_field, "shape": np.array([6, 6, 6]),
                                             "seeds": np.array([[2.0, 0.0, 0.0]])},
    "reconstruction.tangent_plane_sdf": {"k": 3},
    "reconstruction.sample_grid": {"bounds": np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 1.0]]), "resolution": 5},
    "reconstruction.poisson": {"depth": 4, "coarse_depth": 3, "max_iterations": 50},
    "reconstruction.trim_by_density": {"density": np.linspace(0.0, 1.0, 42)},
    "reconstruction.graph_cut": {"P": datasets.sphere_points(400, seed=1)[0], "resolution": 16},
    "reconstruction.max_flow": {"node_count": 3, "edges": np.array([[0, 1], [1, 2]]), "capacities": np.ones(2),
                                "reverse_capacities": np.zeros(2), "source": np.array([1.0, 0, 0]),
                                "sink": np.array([0, 0, 1.0])},
    "datasets.icosphere": {"subdivisions": 1},
    "datasets.uv_sphere": {"n_latitude": 4, "n_longitude": 8},
    "datasets.torus": {"n_major": 8, "n_minor": 4},
    "datasets.grid": {"nx": 3, "ny": 3},
    "datasets.disk": {"n_rings": 2, "n_segments": 8},
    "datasets.cube": {"subdivisions": 2},
    "datasets.noisy": {"seed": 2},
    "datasets.sample_points": {"n": 20, "seed": 2},
    "datasets.sphere_points": {"n": 20, "seed": 2},
    "datasets.scan_pair": {"n_source": 20, "n_target": 30, "seed": 2, "outliers": 0.1, "angle": 10.0},
}
#: Result fields documented to hold NaN (a lossy cast of the valid array, e.g. to uint8, can make
#: every triangle of a vertex degenerate).
NAN_ALLOWED: dict[str, tuple] = {
    "geometry.triangle_distortion": ("vertex_isometric", "vertex_conformal", "vertex_area", "vertex_stretch_l2",
                                     "vertex_stretch_linf"),
    "repair.ReferencedMesh.to_input_rows": ("result",),   # `fill`, NaN by default, in the unreferenced rows
    # no quad at all (a grid too coarse for the surface): the quality figures are undefined
    "quadrangulation.quadrangulate": ("mean_angle_deviation", "max_angle_deviation", "min_scaled_jacobian",
                                      "min_scaled_jacobian_extracted"),
}
#: Functions that take arrays of any shape (their dimension and column variants are valid input).
ANY_SHAPE = {"repair.ReferencedMesh.to_input_rows", "repair.ReferencedMesh.to_input_indices",
             "repair.ReferencedMesh.from_input_indices", "smoothing.transfer_function",
             "deformation.harmonic"}  # bc: (#b, c) for any number c of value columns
#: Face parameters that take polygons of any size as (m, s) arrays, s >= 3 (quad meshes): more
#: columns are valid input there.
POLYGON_FACES = {("render.render", "F"), ("render.render_uv_layout", "F"), ("topology.info", "F"),
                 ("io.Polygons.from_array", "F"), ("io.write_mesh", "F")}
#: Array parameters without a default for which None is documented as valid.
NONE_ACCEPTED = {("tessellation.constrained_delaunay", "segments"), ("tessellation.refine", "segments"),
                 ("core.set_num_threads", "count")}
#: Where a message names an integer option under another name than the Python parameter's.
OPTION_NAMES = {("geometry.uniform_laplacian", "second"): "n"}


# ---- the public API -------------------------------------------------------------------------

def is_data_class(obj) -> bool:
    """Result and value types (dataclasses, NamedTuples): data, not calls."""
    return inspect.isclass(obj) and (dataclasses.is_dataclass(obj) or
                                     (issubclass(obj, tuple) and hasattr(obj, "_fields")))


def public_targets() -> dict[str, object]:
    """target name ("chapter.function", "chapter.Class.method") → callable, from the __all__ lists:
    every function, every class that is not a data class, its public methods, and the methods of
    data classes that take arguments (Polygons.from_triangles) or that VALID names."""
    targets = {}
    for chapter in meshsmith.__all__:
        module = getattr(meshsmith, chapter)
        if not inspect.ismodule(module):
            continue
        assert hasattr(module, "__all__"), f"meshsmith.{chapter} has no __all__"
        for name in module.__all__:
            obj = getattr(module, name)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)) or \
                    (inspect.isclass(obj) and issubclass(obj, BaseException)):
                continue  # constants, type aliases (FloatArray, ...), exceptions and warnings
            if not is_data_class(obj):
                targets[f"{chapter}.{name}"] = obj
            if not inspect.isclass(obj):
                continue
            for method_name, method in inspect.getmembers(obj):
                target = f"{chapter}.{name}.{method_name}"
                if method_name.startswith("_") or not (inspect.isfunction(method) or inspect.ismethod(method)):
                    continue  # private, properties
                takes_arguments = len(inspect.signature(method).parameters) > inspect.isfunction(method)
                if is_data_class(obj) and not (target in VALID or (takes_arguments and not inspect.isfunction(method))):
                    continue  # a result's own methods (summary, lines) read its fields; classmethods are calls
                targets[target] = method
    return targets


def valid_call(target: str, function, folder_files) -> tuple[dict, tuple | None] | None:
    """(valid keyword arguments, owner) for `target`, or None when it has nothing to fuzz.
    Raises LookupError naming a required parameter with no known valid value."""
    entry = VALID.get(target, {})
    if entry is None:
        return None
    entry = dict(entry(folder_files) if callable(entry) else entry)
    owner = entry.pop("owner", None)
    chapter = target.split(".")[0]
    parameters = inspect.signature(function).parameters
    kwargs = {}
    for name, parameter in parameters.items():
        if name in ("self", "cls") or parameter.kind in (parameter.VAR_KEYWORD, parameter.VAR_POSITIONAL):
            continue
        if name in entry:
            kwargs[name] = entry[name]
        elif f"{chapter}.{name}" in VALID_BY_NAME:
            kwargs[name] = VALID_BY_NAME[f"{chapter}.{name}"]
        elif name in VALID_BY_NAME:
            kwargs[name] = VALID_BY_NAME[name]
        elif isinstance(parameter.default, (int, float)) and not isinstance(parameter.default, bool):
            kwargs[name] = parameter.default  # a numeric option: fuzzed from its default
        elif parameter.default is inspect.Parameter.empty:
            raise LookupError(f"{target}: no valid value known for its parameter {name!r}: "
                              "add it to VALID in tests/test_fuzz_inputs.py")
    return kwargs, owner


# ---- variants -----------------------------------------------------------------------------

REJECT, EITHER, SAME = "reject", "either", "same"


@dataclasses.dataclass
class Profile:
    """What one hypothesis example varies in every variant it makes."""

    seed: int
    wrong_columns: int          # a column count no function takes for an array (not 2 or 3)
    ragged_row: float           # which row is cut short, as a fraction of the rows
    float_dtype: str
    index_dtype: str
    layout: str                 # how the non-contiguous copy is made
    int_overflow: int           # an index beyond int32
    empty_rows: bool            # empty as (0, c) or as []


def profiles():
    return st.builds(
        Profile, seed=st.integers(0, 2**32 - 1), wrong_columns=st.sampled_from([1, 4, 5, 7]),
        ragged_row=st.floats(0, 1), float_dtype=st.sampled_from(["float32", "float16", "int32", "uint8", "longdouble"]),
        index_dtype=st.sampled_from(["int16", "uint16", "int32", "uint32", "uint64", ">i8", "<i4"]),
        layout=st.sampled_from(["fortran", "strided", "transposed-back"]),
        int_overflow=st.sampled_from([2**31, 2**32 + 1, 2**63 - 1, -2**31 - 1, -2**63]),
        empty_rows=st.booleans())


def noncontiguous(a: np.ndarray, layout: str) -> np.ndarray:
    if layout == "fortran" and a.ndim == 2:
        out = np.asfortranarray(a)
    elif layout == "strided" or a.ndim != 2:
        out = np.repeat(a, 2, axis=0)[::2]
    else:
        out = np.ascontiguousarray(a.T).T
    assert np.array_equal(out, a)
    return out


def array_variants(a: np.ndarray, optional: bool, mesh_faces: bool, profile: Profile, rng):
    """(kind, value, expectation) for an array argument whose valid value is `a`."""
    image = a.dtype == np.uint8  # a picture (save_png): uint8 only, so other integer forms are not it
    index = a.dtype.kind in "iu" and not image
    flag = a.dtype.kind == "b"
    rows = a.tolist()
    out = []
    if a.ndim >= 1 and len(a) >= 2:
        r = min(int(profile.ragged_row * len(a)), len(a) - 1)
        ragged = [list(row) if isinstance(row, list) else row for row in rows]
        ragged[r] = ragged[r][:-1] if a.ndim == 2 else [ragged[r], ragged[r]]
        out.append(("ragged list", ragged, REJECT))
        out.append(("ragged tuple", (a, np.zeros((len(a) + 1, 3))), REJECT))  # like (H, Hn)
    out += [("object array", a.astype(object), REJECT),
            ("None", None, EITHER if optional else REJECT),
            ("string", "abc", REJECT),
            ("string array", np.full(a.shape, "x"), REJECT),
            ("complex", a.astype(complex), REJECT),
            ("0-d", np.float64(1.0), REJECT),
            ("3-d", a[None], REJECT)]
    if not flag:
        out.append(("bool", a != 0, REJECT))
    if a.ndim == 2:
        out.append(("1-d", a.ravel(), REJECT))
        columns = profile.wrong_columns if profile.wrong_columns != a.shape[1] else (5 if a.shape[1] == 4 else 4)
        wrong = np.hstack([a] * 7)[:, :columns]
        out.append((f"{columns} columns", wrong, REJECT))
        out.append(("empty", a[:0] if profile.empty_rows else [], EITHER))
    else:
        out.append(("2-d", a[:, None], REJECT))
        out.append(("empty", a[:0], EITHER))
    out += [("read-only", _readonly(a), SAME), ("non-contiguous", noncontiguous(a, profile.layout), SAME),
            ("nested lists", rows, EITHER if image else SAME), ("nested tuples", _tuples(rows), EITHER if image else SAME)]
    if image:
        out += [("int64 picture", a.astype(np.int64), EITHER), ("float picture", a.astype(np.float64), EITHER)]
        return out
    if index:
        out.append(("float indices", a.astype(np.float64), REJECT))
        out.append((f"{profile.index_dtype} indices", a.astype(profile.index_dtype), SAME))
        out.append(("big-endian", a.astype(">i8"), SAME))
        position = tuple(rng.integers(0, n) for n in a.shape)
        for kind, value, expected in [("index -1", -1, REJECT if mesh_faces else EITHER),
                                      ("index n", int(a.max()) + 1 if not mesh_faces else None, EITHER),
                                      (f"index {profile.int_overflow}", profile.int_overflow, REJECT),
                                      ("index 2^64-1", 2**64 - 1, REJECT)]:
            if kind == "index n" and mesh_faces:
                continue  # handled below with the vertex count
            bad = a.astype(np.uint64 if value == 2**64 - 1 else np.int64)
            bad[position] = value
            out.append((kind, bad, expected))
    elif not flag:
        other = np.dtype(profile.float_dtype)
        # Integer dtypes get the array scaled onto [50, 150] first, so that geometry stays geometry.
        converted = a.astype(other) if other.kind == "f" else np.rint(50 * a + 100).astype(other)
        out.append((profile.float_dtype, converted, EITHER))
        out.append(("big-endian", a.astype(">f8"), SAME))
        for kind, value in [("NaN", np.nan), ("+Inf", np.inf), ("-Inf", -np.inf)]:
            bad = a.astype(np.float64)
            if bad.size:
                bad[tuple(rng.integers(0, n) for n in a.shape)] = value
            out.append((kind, bad, EITHER))
    return out


def _readonly(a):
    b = a.copy()
    b.flags.writeable = False
    return b


def _tuples(rows):
    return tuple(_tuples(r) if isinstance(r, list) else r for r in rows)


INTEGER_VARIANTS = [("-1", -1, EITHER), ("0", 0, EITHER), ("2^31", 2**31, EITHER), ("2^63", 2**63, EITHER),
                    ("2^70", 2**70, EITHER), ("NaN", float("nan"), REJECT), ("1.5", 1.5, REJECT),
                    ("'3'", "3", REJECT), ("list", [3], REJECT), ("numpy int64", np.int64(3), EITHER)]
FLOAT_VARIANTS = [("NaN", float("nan"), EITHER), ("+Inf", float("inf"), EITHER), ("-Inf", float("-inf"), EITHER),
                  ("-1.0", -1.0, EITHER), ("0.0", 0.0, EITHER), ("'abc'", "abc", REJECT), ("list", [0.5, 1.0], REJECT),
                  ("True", True, REJECT), ("numpy float32", np.float32(0.5), EITHER), ("int 1", 1, EITHER)]
PROGRESS_VARIANTS = [("returns 'yes'", worker.BadReturnCallback("yes"), "bad return"),
                     ("returns 1", worker.BadReturnCallback(1), "bad return"),
                     ("returns 0.5", worker.BadReturnCallback(0.5), "bad return"),
                     ("raises", worker.RaisingCallback(), "propagate"),
                     ("not callable", 5, REJECT)]


@dataclasses.dataclass
class Case:
    target: str
    parameter: str
    kind: str
    expected: str


def build_calls(profile: Profile, folder_files) -> tuple[list[worker.Call], list[Case], list[str]]:
    """Every variant of every fuzzable argument of every public target, as worker calls."""
    rng = np.random.default_rng(profile.seed)
    calls, cases, nothing_to_fuzz = [], [], []
    for target, function in sorted(public_targets().items()):
        found = valid_call(target, function, folder_files)
        if found is None:
            nothing_to_fuzz.append(target)
            continue
        kwargs, owner = found
        parameters = inspect.signature(function).parameters

        def add(parameter, kind, value, expected, reference=True):
            changed = dict(kwargs)
            if parameter is not None:
                changed[parameter] = value
            calls.append(worker.Call(
                id=len(calls), target=target, kwargs=changed,
                owner=owner, reference=((), kwargs) if reference else None,
                nan_allowed=NAN_ALLOWED.get(target, ())))
            cases.append(Case(target, parameter or "-", kind, expected))

        add(None, "valid", None, SAME)
        mesh_vertex_count = len(kwargs["V"]) if "V" in kwargs else len(kwargs["UV"]) if "UV" in kwargs else None
        for name, value in kwargs.items():
            optional = parameters[name].default is None or (target, name) in NONE_ACCEPTED
            values = [(None, value)]
            if isinstance(value, tuple) and all(isinstance(v, np.ndarray) for v in value):
                values = list(enumerate(value))  # a pair of arrays (plot_planar): each part in turn
            for part, array in values:
                if not isinstance(array, np.ndarray):
                    continue
                mesh_faces = name == "F" and mesh_vertex_count is not None
                variants = array_variants(array, optional and part is None, mesh_faces, profile, rng)
                if mesh_faces:
                    bad = array.astype(np.int64)
                    bad[tuple(rng.integers(0, n) for n in array.shape)] = mesh_vertex_count
                    variants.append(("index n", bad, REJECT))
                for kind, bad_value, expected in variants:
                    if target in ANY_SHAPE and (kind in ("1-d", "2-d", "3-d", "0-d") or kind.endswith(" columns")):
                        expected = EITHER
                    if (target, name) in POLYGON_FACES and kind.endswith(" columns") and int(kind.split()[0]) > 3:
                        expected = EITHER
                    if part is not None:
                        bad_value = tuple(bad_value if k == part else v for k, v in enumerate(value))
                        kind = f"[{part}] {kind}"
                    add(name, kind, bad_value, expected)
            if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
                for kind, bad_value, expected in INTEGER_VARIANTS:
                    add(name, f"integer {kind}", bad_value, expected)
                if not optional:
                    add(name, "integer None", None, REJECT)
            elif isinstance(value, float):
                for kind, bad_value, expected in FLOAT_VARIANTS:
                    add(name, f"float {kind}", bad_value, expected)
                if not optional and "None" not in str(parameters[name].annotation):
                    add(name, "float None", None, REJECT)
        for name, parameter in parameters.items():  # numeric options left at their defaults
            default = parameter.default
            if name in kwargs or isinstance(default, bool) or not isinstance(default, (int, float)):
                continue
            kinds = ([("'abc'", "abc"), ("list", [0.5, 1.0]), ("True", True)] if isinstance(default, float)
                     else [("'3'", "3"), ("list", [3]), ("1.5", 1.5)])
            if "None" not in str(parameter.annotation):
                kinds.append(("None", None))
            for kind, bad_value in kinds:
                add(name, f"{'float' if isinstance(default, float) else 'integer'} {kind}", bad_value, REJECT)
        if "progress" in parameters:
            for kind, callback, expected in PROGRESS_VARIANTS:  # a fresh callback per call (it counts its calls)
                add("progress", f"progress {kind}", copy.deepcopy(callback), expected)
    return calls, cases, nothing_to_fuzz


# ---- running the calls in child processes -------------------------------------------------

def run_in_children(calls: list[worker.Call], call_timeout: float = CALL_TIMEOUT) -> dict[int, dict]:
    """Outcome of every call; a call that kills its child or hangs gets {"signal": n} or {"hang": s}
    and the batch goes on in a new child from the next call."""
    outcomes: dict[int, dict] = {}
    remaining = list(calls)
    env = dict(os.environ, PYTHONFAULTHANDLER="1")
    while remaining:
        child = subprocess.Popen([sys.executable, str(WORKER)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, env=env)
        child.stdin.write(pickle.dumps(remaining))
        child.stdin.close()
        started, buffer, stderr = None, b"", b""
        deadline = time.monotonic() + 120.0  # the import before the first call
        streams = [child.stdout, child.stderr]
        while streams:
            ready, _, _ = select.select(streams, [], [], max(0.0, deadline - time.monotonic()))
            if not ready:
                child.kill()  # our own child, by its handle
                child.wait()
                outcomes[started] = {"hang": call_timeout}
                break
            for stream in ready:
                chunk = os.read(stream.fileno(), 1 << 16)
                if not chunk:
                    streams.remove(stream)
                    continue
                if stream is child.stderr:
                    stderr += chunk
                    continue
                buffer += chunk
                *lines, buffer = buffer.split(b"\n")
                for line in lines:
                    word, _, rest = line.decode().partition(" ")
                    if word == "start":
                        started = int(rest)
                        deadline = time.monotonic() + call_timeout
                    elif word == "done":
                        number, _, outcome = rest.partition(" ")
                        outcomes[int(number)] = json.loads(outcome)
                        started = None
        code = child.wait()
        if started is not None and started not in outcomes:
            key = "signal" if code < 0 else "exit"
            outcomes[started] = {key: abs(code), "stderr": stderr.decode(errors="replace")[-1500:]}
        elif code != 0 and started is None and not outcomes:
            pytest.fail(f"the fuzz worker failed before its first call:\n{stderr.decode(errors='replace')[-3000:]}")
        done = set(outcomes)
        remaining = [call for call in remaining if call.id not in done]
    return outcomes


def judge(case: Case, outcome: dict) -> str | None:
    """What is wrong with `outcome` for `case`, or None."""
    if "signal" in outcome:
        frames = [line.strip() for line in outcome["stderr"].splitlines() if line.strip().startswith("File ")]
        return f"killed by signal {outcome['signal']}" + (f" in {frames[0]}" if frames else "")
    if "exit" in outcome:
        return f"the worker exited with code {outcome['exit']} during the call:\n{outcome['stderr'][-600:]}"
    if "hang" in outcome:
        return f"no answer within {outcome['hang']:.0f} s (hang)"
    if "setup_error" in outcome:
        return f"the valid object could not be built: {outcome['setup_error']}"
    if outcome["modified"]:
        return f"modified its arguments {outcome['modified']}"
    raised = outcome.get("raised")
    message = outcome.get("message", "")
    returned_well = not raised and not outcome.get("nan")
    if not raised and outcome.get("nan"):
        problem = f"returned NaN at {outcome['nan']}"
    elif raised:
        problem = f"raised {raised}: {message}"
    else:
        problem = "returned a result"
    expected = case.expected
    if expected in ("bad return", "propagate") and outcome["callback_calls"] == 0:
        expected = SAME  # the callback was never called: nothing to report
    if expected == "bad return":
        if outcome.get("input_error") and "progress" in message:
            return None
        return f"{problem} (expected InputError about the progress callback's return value)"
    if expected == "propagate":
        return None if outcome.get("callback_failure") else f"{problem} (expected the callback's own CallbackFailure)"
    if expected == REJECT:
        if outcome.get("input_error"):
            return _option_named(case, message)
        return f"{problem} (expected InputError)"
    if expected == EITHER:
        if returned_well:
            return None
        if outcome.get("input_error"):
            return _option_named(case, message)
        if raised == "meshsmith._core.SolverError":
            return None
        return f"{problem} (expected InputError, SolverError or a result without NaN)"
    # SAME
    if outcome.get("reference_error"):
        return f"the valid call failed: {outcome['reference_error']}"
    if not returned_well:
        return f"{problem} (expected the valid call's result)"
    if outcome.get("differs"):
        return "returned a result that differs from the valid call's"
    return None


#: Integer option values outside every option's range (or not integers): the message must name it.
NAMED_INTEGER_VARIANTS = {"integer 2^63", "integer 2^70", "integer NaN", "integer 1.5", "integer '3'", "integer None",
                          "integer list", "float 'abc'", "float list", "float True", "float None"}


def _option_named(case: Case, message: str) -> str | None:
    """Integer options out of every range, and float options that are not real numbers: the
    InputError must name the option."""
    if case.kind not in NAMED_INTEGER_VARIANTS:
        return None
    name = OPTION_NAMES.get((case.target, case.parameter), case.parameter)
    return None if name in message else f"InputError that does not name {name!r}: {message}"


# ---- the tests ----------------------------------------------------------------------------

def test_the_harness_names_a_crashing_and_a_hanging_call():
    knn = dict(P=POINTS, k=3)
    calls = [worker.Call(id=0, target="points.knn", kwargs=knn),
             worker.Call(id=1, target="points.knn", kwargs=dict(knn, progress=worker.CrashingCallback())),
             worker.Call(id=2, target="points.knn", kwargs=dict(knn, progress=worker.SleepingCallback())),
             worker.Call(id=3, target="points.knn", kwargs=dict(knn, k=2**40))]
    outcomes = run_in_children(calls, call_timeout=3.0)
    assert outcomes[0]["returned"] and not outcomes[0]["modified"]
    assert outcomes[1]["signal"] == 11 and "fuzz_worker.py" in outcomes[1]["stderr"]
    assert outcomes[2] == {"hang": 3.0}
    assert outcomes[3]["input_error"] and "k = 1099511627776" in outcomes[3]["message"]
    assert judge(Case("points.knn", "P", "ragged list", REJECT), outcomes[1]).startswith("killed by signal 11")
    assert "hang" in judge(Case("points.knn", "P", "ragged list", REJECT), outcomes[2])


def test_every_public_function_has_valid_arguments(tmp_path):
    """A new public function fails here until VALID_BY_NAME / VALID can call it."""
    folder_files = files(tmp_path)
    for target, function in public_targets().items():
        valid_call(target, function, folder_files)
    stale = set(VALID) - set(public_targets())
    assert not stale, f"VALID names functions that are not public (any more): {sorted(stale)}"


# The same examples on every run by default (CI stays reproducible); MESHSMITH_FUZZ_RANDOM=1 draws new
# ones and MESHSMITH_FUZZ_EXAMPLES=40 draws more (about 1.5 s per example here).
@settings(max_examples=int(os.environ.get("MESHSMITH_FUZZ_EXAMPLES", "4")), deadline=None, database=None,
          derandomize=not os.environ.get("MESHSMITH_FUZZ_RANDOM"), phases=[Phase.explicit, Phase.generate],
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(profile=profiles())
def test_public_functions_survive_bad_arguments(profile, tmp_path_factory):
    folder_files = files(tmp_path_factory.mktemp("fuzz"))
    calls, cases, _ = build_calls(profile, folder_files)
    outcomes = run_in_children(calls)
    failures = []
    for call, case in zip(calls, cases):
        problem = judge(case, outcomes[call.id])
        if problem:
            failures.append(f"{case.target}({case.parameter} = {case.kind}): {problem}")
    functions = len({case.target for case in cases})
    summary = f"{len(calls)} calls of {functions} public functions and methods"
    if os.environ.get("MESHSMITH_FUZZ_REPORT"):  # every failure, one per line, for a survey
        with open(os.environ["MESHSMITH_FUZZ_REPORT"], "a") as report:
            report.write(f"# {summary}; {len(failures)} failed\n" + "".join(f + "\n" for f in failures))
    assert not failures, f"{len(failures)} of {summary} failed ({profile}):\n" + "\n".join(failures[:int(os.environ.get("MESHSMITH_FUZZ_SHOW", "60"))])


# ---- the cases issue 14 names, with their messages ----------------------------------------

def test_a_ragged_list_or_a_tuple_of_arrays_is_an_input_error_naming_the_argument():
    V, F = SPHERE_V, SPHERE_F
    with pytest.raises(meshsmith.InputError, match=r"^V is not an array of numbers \(list that numpy cannot"):
        meshsmith.geometry.face_areas([[0, 0, 0], [1, 1]], F)
    curvature = meshsmith.geometry.mean_curvature(V, F)  # a named tuple (H, Hn)
    with pytest.raises(meshsmith.InputError, match=r"^scalar is not an array of numbers \(MeanCurvature that numpy cannot"):
        meshsmith.render.render(V, F, size=(40, 30), scalar=curvature)
    with pytest.raises(meshsmith.InputError, match=r"^uv is not an array of numbers"):
        meshsmith.render.render(V, F, size=(40, 30), uv=[[0, 0]] * 41 + [[0]])
    with pytest.raises(meshsmith.InputError, match=r"^P is not an array of numbers"):
        meshsmith.tessellation.voronoi([[0, 0], [1, 0], [0]])


@pytest.mark.parametrize("faces, message", [
    (SPHERE_F.astype(float), "F has dtype float64: expected integer indices"),
    (SPHERE_F > 3, "F has dtype bool: expected integer indices"),
    (SPHERE_F.astype(object), "F has dtype object: expected integer indices"),
    (None, "F is None: expected an array"),
    ("faces", "F has dtype <U5: expected integer indices"),
    (SPHERE_F.ravel(), "F has shape (240,): expected (n, 3)"),
])
def test_float_bool_object_and_misshapen_faces_are_rejected(faces, message):
    with pytest.raises(meshsmith.InputError, match="^" + re.escape(message)):
        meshsmith.geometry.face_areas(SPHERE_V, faces)


def test_non_contiguous_read_only_and_nested_list_arrays_give_the_same_result_and_stay_unchanged():
    expected = meshsmith.geometry.vertex_normals(SPHERE_V, SPHERE_F)
    V = np.asfortranarray(SPHERE_V)
    F = SPHERE_F.astype(np.uint16)[::1]
    F.flags.writeable = False
    for vertices, faces in [(V, F), (SPHERE_V.tolist(), tuple(map(tuple, SPHERE_F))), (SPHERE_V.astype(">f8"), F)]:
        before = copy.deepcopy((vertices, faces))
        assert np.array_equal(meshsmith.geometry.vertex_normals(vertices, faces), expected)
        assert np.array_equal(np.asarray(vertices), np.asarray(before[0])) and not F.flags.writeable


@pytest.mark.parametrize("call, message", [
    (lambda: datasets.icosphere(2**70), "subdivisions = 1180591620717411303424: expected an integer in [0, 10]"),
    (lambda: meshsmith.points.KdTree(POINTS, leaf_size=2**40), "leaf_size = 1099511627776: expected an integer in [1, 2147483647]"),
    (lambda: meshsmith.points.knn(POINTS, 2**63), "k = 9223372036854775808: expected an integer in [1, 2147483647]"),
    (lambda: meshsmith.points.knn(POINTS, float("nan")), "k = nan: expected an integer in [1, 2147483647]"),
    (lambda: meshsmith.geometry.laplacian_eigenpairs(SPHERE_V, SPHERE_F, 2**31), "k = 2147483648: expected an integer in [1, 2147483647]"),
    (lambda: meshsmith.tessellation.refine(SQUARE, SQUARE_SEGMENTS, max_steiner_points=2**31),
     "max_steiner_points = 2147483648: expected an integer in [0, 2147483647]"),
    (lambda: meshsmith.decimation.decimate(SPHERE_V, SPHERE_F, target_faces=10, seed=-1),
     "seed = -1: expected an integer in [0, 18446744073709551615]"),
    (lambda: meshsmith.decimation.decimate(SPHERE_V, SPHERE_F, target_faces=10, candidates=2**20),
     "candidates = 1048576: expected an integer in [0, 65536]"),
    (lambda: meshsmith.render.colormap("viridis", 2**31), "steps = 2147483648: expected an integer in [2, 1048576]"),
    (lambda: meshsmith.render.render(SPHERE_V, SPHERE_F, size=(2**31, 10)), "size[0] (width) = 2147483648: expected an integer in [1, 16384]"),
    (lambda: meshsmith.curves.arc_length_parametrization(CURVE, n=2**31), "n = 2147483648: expected an integer in [2, 67108864]"),
    (lambda: meshsmith.parametrization.abf(DISK_V, DISK_F, max_iterations=np.nan), "max_iterations = nan: expected an integer in [0, 1048576]"),
])
def test_sizes_and_integer_options_are_checked_before_any_allocation(call, message):
    with pytest.raises(meshsmith.InputError, match="^" + re.escape(message) + "$"):
        call()


def test_a_progress_callback_that_returns_garbage_or_raises_is_reported_as_such():
    with pytest.raises(meshsmith.InputError, match=re.escape("the progress callback returned 'yes' (str): expected True")):
        meshsmith.points.knn(POINTS, 3, progress=lambda fraction, stage: "yes")
    with pytest.raises(meshsmith.InputError, match=re.escape("the progress callback returned 1 (int)")):
        meshsmith.decimation.decimate(SPHERE_V, SPHERE_F, target_faces=20, progress=lambda fraction, stage: 1)
    with pytest.raises(worker.CallbackFailure):  # the callback's own exception, not a replacement
        meshsmith.parametrization.abf(DISK_V, DISK_F, progress=worker.RaisingCallback())
    with pytest.raises(meshsmith.InputError, match=re.escape("progress = 5: expected a callable")):
        meshsmith.points.estimate_normals(POINTS, progress=5)
    with pytest.raises(meshsmith.InputError, match=re.escape("progress = 5: expected a callable")):
        meshsmith.parametrization.parametrize(DISK_V, DISK_F, progress=5)  # lscm never calls it
    assert meshsmith.points.knn(POINTS, 3, progress=lambda fraction, stage: np.bool_(True))[0].shape == (60, 3)
    with pytest.raises(meshsmith.Cancelled):
        meshsmith.points.knn(POINTS, 3, progress=lambda fraction, stage: np.False_)
