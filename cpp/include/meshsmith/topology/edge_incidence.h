#pragma once
/// \file edge_incidence.h
/// Unique undirected edges of a triangle mesh and which face sides lie on each (§2, M = (V, E, F):
/// the combinatorics every other topology query is built on). Computed in O(#F) by bucketing the
/// sides by their smaller vertex, so it is cheap enough to rebuild, and it can be passed to the
/// overloads in boundary.h, manifold.h and characteristics.h to be computed only once (those
/// overloads require, without checking, that the EdgeIncidence was computed from the same F).
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::topology {

/// Side k of face f is the directed edge F(f, k) → F(f, (k+1) % 3); its id is 3f + k. The
/// corner k of face f (id 3f + k) sits at vertex F(f, k).
struct EdgeIncidence {
  Eigen::Index n_vertices = 0;    ///< #V the faces index into (unreferenced vertices included)
  EdgeMatrix edges;               ///< #E×2 unique undirected edges (i, j), i < j, sorted lexicographically
  std::vector<int> side_edge;     ///< 3#F: the edge of each side; -1 for a side joining a vertex to itself
  std::vector<int> edge_offsets;  ///< #E+1: the sides of edge e are edge_sides[edge_offsets[e] .. edge_offsets[e+1])
  std::vector<int> edge_sides;    ///< side ids grouped by edge, ascending within an edge

  Eigen::Index n_edges() const { return edges.rows(); }
  /// Number of face sides on edge e: 1 on the boundary, 2 inside a manifold, > 2 non-manifold.
  int side_count(Eigen::Index e) const { return edge_offsets[e + 1] - edge_offsets[e]; }
};

/// Checks F for the F-only topology queries and returns the number of vertices it implies.
/// F: #F×3 triangles. `n_vertices` < 0 means "max index + 1"; otherwise indices must be below it.
/// \throw InputError if F is empty, has a negative index, or an index >= n_vertices (the
///        message names the face); if n_vertices is inferred and the largest index is at least
///        3#F + 2^20 (mostly unreferenced vertices: pass the count); if 3#F or n_vertices
///        overflows a 32-bit index.
Eigen::Index checked_vertex_count(const FaceRef& F, Eigen::Index n_vertices = -1);

/// Edge incidence of F (see EdgeIncidence). F: #F×3 triangles. Sides joining a vertex to itself
/// (faces with a repeated index) belong to no edge.
/// \pre as checked_vertex_count(F, n_vertices) (called here).
/// \throw InputError as checked_vertex_count.
EdgeIncidence edge_incidence(const FaceRef& F, Eigen::Index n_vertices = -1);

/// #E×2 unique undirected edges of F, each as (i, j) with i < j, in lexicographic order (the same
/// set as libigl's `igl::edges`).
/// \throw InputError as checked_vertex_count.
EdgeMatrix edges(const FaceRef& F);

}  // namespace meshsmith::topology
