"""Tessellation chapter (curriculum §2.1): Delaunay triangulations and Voronoi diagrams, Delaunay
refinement, contouring by Voronoi filtering (crust, medial axis, local feature size), 3D surface
reconstruction by the Cocone crust, and power diagrams.

Points are float64 arrays of shape (n, 2) (or (n, 3) where 3D is supported); triangles come back
as (m, 3) int64 arrays, counter-clockwise. Triangulations use CGAL's exact predicates, so
collinear and cocircular input is handled consistently; constructed points (segment
intersections, Steiner points, circumcentres, cell corners) are float64.
Bad input raises :class:`meshsmith.InputError`.

Modules, one per algorithm family: ``delaunay``, ``contouring``.
"""
from .contouring import (
    MedialAxis,
    PowerDiagram,
    crust,
    crust_3d,
    is_r_sample,
    local_feature_size,
    medial_axis,
    power_diagram,
    sampling_ratio,
)
from .delaunay import (
    FlippedTriangulation,
    RefinedMesh,
    Triangulation,
    VoronoiDiagram,
    constrained_delaunay,
    default_bounds,
    delaunay,
    flip_to_delaunay,
    refine,
    triangle_angles,
    voronoi,
)

__all__ = ["delaunay", "constrained_delaunay", "voronoi", "VoronoiDiagram", "flip_to_delaunay", "refine",
           "PowerDiagram", "power_diagram", "crust", "medial_axis", "local_feature_size", "sampling_ratio",
           "is_r_sample", "crust_3d", "default_bounds", "triangle_angles", "Triangulation", "FlippedTriangulation",
           "RefinedMesh", "MedialAxis"]
