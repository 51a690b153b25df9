#pragma once
/// \file degenerate_triangles.h
/// Removal of needles and caps (§2.4, mesh repair: almost-degenerate triangles), on the project's
/// halfedge mesh (core/mesh.h), by edge collapses and flips that keep the topology of the rest.
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::repair {

struct NeedleCapOptions {
  /// A needle: its longest edge over its shortest exceeds this (> 1). Removed by collapsing the
  /// shortest edge onto one of its vertices.
  double needle_ratio = 10.0;
  /// A cap: an angle above this many degrees (in (90, 180)) and no needle. Removed by flipping the
  /// edge opposite that angle.
  double cap_angle = 160.0;
  int max_passes = 10;         ///< passes over every face (each pass can expose new needles or caps)
};

struct NeedleCapResult {
  VertexMatrix V;              ///< the kept input vertices, unmoved
  FaceMatrix F;
  std::vector<int> vertex_map; ///< the input vertex of each output vertex (V == V_in[vertex_map])
  std::vector<int> face_map;   ///< the input face each output face was (its corners change under a collapse or flip)
  int collapses = 0;           ///< needles removed: edges collapsed (each removes one vertex and two faces, one on a boundary)
  int flips = 0;               ///< caps removed: edges flipped
  int remaining_needles = 0;   ///< needles no admissible collapse removed (the link condition, a fold, a boundary)
  int remaining_caps = 0;      ///< caps whose flip was not admissible (a boundary edge, an existing edge, a fold)
};

/// Collapses needles and flips caps until none is left or `max_passes` passes. A collapse is a
/// halfedge collapse (the removed vertex's faces move onto the kept vertex, whose position does
/// not change): taken only when OpenMesh's link condition holds (is_collapse_ok), no face around
/// the removed vertex turns its normal by more than 90°, and a boundary vertex is never pulled off
/// the boundary; a flip only when the edge is inside, is_flip_ok holds, the two new faces keep the
/// side of the old ones (their normals within 90° of the old faces' sum) and the largest angle
/// decreases. So the topology (genus, boundary loops, components) does not change.
/// V: #V×3, F: #F×3, manifold and oriented (repair::clean gives such a mesh); faces of zero area
/// are both needles and caps when they have a zero edge, caps when they have three distinct
/// collinear corners.
/// \throw InputError if to_trimesh rejects the mesh (non-manifold, a repeated vertex) or an option
///        is out of range.
NeedleCapResult remove_needles_and_caps(const VertexRef& V, const FaceRef& F, const NeedleCapOptions& options = {});

}  // namespace meshsmith::repair
