"""Reconstruction chapter (curriculum §2.2, §3.1): iso-surfaces of sampled fields (marching cubes).

Positions are float64 (n, 3), faces come back int64 (m, 3), oriented outward. Bad input raises
:class:`meshsmith.InputError`.

Modules, one per algorithm family: ``marching_cubes``.
"""
from .marching_cubes import ContourMesh, marching_cubes, marching_cubes_sparse

__all__ = ["ContourMesh", "marching_cubes", "marching_cubes_sparse"]
