#include <meshsmith/topology/boundary.h>

#include <algorithm>
#include <numeric>

namespace meshsmith::topology {

Eigen::Index count_boundary_edges(const EdgeIncidence& incidence) {
  Eigen::Index count = 0;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) count += incidence.side_count(e) == 1;
  return count;
}

std::vector<std::vector<int>> boundary_loops(const FaceRef& F) {
  return boundary_loops(F, edge_incidence(F));
}

std::vector<std::vector<int>> boundary_loops(const FaceRef& F, const EdgeIncidence& incidence) {
  // The boundary as a graph: each boundary edge is stored as its one side, directed like the face.
  const int n = static_cast<int>(incidence.n_vertices);
  std::vector<int> boundary_sides;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e)
    if (incidence.side_count(e) == 1) boundary_sides.push_back(incidence.edge_sides[incidence.edge_offsets[e]]);
  auto side_start = [&](int s) { return F(s / 3, s % 3); };
  auto side_end = [&](int s) { return F(s / 3, (s % 3 + 1) % 3); };

  // Boundary edges at each vertex (CSR), in the order of boundary_sides.
  std::vector<int> offsets(n + 1, 0);
  for (int s : boundary_sides) ++offsets[side_start(s) + 1], ++offsets[side_end(s) + 1];
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  std::vector<int> fill(offsets.begin(), offsets.end() - 1), incident(offsets[n]);
  for (int b = 0; b < static_cast<int>(boundary_sides.size()); ++b) {
    incident[fill[side_start(boundary_sides[b])]++] = b;
    incident[fill[side_end(boundary_sides[b])]++] = b;
  }

  std::vector<char> used(boundary_sides.size(), 0);
  // Next unused boundary edge at v: one leaving v along the face orientation if there is one,
  // otherwise any (only on non-oriented meshes). -1 if none is left.
  auto next_edge = [&](int v) {
    int fallback = -1;
    for (int k = offsets[v]; k < offsets[v + 1]; ++k) {
      const int b = incident[k];
      if (used[b]) continue;
      if (side_start(boundary_sides[b]) == v) return b;
      if (fallback < 0) fallback = b;
    }
    return fallback;
  };

  std::vector<std::vector<int>> loops;
  for (int start = 0; start < n; ++start) {
    for (int b = next_edge(start); b >= 0; b = next_edge(start)) {
      std::vector<int> loop{start};
      int current = start;
      while (b >= 0) {
        used[b] = 1;
        const int s = boundary_sides[b];
        current = side_start(s) == current ? side_end(s) : side_start(s);
        if (current == start) break;
        loop.push_back(current);
        b = next_edge(current);
      }
      loops.push_back(std::move(loop));
    }
  }
  std::stable_sort(loops.begin(), loops.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return loops;
}

}  // namespace meshsmith::topology
