"""Geometry chapter (§1.2, §3.0.2): measures and discrete differential geometry of triangle meshes.

Areas and volume; face and vertex normals; uniform, cotangent and mean-value Laplacians; mass
matrices; Gaussian, mean and principal curvatures; Laplacian eigenpairs; per-triangle distortion of a parametrization; exact point-to-surface
distances, Hausdorff and mean surface distance. (Discrete curves are
in :mod:`meshsmith.curves`.)

Conventions follow libigl so results compare one to one: the Laplacians are
``L_ii = -sum_j L_ij`` (the cotangent Laplacian is negative semi-definite), sparse matrices come
back as ``scipy.sparse.csc_matrix`` with sorted indices, and curvature is positive where the
surface bends away from its outward normal (a sphere of radius r has H = 1/r, K = 1/r**2).

Every function validates its input in the C++ core and raises :class:`meshsmith.InputError`
(a ``ValueError``) for a wrong shape or dtype, NaN/Inf coordinates, an index outside
``[0, n)``, an empty array or an unknown option. Degenerate (zero-area) triangles never
produce NaN: their normals are zero and their cotangents are set to zero, so they contribute
nothing.

Modules, one per algorithm family: ``measures``, ``differential``, ``metrics``.
"""
from .differential import (
    Eigenpairs,
    MeanCurvature,
    PrincipalCurvatures,
    cotan_laplacian,
    face_normals,
    gaussian_curvature,
    laplacian_eigenpairs,
    mass_matrix,
    mean_curvature,
    mean_value_laplacian,
    principal_curvatures,
    uniform_laplacian,
    vertex_areas,
    vertex_normals,
)
from .measures import face_areas, surface_area, volume
from .metrics import (
    ClosestPoints,
    SurfaceDistance,
    SurfaceDistances,
    TriangleDistortion,
    hausdorff_distance,
    mean_surface_distance,
    triangle_distortion,
)

__all__ = ["face_areas", "surface_area", "volume", "face_normals", "vertex_normals", "cotan_laplacian",
           "uniform_laplacian", "mean_value_laplacian", "mass_matrix", "vertex_areas", "gaussian_curvature",
           "mean_curvature", "principal_curvatures", "laplacian_eigenpairs", "TriangleDistortion",
           "triangle_distortion", "SurfaceDistance", "hausdorff_distance", "mean_surface_distance",
           "MeanCurvature", "PrincipalCurvatures", "Eigenpairs", "ClosestPoints", "SurfaceDistances"]
