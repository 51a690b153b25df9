#include <meshsmith/parametrization/cut_to_disk.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/topology/boundary.h>
#include <meshsmith/topology/characteristics.h>
#include <meshsmith/topology/dual_walk.h>

#include "input_checks.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <vector>

namespace meshsmith::parametrization {

namespace {

using topology::EdgeIncidence;

/// The edges at every vertex, as a compressed adjacency list.
struct VertexEdges {
  std::vector<int> offsets, edges;
  VertexEdges(const EdgeIncidence& incidence) : offsets(incidence.n_vertices + 1, 0) {
    for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
      ++offsets[incidence.edges(e, 0) + 1];
      ++offsets[incidence.edges(e, 1) + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    edges.resize(offsets.back());
    std::vector<int> fill(offsets.begin(), offsets.end() - 1);
    for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
      edges[fill[incidence.edges(e, 0)]++] = static_cast<int>(e);
      edges[fill[incidence.edges(e, 1)]++] = static_cast<int>(e);
    }
  }
};

int other_end(const EdgeIncidence& incidence, int e, int v) {
  return incidence.edges(e, 0) == v ? incidence.edges(e, 1) : incidence.edges(e, 0);
}

/// Dijkstra on edge lengths from the `sources` (all at distance 0); returns the distance and
/// predecessor edge of each vertex.
void shortest_paths(const VertexRef& V, const EdgeIncidence& incidence, const VertexEdges& adjacency,
                    const std::vector<int>& sources, std::vector<double>& distance, std::vector<int>& via) {
  distance.assign(incidence.n_vertices, std::numeric_limits<double>::infinity());
  via.assign(incidence.n_vertices, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (const int source : sources) {
    distance[source] = 0.0;
    queue.emplace(0.0, source);
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) {
      const int e = adjacency.edges[k];
      const int w = other_end(incidence, e, v);
      const double candidate = d + (V.row(w) - V.row(v)).norm();
      if (candidate < distance[w]) {
        distance[w] = candidate;
        via[w] = e;
        queue.emplace(candidate, w);
      }
    }
  }
}

/// Edges the breadth-first dual spanning tree from face 0 does not cross, pruned of dangling
/// branches: the cut graph (boundary edges included). The dual tree never crosses an edge of
/// `primal_tree` (tree–cotree, Eppstein 2003; Erickson & Whittlesey 2005), so the loops left
/// are each one edge closed by two shortest paths of the primal tree: short, straight seams.
std::vector<char> pruned_cut_graph(const FaceRef& F, const EdgeIncidence& incidence, const VertexEdges& adjacency,
                                   const std::vector<char>& primal_tree) {
  const Eigen::Index n_faces = F.rows();
  std::vector<char> keep(incidence.n_edges(), 1);
  const auto reached = topology::dual_spanning_tree(
      incidence, n_faces, 0, [&](int e) { return primal_tree[e] != 0; },
      [&](int, int e, int) { keep[e] = 0; });  // the dual tree crosses e: the faces stay glued along it
  if (std::find(reached.begin(), reached.end(), 0) != reached.end()) {
    throw SolverError("cut_to_disk: the dual spanning tree does not reach every face; please report this mesh");
  }
  std::vector<int> degree(incidence.n_vertices, 0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (keep[e]) ++degree[incidence.edges(e, 0)], ++degree[incidence.edges(e, 1)];
  }
  std::vector<int> leaves;
  for (Eigen::Index v = 0; v < incidence.n_vertices; ++v) {
    if (degree[v] == 1) leaves.push_back(static_cast<int>(v));
  }
  while (!leaves.empty()) {
    const int v = leaves.back();
    leaves.pop_back();
    if (degree[v] != 1) continue;
    for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) {
      const int e = adjacency.edges[k];
      if (!keep[e]) continue;
      keep[e] = 0;
      degree[v] = 0;
      const int w = other_end(incidence, e, v);
      if (--degree[w] == 1) leaves.push_back(w);
      break;
    }
  }
  return keep;
}

/// The shortest edge path between two far-apart vertices (double Dijkstra sweep), as edge flags;
/// from `start` to its farthest vertex when start ≥ 0.
std::vector<char> far_apart_path(const VertexRef& V, const EdgeIncidence& incidence, const VertexEdges& adjacency,
                                 int start = -1) {
  std::vector<double> distance;
  std::vector<int> via;
  auto farthest = [&] {
    return static_cast<int>(std::max_element(distance.begin(), distance.end()) - distance.begin());
  };
  int a = start;
  if (a < 0) {
    shortest_paths(V, incidence, adjacency, {0}, distance, via);
    a = farthest();
  }
  shortest_paths(V, incidence, adjacency, {a}, distance, via);
  std::vector<char> cut(incidence.n_edges(), 0);
  for (int v = farthest(); v != a;) {
    cut[via[v]] = 1;
    v = other_end(incidence, via[v], v);
  }
  return cut;
}

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// The corner of face f at vertex v (3f + k).
int corner_at(const FaceRef& F, int f, int v) {
  for (int k = 0; k < 3; ++k) {
    if (F(f, k) == v) return 3 * f + k;
  }
  return -1;
}

/// Adds to `cut` the shortest paths joining every vertex of `through` to the seam or the
/// boundary (one multi-source Dijkstra sweep: its tree paths form a forest hung on the sources).
void join_to_cut(const VertexRef& V, const EdgeIncidence& incidence, const VertexEdges& adjacency,
                 const std::vector<int>& through, std::vector<char>& cut) {
  std::vector<char> on_cut(incidence.n_vertices, 0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (cut[e] || incidence.side_count(e) == 1) on_cut[incidence.edges(e, 0)] = on_cut[incidence.edges(e, 1)] = 1;
  }
  std::vector<int> sources;
  for (Eigen::Index v = 0; v < incidence.n_vertices; ++v) {
    if (on_cut[v]) sources.push_back(static_cast<int>(v));
  }
  if (sources.empty()) sources.push_back(through.front());  // a closed sphere: the first vertex starts the seam
  std::vector<double> distance;
  std::vector<int> via;
  shortest_paths(V, incidence, adjacency, sources, distance, via);
  for (const int start : through) {
    for (int v = start; via[v] >= 0 && !cut[via[v]];) {
      cut[via[v]] = 1;
      v = other_end(incidence, via[v], v);
    }
  }
}

}  // namespace

