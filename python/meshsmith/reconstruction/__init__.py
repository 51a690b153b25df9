"""Reconstruction chapter (curriculum §2.2, §3.1): signed distance fields, iso-surfaces of sampled
fields (marching cubes), screened Poisson reconstruction from oriented samples.

Positions are float64 (n, 3), faces come back int64 (m, 3), oriented outward. Bad input raises
:class:`meshsmith.InputError`.

Modules, one per algorithm family: ``signed_distance``, ``marching_cubes``, ``poisson``.
"""
from .marching_cubes import ContourMesh, marching_cubes, marching_cubes_sparse
from .poisson import PoissonMesh, TrimmedMesh, poisson, trim_by_density
from .signed_distance import MeshSignedDistance, SampleGrid, mesh_sdf, sample_grid, tangent_plane_sdf, winding_number

__all__ = ["ContourMesh", "marching_cubes", "marching_cubes_sparse",
           "MeshSignedDistance", "SampleGrid", "mesh_sdf", "sample_grid", "tangent_plane_sdf", "winding_number",
           "PoissonMesh", "TrimmedMesh", "poisson", "trim_by_density"]
