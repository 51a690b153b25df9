#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/topology/manifold.h>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <utility>

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
  const int n = static_cast<int>(incidence.n_vertices);
  const int n_corners = static_cast<int>(3 * F.rows());
  // The corners at each vertex (CSR, ascending corner ids).
  std::vector<int> corner_offsets(n + 1, 0);
  for (int c = 0; c < n_corners; ++c) ++corner_offsets[F(c / 3, c % 3) + 1];
  std::partial_sum(corner_offsets.begin(), corner_offsets.end(), corner_offsets.begin());
  std::vector<int> fill(corner_offsets.begin(), corner_offsets.end() - 1), corners_at(n_corners);
  for (int c = 0; c < n_corners; ++c) corners_at[fill[F(c / 3, c % 3)]++] = c;

  std::vector<int> local_fan(n_corners);   // fan of each corner, numbered within its vertex
  std::vector<int> fans_before(n + 1, 0);  // becomes fan_offsets
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 2048), [&](const tbb::blocked_range<int>& range) {
    std::vector<std::pair<int, int>> edge_slot;  // (two-sided edge at v, slot of a corner on it)
    std::vector<int> parent, label;
    for (int v = range.begin(); v < range.end(); ++v) {
      const int first = corner_offsets[v], degree = corner_offsets[v + 1] - first;
      edge_slot.clear();
      for (int slot = 0; slot < degree; ++slot) {
        const int c = corners_at[first + slot], f = c / 3, k = c % 3;
        // The two sides of face f at corner k: k leaves v, (k + 2) % 3 arrives at v.
        for (const int side : {3 * f + k, 3 * f + (k + 2) % 3}) {
          const int e = incidence.side_edge[side];
          if (e >= 0 && incidence.side_count(e) == 2) edge_slot.emplace_back(e, slot);
        }
      }
      std::sort(edge_slot.begin(), edge_slot.end());
      parent.resize(degree);
      std::iota(parent.begin(), parent.end(), 0);
      auto find = [&](int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
      };
      for (size_t k = 1; k < edge_slot.size(); ++k) {
        if (edge_slot[k].first != edge_slot[k - 1].first) continue;
        const int a = find(edge_slot[k].second), b = find(edge_slot[k - 1].second);
        parent[std::max(a, b)] = std::min(a, b);  // the earliest slot stays the root
      }
      label.assign(degree, -1);
      int count = 0;
      for (int slot = 0; slot < degree; ++slot) {
        const int root = find(slot);
        if (label[root] < 0) label[root] = count++;
        local_fan[corners_at[first + slot]] = label[root];
      }
      fans_before[v + 1] = count;
    }
  });
  VertexFans fans;
  std::partial_sum(fans_before.begin(), fans_before.end(), fans_before.begin());
  fans.fan_offsets = std::move(fans_before);
  fans.corner_fan.resize(n_corners);
  tbb::parallel_for(tbb::blocked_range<int>(0, n_corners, 8192), [&](const tbb::blocked_range<int>& range) {
    for (int c = range.begin(); c < range.end(); ++c)
      fans.corner_fan[c] = fans.fan_offsets[F(c / 3, c % 3)] + local_fan[c];
  });
  return fans;
}

std::vector<int> non_manifold_vertices(const FaceRef& F) {
  return non_manifold_vertices(F, edge_incidence(F));
}

std::vector<int> non_manifold_vertices(const FaceRef& F, const EdgeIncidence& incidence) {
  const VertexFans fans = vertex_fans(F, incidence);
  std::vector<char> flagged(incidence.n_vertices, 0);
  for (Eigen::Index v = 0; v < incidence.n_vertices; ++v) flagged[v] = fans.fan_count(v) > 1;
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
  const int n = static_cast<int>(V.rows());
  std::vector<int> origin(n), fan_new_vertex(fans.fan_offsets[n]);
  std::iota(origin.begin(), origin.end(), 0);
  for (int v = 0; v < n; ++v) {
    for (int fan = fans.fan_offsets[v]; fan < fans.fan_offsets[v + 1]; ++fan) {
      if (fan == fans.fan_offsets[v]) {
        fan_new_vertex[fan] = v;
      } else {
        fan_new_vertex[fan] = static_cast<int>(origin.size());
        origin.push_back(v);
      }
    }
  }
  const int next_vertex = static_cast<int>(origin.size());
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
