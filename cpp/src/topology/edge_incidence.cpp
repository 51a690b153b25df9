#include <meshsmith/core/errors.h>
#include <meshsmith/topology/edge_incidence.h>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

namespace meshsmith::topology {

Eigen::Index checked_vertex_count(const FaceRef& F, Eigen::Index n_vertices) {
  if (F.rows() == 0) throw InputError("F is empty: expected at least one triangle");
  if (F.rows() > std::numeric_limits<int>::max() / 3) {
    std::ostringstream message;
    message << "F has " << F.rows() << " faces: at most " << std::numeric_limits<int>::max() / 3
            << " are supported";
    throw InputError(message.str());
  }
  if (n_vertices > std::numeric_limits<int>::max()) {
    std::ostringstream message;
    message << "n_vertices = " << n_vertices << " exceeds the 32-bit index range";
    throw InputError(message.str());
  }
  int largest = -1;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int index = F(f, c);
      if (index < 0 || (n_vertices >= 0 && index >= n_vertices)) {
        std::ostringstream message;
        message << "F[" << f << "] = (" << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2)
                << ") indexes vertex " << index;
        if (n_vertices >= 0) message << ", outside [0, " << n_vertices << ")";
        else message << ": indices must be non-negative";
        throw InputError(message.str());
      }
      largest = std::max(largest, index);
    }
  }
  if (n_vertices >= 0) return n_vertices;
  // Without a vertex count, #V is inferred from the largest index; arrays of #V entries are
  // allocated, so a stray huge index in a small F must not cost gigabytes.
  const Eigen::Index limit = 3 * F.rows() + (Eigen::Index(1) << 20);
  if (largest >= limit) {
    Eigen::Index f = 0;
    while (F.row(f).maxCoeff() != largest) ++f;
    std::ostringstream message;
    message << "F[" << f << "] = (" << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2)
            << ") indexes vertex " << largest << ", but " << F.rows()
            << " faces reference at most " << 3 * F.rows() << " vertices: without a vertex count"
            << " (V or n_vertices), indices must be below 3 #F + 2^20 = " << limit;
    throw InputError(message.str());
  }
  return Eigen::Index(largest) + 1;
}

EdgeIncidence edge_incidence(const FaceRef& F, Eigen::Index n_vertices) {
  EdgeIncidence result;
  result.n_vertices = checked_vertex_count(F, n_vertices);
  const int n = static_cast<int>(result.n_vertices);
  const int n_sides = static_cast<int>(3 * F.rows());

  // Bucket the sides by their smaller vertex (counting sort; sides ascending inside a bucket).
  std::vector<int> bucket_offsets(n + 1, 0);
  for (int s = 0; s < n_sides; ++s) {
    const int a = F(s / 3, s % 3), b = F(s / 3, (s % 3 + 1) % 3);
    if (a != b) ++bucket_offsets[std::min(a, b) + 1];
  }
  std::partial_sum(bucket_offsets.begin(), bucket_offsets.end(), bucket_offsets.begin());
  const int n_edge_sides = bucket_offsets[n];
  std::vector<int> bucket_fill(bucket_offsets.begin(), bucket_offsets.end() - 1);
  // Each entry: (larger vertex, side id), so sorting a bucket groups the sides by edge.
  std::vector<std::pair<int, int>> entries(n_edge_sides);
  result.side_edge.assign(n_sides, -1);
  for (int s = 0; s < n_sides; ++s) {
    const int a = F(s / 3, s % 3), b = F(s / 3, (s % 3 + 1) % 3);
    if (a != b) entries[bucket_fill[std::min(a, b)]++] = {std::max(a, b), s};
  }

  // Sort each bucket and count its distinct edges (buckets are small: about the vertex degree).
  std::vector<int> edges_before(n + 1, 0);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& range) {
    for (int v = range.begin(); v < range.end(); ++v) {
      auto first = entries.begin() + bucket_offsets[v], last = entries.begin() + bucket_offsets[v + 1];
      std::sort(first, last);
      int distinct = 0;
      for (auto it = first; it != last; ++it) distinct += (it == first || it->first != (it - 1)->first);
      edges_before[v + 1] = distinct;
    }
  });
  std::partial_sum(edges_before.begin(), edges_before.end(), edges_before.begin());
  const int n_edges = edges_before[n];

  result.edges.resize(n_edges, 2);
  result.edge_offsets.resize(n_edges + 1);
  result.edge_offsets[n_edges] = n_edge_sides;
  result.edge_sides.resize(n_edge_sides);
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 4096), [&](const tbb::blocked_range<int>& range) {
    for (int v = range.begin(); v < range.end(); ++v) {
      int e = edges_before[v] - 1;
      for (int k = bucket_offsets[v]; k < bucket_offsets[v + 1]; ++k) {
        const auto [other, side] = entries[k];
        if (k == bucket_offsets[v] || other != entries[k - 1].first) {
          ++e;
          result.edges(e, 0) = v;
          result.edges(e, 1) = other;
          result.edge_offsets[e] = k;
        }
        result.edge_sides[k] = side;
        result.side_edge[side] = e;
      }
    }
  });
  return result;
}

EdgeMatrix edges(const FaceRef& F) { return edge_incidence(F).edges; }

}  // namespace meshsmith::topology
