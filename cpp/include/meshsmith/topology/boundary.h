#pragma once
/// \file boundary.h
/// Boundary loops of a triangle mesh (§2, mesh definitions): the closed chains of edges that have
/// exactly one incident face.
#include <meshsmith/topology/edge_incidence.h>

#include <vector>

namespace meshsmith::topology {

/// Every boundary loop of F as an ordered list of vertex indices (the first vertex is not
/// repeated at the end). Ordering follows libigl's `igl::boundary_loop`: a loop starts at its
/// smallest vertex index and walks along the boundary in the direction of the faces' own sides
/// (for a counter-clockwise, outward-oriented mesh the hole is walked clockwise seen from outside).
/// Loops are sorted longest first, ties by their first vertex.
/// F: #F×3 triangles. A vertex where several loops touch (a pinched boundary) appears in each.
/// On a non-oriented mesh a loop follows the orientation where it can and any boundary edge
/// where it cannot; a chain that cannot close (only around non-manifold edges) is returned open.
/// \throw InputError as checked_vertex_count.
std::vector<std::vector<int>> boundary_loops(const FaceRef& F);

/// Same, reusing an EdgeIncidence computed from the same F.
std::vector<std::vector<int>> boundary_loops(const FaceRef& F, const EdgeIncidence& incidence);

/// Number of edges with exactly one incident face side.
Eigen::Index count_boundary_edges(const EdgeIncidence& incidence);

}  // namespace meshsmith::topology
