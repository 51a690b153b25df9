#pragma once
/// \file normals.h
/// Face and vertex normals of a triangle mesh (§1.2.4, "per triangle and per vertex (weighted
/// average in angle/area/length)"). Results agree with libigl's per_face_normals and
/// per_vertex_normals to round-off on meshes without degenerate faces.
#include <meshsmith/core/types.h>

namespace meshsmith::geometry {

/// How the normals of the faces around a vertex are averaged.
enum class NormalWeighting {
  uniform,  ///< every incident face counts once (libigl PER_VERTEX_NORMALS_WEIGHTING_TYPE_UNIFORM)
  area,     ///< weighted by face area (libigl ..._AREA)
  angle,    ///< weighted by the interior angle at the vertex (libigl ..._ANGLE; Thürmer & Wüthrich 1998)
};

/// Unit normals of the faces, (p1 − p0) × (p2 − p0) normalised (counter-clockwise faces point
/// towards the viewer).
/// V: #V×3 positions, F: #F×3 triangles. Returns #F×3.
/// A degenerate face (twice its area ≤ 8·ε·(longest edge)², e.g. a repeated vertex or three
/// collinear points) gets the zero vector, never NaN.
/// \pre none beyond the shapes; \throw InputError if V or F is empty, V holds NaN/Inf or an
/// index of F is outside [0, #V).
VertexMatrix face_normals(const VertexRef& V, const FaceRef& F);

/// Unit vertex normals: the weighted sum of the unit normals of the incident faces, normalised.
/// V: #V×3, F: #F×3. Returns #V×3. Degenerate faces contribute nothing; a vertex used by no
/// face (or whose incident normals cancel exactly) gets the zero vector, never NaN.
/// \throw InputError as face_normals.
VertexMatrix vertex_normals(const VertexRef& V, const FaceRef& F,
                            NormalWeighting weighting = NormalWeighting::angle);

}  // namespace meshsmith::geometry
