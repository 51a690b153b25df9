"""Reconstruction chapter (curriculum §2.2–2.3, §3.1): from scans to surfaces — signed distance fields,
iso-surfaces of sampled fields (marching cubes), screened Poisson reconstruction from oriented samples,
graph-cut reconstruction from unoriented samples (an s–t minimum cut of a voxel grid, §3.2), and depth
images (pinhole back-projection, pixel-grid meshes cut at depth discontinuities, the 2D scanline case).

Positions are float64 (n, 3), faces come back int64 (m, 3), oriented outward. Bad input raises
:class:`meshsmith.InputError`.

Modules, one per algorithm family: ``signed_distance``, ``marching_cubes``, ``poisson``, ``graph_cut``, ``depth``.
"""
from .depth import DepthMesh, DepthPoints, ScanlinePoints, depth_to_mesh, depth_to_points, scanline_to_points
from .graph_cut import GraphCutMesh, MinimumCut, graph_cut, max_flow
from .marching_cubes import ContourMesh, marching_cubes, marching_cubes_sparse
from .poisson import PoissonMesh, TrimmedMesh, poisson, trim_by_density
from .signed_distance import MeshSignedDistance, SampleGrid, mesh_sdf, sample_grid, tangent_plane_sdf, winding_number

__all__ = ["ContourMesh", "marching_cubes", "marching_cubes_sparse",
           "MeshSignedDistance", "SampleGrid", "mesh_sdf", "sample_grid", "tangent_plane_sdf", "winding_number",
           "PoissonMesh", "TrimmedMesh", "poisson", "trim_by_density",
           "GraphCutMesh", "MinimumCut", "graph_cut", "max_flow",
           "DepthPoints", "DepthMesh", "ScanlinePoints", "depth_to_points", "depth_to_mesh", "scanline_to_points"]
