#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/topology/manifold.h>

#include "union_find.h"

#include <algorithm>

namespace meshsmith::topology {

EdgeMatrix non_manifold_edges(const FaceRef& F) { return non_manifold_edges(edge_incidence(F)); }

EdgeMatrix non_manifold_edges(const EdgeIncidence& incidence) {
  std::vector<Eigen::Index> found;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e)
    if (incidence.side_count(e) > 2) found.push_back(e);
  EdgeMatrix result(static_cast<Eigen::Index>(found.size()), 2);
  for (size_t k = 0; k < found.size(); ++k) result.row(k) = incidence.edges.row(found[k]);
  return result;
}

VertexFans vertex_fans(const FaceRef& F, const EdgeIncidence& incidence) {
  const int n_corners = static_cast<int>(3 * F.rows());
  UnionFind corners(n_corners);
  // The corner of the face of side s that sits at vertex v (v is one end of s).
  auto corner_at = [&](int s, int v) {
    const int f = s / 3, k = s % 3;
    return F(f, k) == v ? s : 3 * f + (k + 1) % 3;
  };
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) != 2) continue;  // fans stop at boundary and non-manifold edges
    const int s1 = incidence.edge_sides[incidence.edge_offsets[e]];
    const int s2 = incidence.edge_sides[incidence.edge_offsets[e] + 1];
    for (int c = 0; c < 2; ++c) {
      const int v = incidence.edges(e, c);
      corners.unite(corner_at(s1, v), corner_at(s2, v));
    }
  }
  VertexFans fans;
  fans.corner_fan.resize(n_corners);
  fans.fan_count.assign(incidence.n_vertices, 0);
  std::vector<int> root_fan(n_corners, -1);
  for (int c = 0; c < n_corners; ++c) {
    const int root = corners.find(c);
    if (root_fan[root] < 0) {
      root_fan[root] = static_cast<int>(fans.fan_vertex.size());
      const int v = F(c / 3, c % 3);
      fans.fan_vertex.push_back(v);
      ++fans.fan_count[v];
    }
    fans.corner_fan[c] = root_fan[root];
  }
  return fans;
}

std::vector<int> non_manifold_vertices(const FaceRef& F) {
  return non_manifold_vertices(F, edge_incidence(F));
}

std::vector<int> non_manifold_vertices(const FaceRef& F, const EdgeIncidence& incidence) {
  const VertexFans fans = vertex_fans(F, incidence);
  std::vector<char> flagged(incidence.n_vertices, 0);
  for (Eigen::Index v = 0; v < incidence.n_vertices; ++v) flagged[v] = fans.fan_count[v] > 1;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e)
    if (incidence.side_count(e) > 2) flagged[incidence.edges(e, 0)] = flagged[incidence.edges(e, 1)] = 1;
  std::vector<int> result;
  for (Eigen::Index v = 0; v < incidence.n_vertices; ++v)
    if (flagged[v]) result.push_back(static_cast<int>(v));
  return result;
}

bool is_manifold(const FaceRef& F) {
  const EdgeIncidence incidence = edge_incidence(F);
  return non_manifold_edges(incidence).rows() == 0 && non_manifold_vertices(F, incidence).empty();
}

bool is_oriented(const FaceRef& F) { return is_oriented(F, edge_incidence(F)); }

bool is_oriented(const FaceRef& F, const EdgeIncidence& incidence) {
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) != 2) continue;
    const int s1 = incidence.edge_sides[incidence.edge_offsets[e]];
    const int s2 = incidence.edge_sides[incidence.edge_offsets[e] + 1];
    if (F(s1 / 3, s1 % 3) == F(s2 / 3, s2 % 3)) return false;  // both sides start at the same vertex
  }
  return true;
}

SplitMesh split_non_manifold_vertices(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  const EdgeIncidence incidence = edge_incidence(F, V.rows());
  const VertexFans fans = vertex_fans(F, incidence);
  // The first fan of each vertex keeps the vertex's index; every further fan gets a new vertex.
  std::vector<int> fan_new_vertex(fans.fan_vertex.size());
  std::vector<char> vertex_taken(V.rows(), 0);
  int next_vertex = static_cast<int>(V.rows());
  std::vector<int> origin(V.rows());
  for (int v = 0; v < static_cast<int>(V.rows()); ++v) origin[v] = v;
  for (size_t fan = 0; fan < fans.fan_vertex.size(); ++fan) {
    const int v = fans.fan_vertex[fan];
    if (!vertex_taken[v]) {
      vertex_taken[v] = 1;
      fan_new_vertex[fan] = v;
    } else {
      fan_new_vertex[fan] = next_vertex++;
      origin.push_back(v);
    }
  }
  SplitMesh result;
  result.origin = Eigen::Map<const Eigen::VectorXi>(origin.data(), static_cast<Eigen::Index>(origin.size()));
  result.V.resize(next_vertex, 3);
  for (int i = 0; i < next_vertex; ++i) result.V.row(i) = V.row(origin[i]);
  result.F.resize(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) result.F(f, k) = fan_new_vertex[fans.corner_fan[3 * f + k]];
  return result;
}

}  // namespace meshsmith::topology