CutMesh cut_to_disk(const VertexRef& input_V, const FaceRef& F) { return cut_to_disk(input_V, F, {}); }

CutMesh cut_to_disk(const VertexRef& input_V, const FaceRef& F, const std::vector<int>& through) {
  // Path lengths on normalized coordinates (edge lengths of 1e300-sized meshes overflowed to
  // inf and broke the shortest paths); the cut mesh copies the input's rows.
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto checked = detail::check_mesh(V, F, detail::Requirement::any, "cut_to_disk");
  const EdgeIncidence& incidence = checked.incidence;
  const Eigen::Index n = V.rows(), m = F.rows();
  for (std::size_t k = 0; k < through.size(); ++k) {
    if (through[k] < 0 || through[k] >= n) {
      throw InputError("cut_to_disk: entry " + std::to_string(k) + " of the vertices to cut through is " +
                       std::to_string(through[k]) + ", outside [0, " + std::to_string(n) + ")");
    }
  }
  CutMesh result;
  bool through_interior = false;
  if (!through.empty() && checked.is_disk()) {
    std::vector<char> boundary(n, 0);
    for (const auto& loop : checked.boundary_loops) for (const int v : loop) boundary[v] = 1;
    for (const int v : through) through_interior |= !boundary[v];
  }
  if (checked.is_disk() && !through_interior) {
    result.V = input_V;
    result.F = F;
    result.vertex_origin.setLinSpaced(n, 0, static_cast<int>(n - 1));
    result.seam_edges.resize(0, 2);
    return result;
  }
  const VertexEdges adjacency(incidence);
  // The shortest-path tree (Dijkstra on edge lengths) from vertex 0, or on a mesh with boundary
  // the forest grown from all boundary vertices at once, so that no two of its paths close a
  // loop through the boundary (which would separate the faces), as edge flags.
  std::vector<int> sources;
  for (const auto& loop : checked.boundary_loops) sources.insert(sources.end(), loop.begin(), loop.end());
  if (sources.empty()) sources.push_back(0);
  std::vector<double> distance;
  std::vector<int> via;
  shortest_paths(V, incidence, adjacency, sources, distance, via);
  std::vector<char> primal_tree(incidence.n_edges(), 0);
  for (const int e : via) {
    if (e >= 0) primal_tree[e] = 1;
  }
  std::vector<char> cut = pruned_cut_graph(F, incidence, adjacency, primal_tree);
  Eigen::Index n_cut = 0;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) == 1) cut[e] = 0;  // boundary edges are open already
    n_cut += cut[e];
  }
  if (!through.empty()) {
    join_to_cut(V, incidence, adjacency, through, cut);
    n_cut = std::count(cut.begin(), cut.end(), 1);
  }
  if (n_cut == 0) {  // a closed sphere
    cut = far_apart_path(V, incidence, adjacency, through.empty() ? -1 : through.front());
  }

  // Corners stay together across every interior edge that is not cut; each group of corners
  // around a vertex becomes one output vertex.
  std::vector<int> parent(3 * m);
  std::iota(parent.begin(), parent.end(), 0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (cut[e] || incidence.side_count(e) != 2) continue;
    const int f = incidence.edge_sides[incidence.edge_offsets[e]] / 3;
    const int g = incidence.edge_sides[incidence.edge_offsets[e] + 1] / 3;
    for (int end = 0; end < 2; ++end) {
      const int v = incidence.edges(e, end);
      const int a = find_root(parent, corner_at(F, f, v)), b = find_root(parent, corner_at(F, g, v));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Number the groups: the group of a vertex's first corner keeps the vertex's index.
  std::vector<int> group_vertex(3 * m, -1);
  std::vector<char> taken(n, 0);
  std::vector<int> origin(n);
  std::iota(origin.begin(), origin.end(), 0);
  for (int c = 0; c < 3 * m; ++c) {
    const int root = find_root(parent, c), v = F(c / 3, c % 3);
    if (group_vertex[root] < 0 && !taken[v]) group_vertex[root] = v, taken[v] = 1;
  }
  std::vector<std::pair<int, int>> extra;  // (original vertex, root), appended in vertex order
  for (int c = 0; c < 3 * m; ++c) {
    const int root = find_root(parent, c);
    if (group_vertex[root] == -1) {
      group_vertex[root] = -2;  // listed
      extra.emplace_back(F(c / 3, c % 3), root);
    }
  }
  std::stable_sort(extra.begin(), extra.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [v, root] : extra) {
    group_vertex[root] = static_cast<int>(origin.size());
    origin.push_back(v);
  }
  result.vertex_origin = Eigen::Map<const Eigen::VectorXi>(origin.data(), static_cast<Eigen::Index>(origin.size()));
  result.V.resize(static_cast<Eigen::Index>(origin.size()), 3);
  for (std::size_t i = 0; i < origin.size(); ++i) result.V.row(i) = input_V.row(origin[i]);
  result.F.resize(m, 3);
  for (int c = 0; c < 3 * m; ++c) result.F(c / 3, c % 3) = group_vertex[find_root(parent, c)];

  std::vector<int> seam;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (cut[e]) seam.push_back(static_cast<int>(e));
  }
  result.seam_edges.resize(static_cast<Eigen::Index>(seam.size()), 2);
  for (std::size_t k = 0; k < seam.size(); ++k) result.seam_edges.row(k) = incidence.edges.row(seam[k]);

  const auto loops = topology::boundary_loops(result.F);
  if (loops.size() != 1 || topology::euler_characteristic(result.F) != 1) {
    throw SolverError("cut_to_disk: the cut mesh is not a disk (" + std::to_string(loops.size()) +
                      " boundary loops); please report this mesh");
  }
  return result;
}

}  // namespace meshsmith::parametrization
