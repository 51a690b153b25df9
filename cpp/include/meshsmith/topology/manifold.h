#pragma once
/// \file manifold.h
/// Manifoldness and orientation of a triangle mesh, and the repair that splits a non-manifold
/// mesh into a manifold one without moving any point (§2: the manifold conditions; §2.4 repair).
///
/// Definitions used throughout meshsmith:
/// - A non-manifold EDGE has more than two incident face sides.
/// - The FANS of a vertex v are the groups of faces around v that are connected through edges
///   at v that have exactly two incident faces. A vertex is non-manifold when it has more than
///   one fan (a pinch, like the shared corner of two cubes touching at a point) or is an end of
///   a non-manifold edge (such a vertex always has more than one fan anyway). A manifold vertex's
///   faces form one disk (interior) or one half-disk (boundary). Unreferenced vertices have no
///   fan and are not counted as non-manifold (unlike `igl::is_vertex_manifold`).
/// - A mesh is manifold when it has neither non-manifold edges nor non-manifold vertices.
/// - A mesh is oriented when every edge with exactly two incident faces is used once in each
///   direction (non-manifold edges are not considered).
#include <meshsmith/core/types.h>
#include <meshsmith/topology/edge_incidence.h>

#include <vector>

namespace meshsmith::topology {

/// #N×2 edges (i < j, lexicographic) with more than two incident faces.
/// \throw InputError as checked_vertex_count.
EdgeMatrix non_manifold_edges(const FaceRef& F);
EdgeMatrix non_manifold_edges(const EdgeIncidence& incidence);

/// Fans around the vertices (see the definitions above).
struct VertexFans {
  std::vector<int> corner_fan;   ///< 3#F: fan of each corner (3f + k), in [0, n_fans)
  std::vector<int> fan_offsets;  ///< #V+1: the fans of vertex v are fan_offsets[v] .. fan_offsets[v+1]-1,
                                 ///< in the order of their first corner
  int fan_count(Eigen::Index v) const { return fan_offsets[v + 1] - fan_offsets[v]; }
};

/// Fans of every vertex of F: the corners at each vertex are joined through its two-sided edges
/// by a small union-find per vertex, vertices in parallel. O(#F log(max degree)).
/// \pre incidence == edge_incidence(F, n) for some n.
VertexFans vertex_fans(const FaceRef& F, const EdgeIncidence& incidence);

/// Non-manifold vertices (ascending), as defined above.
/// \throw InputError as checked_vertex_count.
std::vector<int> non_manifold_vertices(const FaceRef& F);
std::vector<int> non_manifold_vertices(const FaceRef& F, const EdgeIncidence& incidence);

/// True when F has no non-manifold edge and no non-manifold vertex.
/// \throw InputError as checked_vertex_count.
bool is_manifold(const FaceRef& F);

/// True when every edge with two incident faces is traversed once in each direction.
/// \throw InputError as checked_vertex_count.
bool is_oriented(const FaceRef& F);
bool is_oriented(const FaceRef& F, const EdgeIncidence& incidence);

/// Result of split_non_manifold_vertices.
struct SplitMesh {
  VertexMatrix V;             ///< #V2×3 positions, V.row(i) == input V.row(origin[i])
  FaceMatrix F;               ///< #F×3 faces, same order as the input faces
  Eigen::VectorXi origin;     ///< #V2: the input vertex each output vertex copies
};

/// Makes a mesh manifold without moving geometry: every vertex gets one copy per fan, so each
/// pinch vertex is separated, and because fans never continue across a non-manifold edge, the
/// faces around a non-manifold edge are detached from each other too (each ends up sharing the
/// edge with at most one other face: the one it was already connected to around both ends). The
/// result is_manifold. Vertex i < #V keeps its index (its first fan keeps it); extra copies are
/// appended in the order of the vertex they copy. Unreferenced vertices are kept.
/// V: #V×3 positions, F: #F×3 triangles.
/// \pre validate_mesh(V, F) passes (called here).
/// \throw InputError if it does not.
SplitMesh split_non_manifold_vertices(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::topology
