"""Cross fields (4-RoSy) on triangle meshes and their singularities (§5.2.2 step 1); C++
src/quadrangulation/cross_field.cpp.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

import numpy as np

from .. import _arguments
from .._core import quadrangulation as _core
from .._results import Unpackable
from .._typing import ArrayLike, FloatArray, IndexArray, ProgressCallback
from .._core import InputError
from ..repair.unreferenced import on_referenced_vertices

__all__ = ["CrossField", "Singularities", "cross_field", "field_angles", "singularities", "FieldLike"]


@dataclass(frozen=True)
class CrossField(Unpackable):
    """A cross field (:func:`cross_field`); unpacks as ``theta, directions``.

    theta: (m,) float64 angle of each face's cross against its reference edge F[f,0] → F[f,1],
    in [0, π/2) (the cross is the four directions theta + k·π/2); directions: (m, 3) float64 unit
    vectors at angle theta in the face planes; edges: (e, 2) int64 unique edges (i < j);
    edge_faces: (e, 2) int64 the faces on each side, the first one's side running i → j (−1 on a
    boundary); connection: (e,) float64 parallel-transport angle κ from the first face's frame
    to the second's; period_jumps: (e,) int64 p with θ_g − θ_f − κ − p·π/2 in [−π/4, π/4);
    constrained_faces: faces held by a hard constraint.
    """

    unpacks = ("theta", "directions")
    theta: FloatArray
    directions: FloatArray
    edges: IndexArray
    edge_faces: IndexArray
    connection: FloatArray
    period_jumps: IndexArray
    constrained_faces: int


@dataclass(frozen=True)
class Singularities(Unpackable):
    """Singular vertices of a cross field (:func:`singularities`); unpacks as ``vertices, indices``.

    vertices: (k,) int64 input vertex indices, increasing; indices: (k,) int64 their indices in
    quarter turns (+1 at a valence-3 corner of a quad mesh, −1 at a valence-5 vertex).
    """

    vertices: IndexArray
    indices: IndexArray


#: A cross field argument: a :class:`CrossField`, (m,) angles or (m, 3) direction vectors.
FieldLike = Union[CrossField, ArrayLike]


@_arguments.real_options
def cross_field(V: ArrayLike, F: ArrayLike, *, align: str = "curvature", constraints: object = None,
                sharp_angle: float | None = None, curvature_weight: float = 1e-3,
                progress: ProgressCallback = None) -> CrossField:
    """A smooth cross field on a triangle mesh (§5.2.2 step 1; Bommes et al. 2009, in the
    power-4 representation of Knöppel et al. 2013).

    The power-4 complex numbers z_f = exp(4iθ_f) minimize Σ_edges w |z_g − exp(4iκ) z_f|²
    (κ the parallel transport between the two faces' frames) — a sparse Hermitian system solved
    by CHOLMOD, or its smallest eigenvector when nothing constrains the field.

    V: (n, 3) float array, F: (m, 3) integer array.
    align: ``"curvature"`` — principal curvature directions where the surface is anisotropic
    (a soft term of weight ``curvature_weight`` against the smoothness term; the default 1e-3 keeps
    noisy principal directions from adding singularities: at 1e-2 bumpy-cube had 104 instead of
    56) and the boundary (hard); where no face is
    anisotropic (a sphere) the smoothest field; ``"boundary"`` — the boundary (hard), smooth
    inside; ``"smooth"`` — the smoothest field, boundary ignored.
    constraints: None or a pair ``(faces, directions)``: (k,) face indices and (k, 3) vectors,
    one direction of each listed face's cross (projected into the face plane; hard).
    sharp_angle: None, or degrees: interior edges whose dihedral angle exceeds it are features
    and their two faces follow the edge (hard).
    Returns a :class:`CrossField` (unpacks as ``theta, directions``).
    Raises InputError for non-manifold, unoriented or multi-component input, zero-area or
    repeated-index faces (clean it first: :func:`meshsmith.repair.clean`, ``meshsmith clean``),
    a constraint face out of range, a NaN or zero constraint direction, or an unknown align.
    """
    mesh = on_referenced_vertices(V, F)
    faces: object = None
    directions: object = None
    if constraints is not None:
        if not isinstance(constraints, (tuple, list)) or len(constraints) != 2:
            raise InputError("cross_field: constraints must be a pair (faces, directions)")
        faces, directions = constraints
    angle = 0.0
    if sharp_angle is not None:
        angle = float(sharp_angle)
        if not 0 < angle < 180:
            raise InputError(f"cross_field: sharp_angle must be in (0, 180) degrees, got {sharp_angle}")
    out = _core.cross_field(mesh.V, mesh.F, align=align, sharp_angle=angle, constraint_faces=faces,
                            constraint_directions=directions, curvature_weight=curvature_weight,
                            progress=progress)
    edges = mesh.vertex_map[out["edges"]] if mesh.removed else out["edges"]
    return CrossField(theta=out["theta"], directions=out["directions"], edges=edges,
                      edge_faces=out["edge_faces"], connection=out["connection"],
                      period_jumps=out["period_jumps"], constrained_faces=int(out["constrained_faces"]))


def field_angles(V: ArrayLike, F: ArrayLike, field: FieldLike) -> FloatArray:
    """The per-face angles θ (m,) of a cross field given as a :class:`CrossField`, (m,) angles
    (returned as float64) or (m, 3) direction vectors (measured in each face's frame: against
    the reference edge F[f,0] → F[f,1], counter-clockwise about the face normal).
    Raises InputError for a field of the wrong size, with NaN/Inf, or a direction normal to its face."""
    if isinstance(field, CrossField):
        field = field.theta
    if _arguments.numbers(field, "field").ndim == 1:
        theta = _arguments.finite(_arguments.real_array(field, "field"), "field")
        n_faces = len(_arguments.index_array(F, "F", 3))
        if len(theta) != n_faces:
            raise InputError(f"field has {len(theta)} angles but the mesh has {n_faces} faces")
        return theta
    mesh = on_referenced_vertices(V, F)
    return _core.field_angles(mesh.V, mesh.F, _arguments.real_array(field, "field", 3))


def singularities(V: ArrayLike, F: ArrayLike, field: FieldLike) -> Singularities:
    """The singular vertices of a cross field and their indices in quarter turns (§5.2.2).

    The index of a vertex is its angle defect plus the field's rotation against parallel
    transport around it, in quarter turns; on a closed mesh the indices sum to 4χ exactly
    (Poincaré–Hopf: +8 on a sphere, 0 on a torus), and on a mesh with boundary too when the
    field follows the boundary. field: a :class:`CrossField`, (m,) angles or (m, 3) directions.
    Returns a :class:`Singularities` (unpacks as ``vertices, indices``).
    Raises InputError as :func:`cross_field` and for a field with NaN or the wrong size.
    """
    theta = field_angles(V, F, field)
    mesh = on_referenced_vertices(V, F)
    vertices, indices = _core.singularities(mesh.V, mesh.F, theta)
    if mesh.removed:
        vertices = mesh.vertex_map[vertices]
    return Singularities(vertices=np.asarray(vertices, dtype=np.int64), indices=np.asarray(indices, dtype=np.int64))
