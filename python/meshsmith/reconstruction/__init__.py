"""Reconstruction chapter (curriculum §2.2–2.3): from scans to surfaces.

This part: depth images (§2.3), module ``depth``: pinhole back-projection, pixel-grid meshes cut
at depth discontinuities, the 2D scanline case. Bad input raises :class:`meshsmith.InputError`.
"""
from .depth import DepthMesh, DepthPoints, ScanlinePoints, depth_to_mesh, depth_to_points, scanline_to_points

__all__ = ["DepthPoints", "DepthMesh", "ScanlinePoints", "depth_to_points", "depth_to_mesh", "scanline_to_points"]
