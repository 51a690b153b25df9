#pragma once
/// \file measures.h
/// Areas and enclosed volume of a triangle mesh (§1.2: the surface area integral made discrete, the
/// triangle area |(b − a) × (c − a)| / 2; the divergence theorem for the volume).
#include <meshsmith/core/types.h>

namespace meshsmith::geometry {

/// Area of each triangle, |(v1 − v0) × (v2 − v0)| / 2 (libigl's `doublearea` / 2).
/// V: #V×3 positions, F: #F×3 triangles. Returns #F areas (0 for degenerate faces). Each face
/// is computed on its edge vectors scaled by a power of two (core/normalization.h), so
/// coordinates from 1e-300 to 1e308 neither overflow nor underflow inside the cross product.
/// \pre validate_mesh(V, F) passes (called here).
/// \throw InputError if it does not, or if an area exceeds the double range (naming the face).
Eigen::VectorXd face_areas(const VertexRef& V, const FaceRef& F);

/// Total area Σ face_areas(V, F), summed in a fixed order (same result for any thread count).
/// \throw InputError as face_areas, or if the sum exceeds the double range.
double surface_area(const VertexRef& V, const FaceRef& F);

/// Signed volume enclosed by the surface, by the divergence theorem:
/// Σ_f v0 · (v1 × v2) / 6 over the faces (signed tetrahedra to the origin). Positive for a closed
/// surface whose faces are counter-clockwise seen from outside (outward normals); for an open
/// or inconsistently oriented mesh the value depends on the origin and has no meaning as a volume.
/// V: #V×3 positions, F: #F×3 triangles. Summed on normalized coordinates, then scaled back.
/// \throw InputError as validate_mesh, or if the volume exceeds the double range.
double volume(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::geometry
