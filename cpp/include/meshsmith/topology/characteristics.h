#pragma once
/// \file characteristics.h
/// Topological invariants (§2: Euler's formula V − E + F = 2 − 2g − b, b boundary loops) and the
/// one-call topological summary of a mesh (Python's `meshsmith.topology.info` adds the geometric
/// measures to it, so that topology does not depend on the geometry chapter).
#include <meshsmith/core/types.h>
#include <meshsmith/topology/edge_incidence.h>

#include <optional>
#include <vector>

namespace meshsmith::topology {

/// χ = V − E + F with V the number of vertices some face uses, E the unique edges, F the faces.
/// F: #F×3 triangles.
/// \throw InputError as checked_vertex_count.
long long euler_characteristic(const FaceRef& F);
long long euler_characteristic(const FaceRef& F, const EdgeIncidence& incidence);

/// Genus of each connected component (numbered as connected_components), from
/// χ_c = 2 − 2 g_c − b_c with b_c the component's boundary loops.
/// F: #F×3 triangles.
/// \pre F is manifold and every component is orientable.
/// \throw InputError naming the first non-manifold edge or vertex, or the first
///        non-orientable component (a Möbius strip or Klein bottle has no orientable genus).
std::vector<int> genus_per_component(const FaceRef& F);

/// The topological part of what `meshsmith info` reports, computed with one EdgeIncidence.
struct MeshInfo {
  Eigen::Index n_vertices = 0, n_faces = 0, n_edges = 0;
  int n_components = 0;
  Eigen::Index n_boundary_loops = 0, n_boundary_edges = 0;
  long long euler_characteristic = 0;
  std::optional<int> genus;  ///< sum over components; empty if non-manifold or non-orientable
  bool is_manifold = false, is_oriented = false;
  Eigen::Index n_non_manifold_edges = 0, n_non_manifold_vertices = 0, n_unreferenced_vertices = 0;
};

/// Topological summary of (V, F). V: #V×3 positions, F: #F×3 triangles.
/// \pre validate_mesh(V, F) passes (called here).
/// \throw InputError if it does not.
MeshInfo mesh_info(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::topology
