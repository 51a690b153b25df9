#pragma once
/// \file orient.h
/// Consistent orientation of a triangle mesh, closed components outward (§2.4, mesh repair:
/// the orientation step of cleaning).
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::repair {

/// Result of orient_faces.
struct OrientedFaces {
  FaceMatrix F;                ///< #F×3: the input faces, those in `flipped` with two corners swapped
  std::vector<int> flipped;    ///< faces whose orientation was reversed, ascending
  int components = 0;          ///< edge-connected components (through edges with exactly two faces)
  int closed_components = 0;   ///< components every edge of which has exactly two faces
  /// Components that admit no consistent orientation (a Möbius strip, a Klein bottle): each keeps
  /// the orientation of a breadth-first spanning tree of its faces, so some of its edges remain
  /// traversed twice in the same direction.
  int non_orientable_components = 0;
};

/// Orients every component consistently: faces are joined across the edges with exactly two
/// incident faces (boundary and non-manifold edges join nothing), and a breadth-first walk from
/// each component's lowest-numbered face flips each face to agree with the face it was reached
/// from. Then a closed orientable component whose signed volume is negative is reversed as a
/// whole (it comes out oriented outward: counter-clockwise seen from outside), and an open or
/// non-orientable component (or a closed one of zero volume) is reversed when that flips fewer
/// of its faces, so an already consistent mesh is returned unchanged.
/// V: #V×3 positions, F: #F×3 triangles. Faces with a repeated vertex take part through their
/// proper edges. O(#F) after the edge incidence.
/// \pre validate_mesh(V, F) passes (called here); non-manifold edges are best split first
///      (topology::split_non_manifold_vertices), since the faces around them are not joined.
/// \throw InputError if validate_mesh fails.
OrientedFaces orient_faces(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::repair
