// Spectral Morse–Smale quadrangulation (§5.2.1) in four steps.
//
// 1. The eigenfunction: the lowest eigenpairs of −L u = λ M u (geometry::laplacian_eigenpairs);
//    the eigenvector's index sets the frequency, hence the number of critical points and cells.
// 2. The complex: vertices classified by the wedges of their one-ring (ties broken by index);
//    from every saddle one line per wedge, walked along edges by steepest ascent or descent to an
//    extremum. Lines are kept vertex-disjoint (but at their ends) and chordless, which is what
//    makes every cell an embedded disk whose boundary maps onto the square's sides without a
//    degenerate triangle. A line with no admissible step leaves the complex incomplete: the mesh is
//    then split 1-to-4 (the function interpolated linearly, so the same PL function and the same
//    critical points) and the complex traced again (for the candidate eigenvectors after the
//    nearest ones, only once no candidate completed on the coarser mesh).
// 3. The maps: every cell, cut out as its own disk, is mapped by a mean-value harmonic map
//    (parametrization::harmonic) onto the unit square, its corners on the square's corners and
//    its sides spaced by arc length.
// 4. The grids: sides are chained (opposite sides of a cell; the two cells of a line share it) by
//    union–find, each chain gets one count, so the n×m grids of neighbouring cells meet node for
//    node; side nodes are placed once per line (by arc length, the same as the maps' boundary), the
//    interior nodes are the maps' preimages of the grid points.
#include <meshsmith/quadrangulation/spectral.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/geometry/spectral.h>
#include <meshsmith/parametrization/harmonic.h>
#include <meshsmith/parametrization/mesh_checks.h>
#include <meshsmith/topology/edge_incidence.h>

#include "field_geometry.h"
#include "seamless_map.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <queue>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

namespace meshsmith::quadrangulation {

namespace {

/// The mesh a complex is traced on: the input, or a 1-to-4 refinement of it.
struct Surface {
  VertexMatrix V;
  FaceMatrix F;
  Eigen::VectorXd f;
};

/// f[a] above f[b], ties broken by index (simulation of simplicity).
inline bool above(const Eigen::VectorXd& f, int a, int b) { return f[a] > f[b] || (f[a] == f[b] && a > b); }

/// Counter-clockwise one-rings of a closed oriented manifold: vertex v's ring is
/// ring[start[v] .. start[v] + count[v]). A ring changed by edge splits is appended anew (set).
struct Rings {
  std::vector<int> start, count, ring;
  int size(int v) const { return count[v]; }
  const int* begin(int v) const { return ring.data() + start[v]; }
  /// Vertex v's ring from its corner steps (b, c) (one per face (v, b, c)), chained
  /// counter-clockwise and appended; v may be the next new vertex. Throws InputError unless the
  /// steps form one closed fan.
  void set(int v, const std::vector<std::pair<int, int>>& steps) {
    if (v == static_cast<int>(start.size())) start.push_back(0), count.push_back(0);
    start[v] = static_cast<int>(ring.size());
    count[v] = static_cast<int>(steps.size());
    int current = steps.empty() ? -1 : steps.front().first;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      ring.push_back(current);
      int next = -1;
      for (const auto& [from, to] : steps)
        if (from == current) next = to;
      if (next < 0 || (k + 1 < steps.size() && next == ring[start[v]]))
        throw InputError("vertex " + std::to_string(v) + " is not a closed manifold vertex (its faces do not form one fan)");
      current = next;
    }
  }
};

Rings one_rings(const FaceMatrix& F, int n) {
  std::vector<int> offset(n + 1, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++offset[F(f, k) + 1];
  std::partial_sum(offset.begin(), offset.end(), offset.begin());
  // At corner v of face (v, b, c), the ring goes from b to c (counter-clockwise around v).
  std::vector<std::pair<int, int>> steps(offset[n]);
  std::vector<int> fill(offset.begin(), offset.end() - 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) steps[fill[F(f, k)]++] = {F(f, (k + 1) % 3), F(f, (k + 2) % 3)};
  Rings rings;
  rings.start.resize(n);
  rings.count.resize(n);
  rings.ring.reserve(steps.size());
  std::vector<std::pair<int, int>> around;
  for (int v = 0; v < n; ++v) {
    around.assign(steps.begin() + offset[v], steps.begin() + offset[v + 1]);
    rings.set(v, around);
  }
  return rings;
}

/// Critical points of f from the sign changes around each vertex.
void classify(const Rings& rings, const Eigen::VectorXd& f, Eigen::VectorXi& type, Eigen::VectorXi& multiplicity) {
  const int n = static_cast<int>(f.size());
  type.setZero(n);
  multiplicity.setZero(n);
  for (int v = 0; v < n; ++v) {
    const int* r = rings.begin(v);
    const int d = rings.size(v);
    int changes = 0, up = 0;
    for (int k = 0; k < d; ++k) {
      const bool a = above(f, r[k], v), b = above(f, r[(k + 1) % d], v);
      changes += a != b;
      up += a;
    }
    if (changes == 0) {
      type[v] = static_cast<int>(up ? CriticalType::minimum : CriticalType::maximum);
    } else if (changes > 2) {
      type[v] = static_cast<int>(CriticalType::saddle);
      multiplicity[v] = changes / 2 - 1;
    }
  }
}

using EdgeKey = std::uint64_t;
inline EdgeKey edge_key(int a, int b) {
  return (static_cast<EdgeKey>(std::min(a, b)) << 32) | static_cast<EdgeKey>(std::max(a, b));
}

void build_cells(const Surface& S, MorseSmaleComplex& C);

/// Faces around each vertex (for edge splits).
std::vector<std::vector<int>> faces_of_vertices(const FaceMatrix& F, Eigen::Index n) {
  std::vector<std::vector<int>> vertex_faces(n);
  for (Eigen::Index face = 0; face < F.rows(); ++face)
    for (int k = 0; k < 3; ++k) vertex_faces[F(face, k)].push_back(static_cast<int>(face));
  return vertex_faces;
}

/// Splits edge (a, b) at its midpoint, f interpolated linearly, each of its two faces into two;
/// returns the new vertex. The new vertex is regular and no other vertex changes type (its value
/// lies between those of a and b, which it separates in every ring it joins).
int split_edge(Surface& S, std::vector<std::vector<int>>& vertex_faces, int a, int b) {
  const int m = static_cast<int>(S.V.rows());
  S.V.conservativeResize(m + 1, 3);
  S.V.row(m) = 0.5 * (S.V.row(a) + S.V.row(b));
  S.f.conservativeResize(m + 1);
  S.f[m] = 0.5 * (S.f[a] + S.f[b]);
  vertex_faces.emplace_back();
  const std::vector<int> around = vertex_faces[a];
  for (const int face : around) {
    int k = 0;
    while (k < 3 && !((S.F(face, k) == a && S.F(face, (k + 1) % 3) == b) || (S.F(face, k) == b && S.F(face, (k + 1) % 3) == a))) ++k;
    if (k == 3) continue;
    const int u = S.F(face, k), w = S.F(face, (k + 1) % 3), c = S.F(face, (k + 2) % 3);
    const int g = static_cast<int>(S.F.rows());
    S.F.conservativeResize(g + 1, 3);
    S.F.row(face) << u, m, c;
    S.F.row(g) << m, w, c;
    std::replace(vertex_faces[w].begin(), vertex_faces[w].end(), face, g);
    vertex_faces[c].push_back(g);
    vertex_faces[m].push_back(face);
    vertex_faces[m].push_back(g);
  }
  return m;
}

/// Traces the complex's lines; `stuck` is the saddle of the first line that found no admissible
/// step (refinement may help), −1 when none did. The cells follow (build_cells) unless the lines are incomplete.
/// With `split` (S is then refined in place: the complex refers to the refined mesh), a line walled
/// in by others goes on through the gaps between them: a shortest path that may run through the
/// midpoints of mesh edges joining two lines (or a line and an extremum), which are then split.
MorseSmaleComplex trace_complex(Surface& S, const Rings& initial_rings, int& stuck, int order = 0, bool split = false) {
  const Eigen::VectorXd& f = S.f;
  int n = static_cast<int>(S.V.rows());
  Rings rings = initial_rings;
  MorseSmaleComplex C;
  classify(rings, f, C.vertex_type, C.saddle_multiplicity);
  const auto is = [&](int v, CriticalType t) { return C.vertex_type[v] == static_cast<int>(t); };
  for (int v = 0; v < n; ++v) {
    C.maxima += is(v, CriticalType::maximum);
    C.minima += is(v, CriticalType::minimum);
    C.saddles += C.saddle_multiplicity[v];
  }
  C.face_patch.setConstant(S.F.rows(), -1);
  stuck = -1;

  std::vector<int> owner(n, -1), reserved(n, -1);
  // A route towards a given extremum is given up (and another way tried) once it would be longer
  // than kDetourFactor times the straight distance plus kDetourSlack mean edge lengths: such a
  // line would wander across the surface, and proving that no route exists would search it all.
  constexpr double kDetourFactor = 4.0, kDetourSlack = 10.0;
  double mean_edge = 0.0;  // of S before any gap route splits it
  for (Eigen::Index face = 0; face < S.F.rows(); ++face)
    for (int k = 0; k < 3; ++k) mean_edge += (S.V.row(S.F(face, k)) - S.V.row(S.F(face, (k + 1) % 3))).norm();
  mean_edge /= std::max<double>(1.0, 3.0 * static_cast<double>(S.F.rows()));
  const auto detour_limit = [&](double straight) {
    return kDetourFactor * straight + kDetourSlack * mean_edge;
  };
  // The admissible step from x of line `id` with the highest slope towards its extremum; an
  // extremum is preferred (it ends the line); -1 when there is none.
  const auto step = [&](int x, const int* candidates, int count, bool ascending, int id) {
    const CriticalType target = ascending ? CriticalType::maximum : CriticalType::minimum;
    int best = -1;
    bool best_end = false;
    double best_slope = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < count; ++k) {
      const int y = candidates[k];
      if (ascending ? !above(f, y, x) : !above(f, x, y)) continue;
      if (is(y, CriticalType::saddle)) continue;
      const bool end = is(y, target);
      if (!end && (owner[y] >= 0 || reserved[y] >= 0)) continue;
      const double slope = std::abs(f[y] - f[x]) / std::max((S.V.row(y) - S.V.row(x)).norm(), 1e-300);
      if ((end && !best_end) || (end == best_end && slope > best_slope)) {
        best = y;
        best_end = end;
        best_slope = slope;
      }
    }
    return best;
  };

  // Dijkstra (by length) from x through vertices of no line, no saddle and no extremum but the
  // one the steepest blocking line ends at (or any of the right kind); the path after x, or empty.
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int> from(n, -1), touched;
  // A* towards `target` when there is one: the straight-line distance to it never overestimates.
  std::function<std::vector<int>(int, bool, int, int, bool)> route_to = [&](int x, bool ascending, int id, int target,
                                                                            bool keep_reserved) {
    const CriticalType target_type = ascending ? CriticalType::maximum : CriticalType::minimum;
    const auto to_go = [&](int v) { return target < 0 ? 0.0 : (S.V.row(target) - S.V.row(v)).norm(); };
    using Item = std::tuple<double, double, int>;  // (distance + to_go, distance, vertex)
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    distance[x] = 0.0;
    touched.assign(1, x);
    heap.push({to_go(x), 0.0, x});
    const double limit = target < 0 ? std::numeric_limits<double>::infinity() : detour_limit(to_go(x));
    int reached = -1;
    while (!heap.empty()) {
      const auto [key, d, v] = heap.top();
      heap.pop();
      if (key > limit) break;
      if (d > distance[v]) continue;
      if (v != x && is(v, target_type)) {
        reached = v;
        break;
      }
      for (int j = 0; j < rings.size(v); ++j) {
        const int w = rings.begin(v)[j];
        if (owner[w] >= 0 || (keep_reserved && reserved[w] >= 0) || is(w, CriticalType::saddle)) continue;
        if (C.vertex_type[w] != static_cast<int>(CriticalType::regular) && !(is(w, target_type) && (target < 0 || w == target))) continue;
        const double dw = d + (S.V.row(w) - S.V.row(v)).norm();
        if (dw < distance[w]) {
          if (distance[w] == std::numeric_limits<double>::infinity()) touched.push_back(w);
          distance[w] = dw;
          from[w] = v;
          heap.push({dw + to_go(w), dw, w});
        }
      }
    }
    if (reached < 0 && target >= 0) {
      for (const int v : touched) distance[v] = std::numeric_limits<double>::infinity(), from[v] = -1;
      return route_to(x, ascending, id, -1, keep_reserved);
    }
    std::vector<int> path;
    for (int v = reached; v >= 0 && v != x; v = from[v]) path.push_back(v);
    std::reverse(path.begin(), path.end());
    for (const int v : touched) distance[v] = std::numeric_limits<double>::infinity(), from[v] = -1;
    return path;
  };
  // The extremum of the steepest line blocking x's way (−1: none).
  const auto blocking_target = [&](int x, bool ascending, int id) {
    int target = -1;
    double best_slope = -1.0;
    for (int j = 0; j < rings.size(x); ++j) {
      const int y = rings.begin(x)[j];
      if (owner[y] < 0 || owner[y] == id || (ascending ? !above(f, y, x) : !above(f, x, y))) continue;
      const double slope = std::abs(f[y] - f[x]) / std::max((S.V.row(y) - S.V.row(x)).norm(), 1e-300);
      if (slope > best_slope) best_slope = slope, target = C.lines[owner[y]].back();
    }
    return target;
  };
  // Through free vertices; with `steal`, also through other saddles' reserved first steps (the
  // last resort: a saddle whose step is taken then starts from another vertex of that wedge).
  const auto route = [&](int x, bool ascending, int id, bool steal) {
    return route_to(x, ascending, id, blocking_target(x, ascending, id), !steal);
  };
  // Through the gaps (with `split`): Dijkstra over free vertices and the midpoints of splittable
  // edges (no line's edge, none at a saddle, not both ends free); a midpoint neighbours the
  // vertices opposite its edge and the midpoints of the other edges of its faces. The path found
  // is made real by splitting its edges in order (each then joins its predecessor); the vertices
  // after x, or empty.
  std::vector<std::vector<int>> vertex_faces;
  // The search's nodes: vertices, and n + side for the midpoint of an edge, named by the lower of
  // its two face sides (side 3·face + k is the edge from corner k to corner k + 1). Distances and
  // predecessors per node, reset through `gap_touched` after each search.
  std::vector<double> gap_distance;
  std::vector<int> gap_from, gap_touched;
  const auto twin_side = [&](int side) {
    const int face = side / 3, a = S.F(face, side % 3), b = S.F(face, (side % 3 + 1) % 3);
    for (const int g : vertex_faces[b]) {
      if (g == face) continue;
      for (int k = 0; k < 3; ++k)
        if (S.F(g, k) == b && S.F(g, (k + 1) % 3) == a) return 3 * g + k;
    }
    return side;  // not reached on a closed manifold
  };
  const auto route_through_gaps = [&](const std::vector<int>& current, bool ascending, int target) -> std::vector<int> {
    if (!split) return {};
    if (vertex_faces.empty()) vertex_faces = faces_of_vertices(S.F, n);
    const int x = current.back();
    const CriticalType target_type = ascending ? CriticalType::maximum : CriticalType::minimum;
    std::vector<EdgeKey> line_edges;
    const auto add_line = [&](const std::vector<int>& line) {
      for (std::size_t k = 0; k + 1 < line.size(); ++k) line_edges.push_back(edge_key(line[k], line[k + 1]));
    };
    for (const auto& line : C.lines) add_line(line);
    add_line(current);
    std::sort(line_edges.begin(), line_edges.end());
    const auto admissible = [&](int v, int wanted) {
      if (is(v, target_type)) return wanted < 0 || v == wanted;
      return C.vertex_type[v] == static_cast<int>(CriticalType::regular) && owner[v] < 0 && reserved[v] < 0;
    };
    const auto splittable = [&](int a, int b) {
      return !std::binary_search(line_edges.begin(), line_edges.end(), edge_key(a, b)) && !is(a, CriticalType::saddle) &&
             !is(b, CriticalType::saddle) && !(admissible(a, target) && admissible(b, target)) && a != x && b != x;
    };
    const auto side_ends = [&](int side) {
      return std::pair<int, int>(S.F(side / 3, side % 3), S.F(side / 3, (side % 3 + 1) % 3));
    };
    const auto position = [&](int node) -> Eigen::RowVector3d {
      if (node < n) return S.V.row(node);
      const auto [a, b] = side_ends(node - n);
      return 0.5 * (S.V.row(a) + S.V.row(b));
    };
    const std::size_t nodes = static_cast<std::size_t>(n) + 3 * static_cast<std::size_t>(S.F.rows());
    if (gap_distance.size() < nodes) {
      gap_distance.resize(nodes, std::numeric_limits<double>::infinity());
      gap_from.resize(nodes, -1);
    }
    const auto reset = [&] {
      for (const int node : gap_touched) gap_distance[node] = std::numeric_limits<double>::infinity(), gap_from[node] = -1;
      gap_touched.clear();
    };
    for (int attempt = 0; attempt < 2; ++attempt) {
      const int wanted = attempt == 0 ? target : -1;
      if (attempt == 1 && target < 0) break;
      // A* towards `wanted` when there is one (as route_to).
      const auto to_go = [&](int v) { return wanted < 0 ? 0.0 : (S.V.row(wanted) - position(v)).norm(); };
      using Item = std::tuple<double, double, int>;  // (distance + to_go, distance, node)
      std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
      double d = 0.0, key = 0.0;
      int node = x;
      const auto relax_to = [&](int next, double extra) {
        const double dn = d + (position(next) - position(node)).norm() + extra;
        if (dn < gap_distance[next]) {
          if (gap_distance[next] == std::numeric_limits<double>::infinity()) gap_touched.push_back(next);
          gap_distance[next] = dn;
          gap_from[next] = node;
          heap.push({dn + to_go(next), dn, next});
        }
      };
      // The midpoint of side (face, k)'s edge (w, c), 0.25 of its length added (a split costs).
      const auto relax_to_midpoint = [&](int face, int k, int w, int c) {
        if (!splittable(w, c)) return;
        const int side = 3 * face + k;
        relax_to(n + std::min(side, twin_side(side)), 0.25 * (S.V.row(w) - S.V.row(c)).norm());
      };
      gap_distance[x] = 0.0;
      gap_touched.push_back(x);
      heap.push({to_go(x), 0.0, x});
      const double limit = wanted < 0 ? std::numeric_limits<double>::infinity() : detour_limit(to_go(x));
      int reached = -1;
      while (!heap.empty() && gap_touched.size() < 400000) {
        std::tie(key, d, node) = heap.top();
        heap.pop();
        if (key > limit) break;
        if (d > gap_distance[node]) continue;
        if (node < n && node != x && is(node, target_type)) {
          reached = node;
          break;
        }
        if (node < n) {
          // Neighbours: b and c of each face (node, b, c) and the midpoint of its edge (b, c).
          for (const int face : vertex_faces[node]) {
            int k = 0;
            while (S.F(face, k) != node) ++k;
            const int b = S.F(face, (k + 1) % 3), c = S.F(face, (k + 2) % 3);
            for (const int w : {b, c})
              if (admissible(w, wanted)) relax_to(w, 0.0);
            relax_to_midpoint(face, (k + 1) % 3, b, c);
          }
        } else {
          // Neighbours of edge (a, b)'s midpoint: in each of its faces (a, b, c), c and the
          // midpoints of the edges (b, c) and (c, a).
          const int side = node - n;
          for (const int s : {side, twin_side(side)}) {
            const int face = s / 3, k = s % 3;
            const int a = S.F(face, k), b = S.F(face, (k + 1) % 3), c = S.F(face, (k + 2) % 3);
            if (admissible(c, wanted)) relax_to(c, 0.0);
            relax_to_midpoint(face, (k + 1) % 3, b, c);
            relax_to_midpoint(face, (k + 2) % 3, a, c);
          }
        }
      }
      if (reached < 0) {
        reset();
        continue;
      }
      std::vector<int> route_nodes;
      for (int v = reached; v != x; v = gap_from[v]) route_nodes.push_back(v);
      std::reverse(route_nodes.begin(), route_nodes.end());
      reset();
      // The edges to split, read before any split renumbers the faces' corners.
      std::vector<std::pair<int, int>> ends(route_nodes.size(), {-1, -1});
      for (std::size_t k = 0; k < route_nodes.size(); ++k)
        if (route_nodes[k] >= n) ends[k] = side_ends(route_nodes[k] - n);
      // Make it real; every step must then be a mesh edge.
      std::vector<int> path;
      for (std::size_t k = 0; k < route_nodes.size(); ++k)
        path.push_back(route_nodes[k] < n ? route_nodes[k] : split_edge(S, vertex_faces, ends[k].first, ends[k].second));
      const auto adjacent = [&](int a, int b) {
        for (const int face : vertex_faces[a])
          for (int k = 0; k < 3; ++k)
            if (S.F(face, k) == b) return true;
        return false;
      };
      const int added = static_cast<int>(S.V.rows()) - n;
      const int before = n;
      n = static_cast<int>(S.V.rows());
      owner.resize(n, -1);
      reserved.resize(n, -1);
      distance.resize(n, std::numeric_limits<double>::infinity());
      from.resize(n, -1);
      C.vertex_type.conservativeResize(n);
      C.saddle_multiplicity.conservativeResize(n);
      C.vertex_type.tail(added).setZero();
      C.saddle_multiplicity.tail(added).setZero();
      // The rings that changed: the new vertices' and their neighbours' (a split changes only
      // the rings around its new vertex).
      std::vector<int> changed;
      for (int v = before; v < n; ++v)
        for (const int face : vertex_faces[v])
          for (int k = 0; k < 3; ++k) changed.push_back(S.F(face, k));
      std::sort(changed.begin(), changed.end());
      changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
      std::vector<std::pair<int, int>> steps;
      for (const int v : changed) {
        steps.clear();
        for (const int face : vertex_faces[v]) {
          int k = 0;
          while (S.F(face, k) != v) ++k;
          steps.emplace_back(S.F(face, (k + 1) % 3), S.F(face, (k + 2) % 3));
        }
        rings.set(v, steps);
      }
      bool ok = adjacent(x, path.front());
      for (std::size_t k = 0; ok && k + 1 < path.size(); ++k) ok = adjacent(path[k], path[k + 1]);
      ++C.gap_routes;
      return ok ? path : std::vector<int>{};
    }
    return {};
  };
  // Every saddle's first step into each wedge is reserved before any line is traced, so a line
  // passing by cannot take a wedge's only vertex. reserved[v]: the saddle whose start v is.
  const auto first_steps = [&](int s, std::vector<std::pair<int, bool>>& starts) {
    const int* r = rings.begin(s);
    const int d = rings.size(s);
    int start = 0;
    while (above(f, r[start], s) == above(f, r[(start + d - 1) % d], s)) ++start;
    starts.clear();
    for (int k = 0; k < d;) {
      const bool up = above(f, r[(start + k) % d], s);
      int best = -1;
      double best_slope = -1.0;
      for (; k < d && above(f, r[(start + k) % d], s) == up; ++k) {
        const int y = r[(start + k) % d];
        if (is(y, CriticalType::saddle) || reserved[y] >= 0) continue;
        const double slope = std::abs(f[y] - f[s]) / std::max((S.V.row(y) - S.V.row(s)).norm(), 1e-300);
        const bool end = is(y, up ? CriticalType::maximum : CriticalType::minimum);
        if (end) {
          if (best < 0 || !is(best, up ? CriticalType::maximum : CriticalType::minimum) || slope > best_slope) best = y, best_slope = slope;
        } else if (best < 0 || (!is(best, up ? CriticalType::maximum : CriticalType::minimum) && slope > best_slope)) {
          best = y, best_slope = slope;
        }
      }
      starts.emplace_back(best, up);
    }
  };
  std::vector<std::vector<std::pair<int, bool>>> saddle_starts(n);
  for (int s = 0; s < n; ++s) {
    if (!is(s, CriticalType::saddle)) continue;
    first_steps(s, saddle_starts[s]);
    for (const auto& [y, up] : saddle_starts[s])
      if (y >= 0 && C.vertex_type[y] == static_cast<int>(CriticalType::regular)) reserved[y] = s;
  }

  // The saddles in the order their lines are traced (later lines go beside earlier ones): by
  // index (order 0), by f descending (1), ascending (2), by index descending (3).
  std::vector<int> saddles;
  for (int s = 0; s < n; ++s)
    if (is(s, CriticalType::saddle)) saddles.push_back(s);
  if (order == 1) std::sort(saddles.begin(), saddles.end(), [&](int a, int b) { return above(f, a, b); });
  if (order == 2) std::sort(saddles.begin(), saddles.end(), [&](int a, int b) { return above(f, b, a); });
  if (order == 3) std::reverse(saddles.begin(), saddles.end());
  for (const int s : saddles) {
    if (!C.problem.empty()) break;
    for (const auto& [first, up] : saddle_starts[s]) {
      if (!C.problem.empty()) break;
      const int id = static_cast<int>(C.lines.size());
      std::vector<int> line{s};
      int y = first >= 0 && owner[first] < 0 ? first : -1;
      if (y < 0 && first >= 0) {
        // The wedge's reserved step was taken (by a last-resort route): its steepest free vertex.
        const int* r = rings.begin(s);
        const int d = rings.size(s);
        int at = 0;
        while (at < d && r[at] != first) ++at;
        double best_slope = -1.0;
        for (const int direction : {1, -1}) {
          for (int k = direction; std::abs(k) < d; k += direction) {
            const int v = r[((at + k) % d + d) % d];
            if (above(f, v, s) != up) break;
            if (owner[v] >= 0 || reserved[v] >= 0 || C.vertex_type[v] != static_cast<int>(CriticalType::regular)) continue;
            const double slope = std::abs(f[v] - f[s]) / std::max((S.V.row(v) - S.V.row(s)).norm(), 1e-300);
            if (slope > best_slope) best_slope = slope, y = v;
          }
        }
      }
      while (y >= 0) {
        line.push_back(y);
        if (is(y, up ? CriticalType::maximum : CriticalType::minimum)) break;
        owner[y] = id;
        y = step(y, rings.begin(y), rings.size(y), up, id);
        if (y < 0) {
          // Merging: every step up (down) is on another line, which PL gradient lines do in
          // valleys and on ridges. Continue beside it instead: the shortest path through free
          // vertices to the extremum that line ends at.
          // From the line's end, or, when that is walled in, from earlier along it (backtracking).
          std::vector<int> detour = route(line.back(), up, id, false);
          if (detour.empty() && split) detour = route_through_gaps(line, up, blocking_target(line.back(), up, id));
          if (detour.empty()) detour = route(line.back(), up, id, true);
          while (detour.empty() && line.size() > 2) {
            owner[line.back()] = -1;
            line.pop_back();
            detour = route(line.back(), up, id, true);
          }
          for (std::size_t k = 0; k + 1 < detour.size(); ++k) line.push_back(detour[k]), owner[detour[k]] = id;
          if (!detour.empty()) line.push_back(detour.back());
          ++C.detours;
          break;
        }
      }
      if (line.size() < 2 || !is(line.back(), up ? CriticalType::maximum : CriticalType::minimum)) {
        stuck = s;
        C.problem = std::string("the ") + (up ? "ascending" : "descending") + " line from saddle " +
                    std::to_string(s) + " found no free step at vertex " + std::to_string(line.back());
      }
      C.lines.push_back(std::move(line));
      C.line_ascending.push_back(up);
    }
  }
  if (!C.problem.empty()) return C;

  // Every extremum must end at least two lines, else it lies inside a cell or on a dangling line.
  std::vector<int> ends(n, 0);
  for (const auto& line : C.lines) ++ends[line.back()];
  for (int v = 0; v < n; ++v) {
    if ((is(v, CriticalType::maximum) || is(v, CriticalType::minimum)) && ends[v] < 2) {
      C.problem = std::string(is(v, CriticalType::maximum) ? "maximum " : "minimum ") + std::to_string(v) +
                  " ends " + std::to_string(ends[v]) + " line(s) (at least 2 make it a cell corner)";
      return C;
    }
  }
  build_cells(S, C);
  return C;
}

/// The cells of complete lines: faces connected across edges that no line uses; each must be a
/// disk bounded by four lines with max–saddle–min–saddle corners (C.problem says which is not).
void build_cells(const Surface& S, MorseSmaleComplex& C) {
  const int n = static_cast<int>(S.V.rows());
  const auto is = [&](int v, CriticalType t) { return C.vertex_type[v] == static_cast<int>(t); };
  C.problem.clear();
  C.face_patch.setConstant(S.F.rows(), -1);
  const topology::EdgeIncidence incidence = topology::edge_incidence(S.F, n);
  std::unordered_map<EdgeKey, int> edge_of;
  edge_of.reserve(incidence.n_edges() * 2);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e)
    edge_of[edge_key(incidence.edges(e, 0), incidence.edges(e, 1))] = static_cast<int>(e);
  std::vector<int> cut(incidence.n_edges(), -1);
  for (std::size_t l = 0; l < C.lines.size(); ++l)
    for (std::size_t k = 0; k + 1 < C.lines[l].size(); ++k)
      cut[edge_of.at(edge_key(C.lines[l][k], C.lines[l][k + 1]))] = static_cast<int>(l);
  const Eigen::Index m = S.F.rows();
  int patches = 0;
  std::vector<int> queue;
  for (Eigen::Index seed = 0; seed < m; ++seed) {
    if (C.face_patch[seed] >= 0) continue;
    C.face_patch[seed] = patches;
    queue.assign(1, static_cast<int>(seed));
    while (!queue.empty()) {
      const int face = queue.back();
      queue.pop_back();
      for (int k = 0; k < 3; ++k) {
        const int e = incidence.side_edge[3 * face + k];
        if (cut[e] >= 0) continue;
        for (int j = incidence.edge_offsets[e]; j < incidence.edge_offsets[e + 1]; ++j) {
          const int other = incidence.edge_sides[j] / 3;
          if (C.face_patch[other] < 0) {
            C.face_patch[other] = patches;
            queue.push_back(other);
          }
        }
      }
    }
    ++patches;
  }
  const auto fail = [&](std::string problem) {
    C.problem = std::move(problem);
    C.face_patch.setConstant(m, -1);
    C.patch_corners.resize(0, 4);
    C.patch_sides.resize(0, 4);
  };
  // Boundary sides of each cell (a side on a line: its face is on the left of a → b).
  std::vector<std::vector<int>> boundary(patches);
  std::vector<int> face_count(patches, 0);
  for (Eigen::Index face = 0; face < m; ++face) ++face_count[C.face_patch[face]];
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (cut[e] < 0) continue;
    const int a = incidence.edge_sides[incidence.edge_offsets[e]] / 3;
    const int b = incidence.edge_sides[incidence.edge_offsets[e] + 1] / 3;
    if (C.face_patch[a] == C.face_patch[b])
      return fail("line " + std::to_string(cut[e]) + " has the same cell on both sides (edge " +
                  std::to_string(incidence.edges(e, 0)) + "-" + std::to_string(incidence.edges(e, 1)) + ")");
    for (int j = incidence.edge_offsets[e]; j < incidence.edge_offsets[e + 1]; ++j)
      boundary[C.face_patch[incidence.edge_sides[j] / 3]].push_back(incidence.edge_sides[j]);
  }
  C.patch_corners.resize(patches, 4);
  C.patch_sides.resize(patches, 4);
  std::vector<int> next_side(n, -1), seen(n, -1);
  for (int p = 0; p < patches; ++p) {
    const auto tail = [&](int side) { return S.F(side / 3, side % 3); };
    const auto head = [&](int side) { return S.F(side / 3, (side % 3 + 1) % 3); };
    for (const int side : boundary[p]) {
      if (next_side[tail(side)] >= 0) return fail("cell " + std::to_string(p) + " touches itself at vertex " + std::to_string(tail(side)));
      next_side[tail(side)] = side;
    }
    std::vector<int> loop, loop_sides;
    if (!boundary[p].empty()) {
      int side = boundary[p].front();
      do {
        loop.push_back(tail(side));
        loop_sides.push_back(side);
        side = next_side[head(side)];
      } while (side >= 0 && side != boundary[p].front() && loop.size() <= boundary[p].size());
    }
    for (const int side : boundary[p]) next_side[tail(side)] = -1;
    if (loop.size() != boundary[p].size() || boundary[p].empty())
      return fail("cell " + std::to_string(p) + " has " + (boundary[p].empty() ? "no" : "more than one") + " boundary loop");
    // χ = V − E + F of the cell (E = (3F + B) / 2) must be 1: a disk.
    long long vertices = 0;
    for (Eigen::Index face = 0; face < m; ++face) {
      if (C.face_patch[face] != p) continue;
      for (int k = 0; k < 3; ++k)
        if (seen[S.F(face, k)] != p) seen[S.F(face, k)] = p, ++vertices;
    }
    const long long faces = face_count[p], edges = (3 * faces + static_cast<long long>(loop.size())) / 2;
    if (vertices - edges + faces != 1) return fail("cell " + std::to_string(p) + " is not a disk");
    std::vector<int> corners, corner_at;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      if (C.vertex_type[loop[k]] != static_cast<int>(CriticalType::regular)) {
        corners.push_back(loop[k]);
        corner_at.push_back(static_cast<int>(k));
      }
    }
    if (corners.size() != 4) return fail("cell " + std::to_string(p) + " has " + std::to_string(corners.size()) + " corners");
    int first = 0;
    while (first < 4 && !is(corners[first], CriticalType::maximum)) ++first;
    if (first == 4 || !is(corners[(first + 1) % 4], CriticalType::saddle) ||
        !is(corners[(first + 2) % 4], CriticalType::minimum) || !is(corners[(first + 3) % 4], CriticalType::saddle))
      return fail("cell " + std::to_string(p) + "'s corners are not maximum, saddle, minimum, saddle");
    for (int k = 0; k < 4; ++k) {
      const int c = (first + k) % 4;
      C.patch_corners(p, k) = corners[c];
      C.patch_sides(p, k) = cut[incidence.side_edge[loop_sides[corner_at[c]]]];
    }
  }
}

/// 1-to-4 split of every triangle at its edge midpoints, f interpolated linearly.
Surface subdivide(const Surface& S) {
  const Eigen::Index n = S.V.rows(), m = S.F.rows();
  const topology::EdgeIncidence incidence = topology::edge_incidence(S.F, n);
  const Eigen::Index e_count = incidence.n_edges();
  Surface R;
  R.V.resize(n + e_count, 3);
  R.f.resize(n + e_count);
  R.V.topRows(n) = S.V;
  R.f.head(n) = S.f;
  for (Eigen::Index e = 0; e < e_count; ++e) {
    const int a = incidence.edges(e, 0), b = incidence.edges(e, 1);
    R.V.row(n + e) = 0.5 * (S.V.row(a) + S.V.row(b));
    R.f[n + e] = 0.5 * (S.f[a] + S.f[b]);
  }
  R.F.resize(4 * m, 3);
  for (Eigen::Index face = 0; face < m; ++face) {
    const int a = S.F(face, 0), b = S.F(face, 1), c = S.F(face, 2);
    const int ab = static_cast<int>(n + incidence.side_edge[3 * face]);
    const int bc = static_cast<int>(n + incidence.side_edge[3 * face + 1]);
    const int ca = static_cast<int>(n + incidence.side_edge[3 * face + 2]);
    R.F.row(4 * face) << a, ab, ca;
    R.F.row(4 * face + 1) << ab, b, bc;
    R.F.row(4 * face + 2) << ca, bc, c;
    R.F.row(4 * face + 3) << ab, bc, ca;
  }
  return R;
}

/// Splits every chord of a line (a mesh edge joining two of its vertices that are not
/// consecutive on it) at its midpoint, f interpolated linearly: otherwise the triangles on a
/// chord would map onto one side of the square with zero area. The new vertices are regular.
/// Returns the number of splits.
Eigen::Index split_chords(Surface& S, MorseSmaleComplex& C) {
  const int n = static_cast<int>(S.V.rows());
  std::vector<std::vector<int>> vertex_faces = faces_of_vertices(S.F, n);
  std::vector<int> stamp(n, -1), position(n, -1);
  std::vector<std::pair<int, int>> chords;
  for (std::size_t l = 0; l < C.lines.size(); ++l) {
    const auto& line = C.lines[l];
    for (std::size_t k = 0; k < line.size(); ++k) stamp[line[k]] = static_cast<int>(l), position[line[k]] = static_cast<int>(k);
    for (std::size_t k = 0; k < line.size(); ++k) {
      for (const int face : vertex_faces[line[k]]) {
        for (int j = 0; j < 3; ++j) {
          const int w = S.F(face, j);
          if (stamp[w] == static_cast<int>(l) && position[w] > static_cast<int>(k) + 1) chords.emplace_back(line[k], w);
        }
      }
    }
  }
  std::sort(chords.begin(), chords.end());
  chords.erase(std::unique(chords.begin(), chords.end()), chords.end());
  // An edge of another line (a one-edge line between the same two ends) is left alone.
  std::vector<EdgeKey> line_edges;
  for (const auto& line : C.lines)
    for (std::size_t k = 0; k + 1 < line.size(); ++k) line_edges.push_back(edge_key(line[k], line[k + 1]));
  std::sort(line_edges.begin(), line_edges.end());
  chords.erase(std::remove_if(chords.begin(), chords.end(), [&](const std::pair<int, int>& c) {
    return std::binary_search(line_edges.begin(), line_edges.end(), edge_key(c.first, c.second));
  }), chords.end());
  if (chords.empty()) return 0;
  for (const auto& [a, b] : chords) split_edge(S, vertex_faces, a, b);
  const Eigen::Index total = S.V.rows();
  const Eigen::Index added = total - n;
  C.vertex_type.conservativeResize(total);
  C.saddle_multiplicity.conservativeResize(total);
  C.vertex_type.tail(added).setZero();
  C.saddle_multiplicity.tail(added).setZero();
  return static_cast<Eigen::Index>(chords.size());
}

/// Every face at an extremum split 1-to-3 at its centroid (f the mean of its corners, so the PL
/// function and its critical points do not change): the extremum's valence doubles, and with it
/// the number of lines that can reach it through distinct neighbours.
Surface star_split(const Surface& S) {
  const int n = static_cast<int>(S.V.rows());
  Eigen::VectorXi type, multiplicity;
  classify(one_rings(S.F, n), S.f, type, multiplicity);
  const auto extremum = [&](int v) {
    return type[v] == static_cast<int>(CriticalType::maximum) || type[v] == static_cast<int>(CriticalType::minimum);
  };
  std::vector<std::array<int, 3>> faces;
  std::vector<int> split;
  for (Eigen::Index face = 0; face < S.F.rows(); ++face) {
    if (extremum(S.F(face, 0)) || extremum(S.F(face, 1)) || extremum(S.F(face, 2))) {
      const int c = n + static_cast<int>(split.size());
      split.push_back(static_cast<int>(face));
      for (int k = 0; k < 3; ++k) faces.push_back({S.F(face, k), S.F(face, (k + 1) % 3), c});
    } else {
      faces.push_back({S.F(face, 0), S.F(face, 1), S.F(face, 2)});
    }
  }
  Surface R;
  R.V.resize(n + split.size(), 3);
  R.f.resize(n + split.size());
  R.V.topRows(n) = S.V;
  R.f.head(n) = S.f;
  for (std::size_t i = 0; i < split.size(); ++i) {
    const auto t = S.F.row(split[i]);
    R.V.row(n + i) = (S.V.row(t[0]) + S.V.row(t[1]) + S.V.row(t[2])) / 3.0;
    R.f[n + i] = (S.f[t[0]] + S.f[t[1]] + S.f[t[2]]) / 3.0;
  }
  R.F.resize(faces.size(), 3);
  for (std::size_t face = 0; face < faces.size(); ++face) R.F.row(face) << faces[face][0], faces[face][1], faces[face][2];
  return R;
}

int find_root(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// The grid counts of the lines and their arc lengths.
struct LineCounts {
  std::vector<std::vector<double>> arc;  ///< per line, the arc length at each of its vertices
  std::vector<int> count;                ///< per line, its number of quad edges
};

/// Step 4's integer problem: sides are chained (opposite sides of a cell; the two cells of a line
/// share it) by union–find and each chain gets one count, so that opposite sides of every cell
/// and the two sides of every line agree; n = round(mean chain length / step), the step rescaled
/// a few rounds so that Σ over the cells of n·m comes nearest target_quads.
LineCounts line_counts(const Surface& S, const MorseSmaleComplex& C, double h, double target_quads) {
  const auto& lines = C.lines;
  const int n_lines = static_cast<int>(lines.size());
  const Eigen::Index patches = C.patch_corners.rows();
  LineCounts out;
  auto& arc = out.arc;
  auto& count = out.count;
  arc.resize(n_lines);
  for (int l = 0; l < n_lines; ++l) {
    arc[l].assign(1, 0.0);
    for (std::size_t k = 1; k < lines[l].size(); ++k)
      arc[l].push_back(arc[l].back() + (S.V.row(lines[l][k]) - S.V.row(lines[l][k - 1])).norm());
  }
  // Chains of sides that must have the same count.
  std::vector<int> parent(n_lines);
  std::iota(parent.begin(), parent.end(), 0);
  for (Eigen::Index p = 0; p < patches; ++p)
    for (int k = 0; k < 2; ++k)
      parent[find_root(parent, C.patch_sides(p, k))] = find_root(parent, C.patch_sides(p, k + 2));
  std::vector<double> chain_length(n_lines, 0.0);
  std::vector<int> chain_size(n_lines, 0);
  count.resize(n_lines);
  for (int l = 0; l < n_lines; ++l) {
    chain_length[find_root(parent, l)] += arc[l].back();
    ++chain_size[find_root(parent, l)];
  }
  // Counts n = round(mean chain length / step); the cells are not rectangles (Σ n·m over-counts
  // area / h²), so the step is rescaled a few times towards the target, the closest kept.
  const auto assign = [&](double step) {
    for (int l = 0; l < n_lines; ++l) {
      const int root = find_root(parent, l);
      count[l] = static_cast<int>(std::clamp(std::round(chain_length[root] / chain_size[root] / step), 1.0, 1e6));
    }
    double total = 0.0;
    for (Eigen::Index p = 0; p < patches; ++p) total += double(count[C.patch_sides(p, 0)]) * count[C.patch_sides(p, 1)];
    return total;
  };
  double step = h, best_step = h, best_error = std::numeric_limits<double>::infinity();
  for (int iteration = 0; iteration < 6; ++iteration) {
    const double total = assign(step);
    if (std::abs(total - target_quads) < best_error) best_error = std::abs(total - target_quads), best_step = step;
    step *= std::sqrt(total / target_quads);
  }
  assign(best_step);
  return out;
}

/// Cell p's own harmonic map (step 3 cell by cell): the cell (its faces `faces`) cut out as a disk
/// and mapped by a mean-value harmonic map (parametrization::harmonic) onto the unit square, side k
/// (line patch_sides(p, k), from corner k to k + 1) onto the square's side k by arc length. Convex
/// boundary and positive mean-value weights make the map a bijection (Floater 2003), so every
/// face's Jacobian is orientation-preserving. `local` (#V, all −1) is scratch, left all −1.
struct CellMap {
  VertexMatrix V;                 ///< the cell's vertices (local indices)
  FaceMatrix F;                   ///< the cell's faces, corners as in S.F, local vertex indices
  geometry::ParameterMatrix uv;   ///< per local vertex, in the unit square
  std::array<bool, 4> forward{};  ///< side k runs along its line's vertex order
};

CellMap map_cell(const Surface& S, const MorseSmaleComplex& C, const LineCounts& counts, Eigen::Index p,
                 const std::vector<int>& faces, std::vector<int>& local) {
  const auto& lines = C.lines;
  const auto& arc = counts.arc;
  static const std::array<Eigen::RowVector2d, 4> square{Eigen::RowVector2d(0, 0), Eigen::RowVector2d(1, 0),
                                                        Eigen::RowVector2d(1, 1), Eigen::RowVector2d(0, 1)};
  CellMap out;
  std::vector<int> global;
  out.F.resize(faces.size(), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const int v = S.F(faces[i], k);
      if (local[v] < 0) local[v] = static_cast<int>(global.size()), global.push_back(v);
      out.F(i, k) = local[v];
    }
  }
  out.V.resize(global.size(), 3);
  for (std::size_t i = 0; i < global.size(); ++i) out.V.row(i) = S.V.row(global[i]);
  parametrization::BoundaryMap boundary;
  for (int k = 0; k < 4; ++k) {
    const int l = C.patch_sides(p, k);
    out.forward[k] = lines[l].front() == C.patch_corners(p, k);
    const int length = static_cast<int>(lines[l].size());
    for (int i = 0; i + 1 < length; ++i) {
      const int at = out.forward[k] ? i : length - 1 - i;
      const double t = out.forward[k] ? arc[l][at] / arc[l].back() : 1.0 - arc[l][at] / arc[l].back();
      boundary.indices.push_back(local[lines[l][at]]);
      boundary.uv.conservativeResize(boundary.uv.rows() + 1, 2);
      boundary.uv.row(boundary.uv.rows() - 1) = (1 - t) * square[k] + t * square[(k + 1) % 4];
    }
  }
  out.uv = parametrization::harmonic(out.V, out.F, boundary, parametrization::HarmonicWeights::mean_value);
  for (const int v : global) local[v] = -1;
  return out;
}

/// Steps 3 and 4 cell by cell: harmonic maps of the cells and their conforming grids.
SpectralQuadrangulation cell_grids(const Surface& S, const MorseSmaleComplex& C, const LineCounts& counts,
                                   const Progress& progress) {
  const auto& lines = C.lines;
  const int n_lines = static_cast<int>(lines.size());
  const Eigen::Index patches = C.patch_corners.rows();
  const auto& arc = counts.arc;
  const auto& count = counts.count;
  SpectralQuadrangulation out;
  std::vector<Eigen::RowVector3d> nodes;
  std::vector<int> node_of_vertex(S.V.rows(), -1);
  for (const auto& line : lines)
    for (const int v : {line.front(), line.back()})
      if (node_of_vertex[v] < 0) node_of_vertex[v] = static_cast<int>(nodes.size()), nodes.push_back(S.V.row(v));
  std::vector<int> line_start(n_lines);
  for (int l = 0; l < n_lines; ++l) {
    line_start[l] = static_cast<int>(nodes.size());
    std::size_t k = 1;
    for (int i = 1; i < count[l]; ++i) {
      const double t = arc[l].back() * i / count[l];
      while (k + 1 < arc[l].size() && arc[l][k] < t) ++k;
      const double span = arc[l][k] - arc[l][k - 1];
      const double w = span > 0 ? std::clamp((t - arc[l][k - 1]) / span, 0.0, 1.0) : 0.0;
      nodes.push_back((1 - w) * S.V.row(lines[l][k - 1]) + w * S.V.row(lines[l][k]));
    }
  }
  const auto line_node = [&](int l, int t) {
    if (t == 0) return node_of_vertex[lines[l].front()];
    if (t == count[l]) return node_of_vertex[lines[l].back()];
    return line_start[l] + t - 1;
  };

  std::vector<std::vector<int>> patch_faces(patches);
  for (Eigen::Index face = 0; face < S.F.rows(); ++face) patch_faces[C.face_patch[face]].push_back(static_cast<int>(face));
  std::vector<int> local(S.V.rows(), -1);
  std::vector<std::array<int, 4>> quads;
  std::vector<int> quad_patch;
  out.patch_corners.resize(patches, 4);
  for (Eigen::Index p = 0; p < patches; ++p) {
    progress.report(static_cast<double>(p) / patches, "harmonic maps of the cells");
    const CellMap map = map_cell(S, C, counts, p, patch_faces[p], local);
    const VertexMatrix& Vp = map.V;
    const FaceMatrix& Fp = map.F;
    const geometry::ParameterMatrix& uv = map.uv;
    const auto& forward = map.forward;
    std::array<int, 4> side_count{};
    for (int k = 0; k < 4; ++k) {
      side_count[k] = count[C.patch_sides(p, k)];
      out.patch_corners(p, k) = node_of_vertex[C.patch_corners(p, k)];
    }

    const int nu = side_count[0], nv = side_count[1];
    const auto side_node = [&](int k, int index) {
      const int l = C.patch_sides(p, k);
      return line_node(l, forward[k] ? index : count[l] - index);
    };
    // Interior grid points: located in the map's triangles (the one with the largest smallest
    // barycentric coordinate, so points on edges get one answer).
    const int inner = std::max(0, nu - 1) * std::max(0, nv - 1);
    std::vector<double> best(inner, -std::numeric_limits<double>::infinity());
    std::vector<Eigen::RowVector3d> position(inner);
    for (Eigen::Index t = 0; t < Fp.rows(); ++t) {
      const Eigen::RowVector2d a = uv.row(Fp(t, 0)), b = uv.row(Fp(t, 1)), c = uv.row(Fp(t, 2));
      const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      if (!(std::abs(area) > 0)) continue;
      const double eps = 1e-9;
      const int i0 = std::max(1, static_cast<int>(std::ceil((std::min({a.x(), b.x(), c.x()}) - eps) * nu)));
      const int i1 = std::min(nu - 1, static_cast<int>(std::floor((std::max({a.x(), b.x(), c.x()}) + eps) * nu)));
      const int j0 = std::max(1, static_cast<int>(std::ceil((std::min({a.y(), b.y(), c.y()}) - eps) * nv)));
      const int j1 = std::min(nv - 1, static_cast<int>(std::floor((std::max({a.y(), b.y(), c.y()}) + eps) * nv)));
      for (int i = i0; i <= i1; ++i) {
        for (int j = j0; j <= j1; ++j) {
          const Eigen::RowVector2d q(static_cast<double>(i) / nu, static_cast<double>(j) / nv);
          const double wa = ((b - q).x() * (c - q).y() - (b - q).y() * (c - q).x()) / area;
          const double wb = ((c - q).x() * (a - q).y() - (c - q).y() * (a - q).x()) / area;
          const double wc = 1.0 - wa - wb;
          const double worst = std::min({wa, wb, wc});
          const int index = (i - 1) * (nv - 1) + (j - 1);
          if (worst > best[index] && worst > -1e-6) {
            best[index] = worst;
            position[index] = wa * Vp.row(Fp(t, 0)) + wb * Vp.row(Fp(t, 1)) + wc * Vp.row(Fp(t, 2));
          }
        }
      }
    }
    const int interior_start = static_cast<int>(nodes.size());
    for (int index = 0; index < inner; ++index) {
      if (!(best[index] > -1e-6))
        throw SolverError("spectral_quadrangulate: a grid point of cell " + std::to_string(p) +
                          " is outside its harmonic map (a folded map)");
      nodes.push_back(position[index]);
    }
    const auto grid_node = [&](int i, int j) {
      if (j == 0) return side_node(0, i);
      if (j == nv) return side_node(2, nu - i);
      if (i == 0) return side_node(3, nv - j);
      if (i == nu) return side_node(1, j);
      return interior_start + (i - 1) * (nv - 1) + (j - 1);
    };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) {
        quads.push_back({grid_node(i, j), grid_node(i + 1, j), grid_node(i + 1, j + 1), grid_node(i, j + 1)});
        quad_patch.push_back(static_cast<int>(p));
      }
  }
  out.V.resize(nodes.size(), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) out.V.row(i) = nodes[i];
  out.Q.resize(quads.size(), 4);
  out.quad_patch.resize(quads.size());
  for (std::size_t i = 0; i < quads.size(); ++i) {
    for (int k = 0; k < 4; ++k) out.Q(i, k) = quads[i][k];
    out.quad_patch[i] = quad_patch[i];
  }
  return out;
}

/// The coupled map's blends β of its cells' harmonic-map Jacobians with their conformal parts,
/// tried in turn (see coupled_grid).
constexpr std::array<double, 3> COUPLED_CONFORMAL_BLENDS{0.6, 0.3, 0.15};

/// What the coupled map made (besides the quads).
struct CoupledStats {
  Eigen::Index flipped_before = 0;  ///< triangles with det ≤ 0 in (u, v) as first solved
  Eigen::Index flipped_after = 0;   ///< after the stiffening repair
  int repair_rounds = 0;
  double conformal_blend = 0;       ///< β of the map extracted (COUPLED_CONFORMAL_BLENDS)
  bool complete = false;            ///< the extraction covered the surface with the input's χ
};

/// Steps 3 and 4 coupled (Dong et al. 2006, §5: the global relaxation): one seamless
/// parametrization of all cells. Cell p's chart is the rectangle [0, n] × [0, m] of its line
/// counts (one unit per quad edge), its corners max, saddle, min, saddle held at (0, 0), (n, 0),
/// (n, m), (0, m). The mesh is cut along the lines: a vertex inside a cell has one (u, v), a
/// vertex inside a line one per side, related by the line's transition function (the rotation by
/// a multiple of π/2 and the integer translation that take the side in one chart onto the same
/// side in the other, exact since both have the line's count), so lines are free to move and
/// iso-lines cross them smoothly. The energy Σ_f A_f (‖∇u − u*_f‖² + ‖∇v − v*_f‖²) over the cut
/// mesh (MIQ's, detail::assemble_energy), its targets the cells' own harmonic maps blended with
/// their conformal parts (COUPLED_CONFORMAL_BLENDS, below), with the unknowns of the
/// lower-numbered cell of each line kept, is one sparse SPD system (CHOLMOD); flipped triangles are
/// repaired by stiffening as in MIQ; the integer grid is then extracted by extract_quads (QEx).
/// Cell corners sit on integer points, so the extremum corners are the mesh's only possible
/// irregular vertices. Failure modes: flips left by every blend (then the extraction is usually
/// incomplete and the caller falls back to cell_grids); SolverError for a line that does not
/// separate two cells, sides of different counts, or a failed factorization.
SpectralQuadrangulation coupled_grid(const Surface& S, const MorseSmaleComplex& C, const LineCounts& counts,
                                     const Progress& progress, CoupledStats& stats) {
  const auto& lines = C.lines;
  const auto& count = counts.count;
  const int n_lines = static_cast<int>(lines.size());
  const Eigen::Index patches = C.patch_corners.rows(), m = S.F.rows(), n = S.V.rows();
  using Matrix2 = Eigen::Matrix2d;
  using Vector2 = Eigen::Vector2d;
  // The charts' corners.
  std::vector<std::array<Vector2, 4>> corner_uv(patches);
  for (Eigen::Index p = 0; p < patches; ++p) {
    const double a = count[C.patch_sides(p, 0)], b = count[C.patch_sides(p, 1)];
    corner_uv[p] = {Vector2(0, 0), Vector2(a, 0), Vector2(a, b), Vector2(0, b)};
  }
  // Each line's two sides (cell, side index) and the transition from the first cell's chart to
  // the second's: x ↦ R x + t.
  std::vector<std::vector<std::pair<int, int>>> sides(n_lines);
  for (Eigen::Index p = 0; p < patches; ++p)
    for (int k = 0; k < 4; ++k) sides[C.patch_sides(p, k)].emplace_back(static_cast<int>(p), k);
  std::vector<Matrix2> rotation(n_lines);
  std::vector<Vector2> translation(n_lines);
  for (int l = 0; l < n_lines; ++l) {
    if (sides[l].size() != 2 || sides[l][0].first == sides[l][1].first)
      throw SolverError("spectral_quadrangulate: line " + std::to_string(l) + " does not separate two cells");
    std::sort(sides[l].begin(), sides[l].end());
    const auto [p, kp] = sides[l][0];
    const auto [q, kq] = sides[l][1];
    // Side kp of p runs from its corner kp to kp + 1; the same line in q runs the other way.
    const Vector2 from = corner_uv[p][(kp + 1) % 4] - corner_uv[p][kp];
    const Vector2 to = corner_uv[q][kq] - corner_uv[q][(kq + 1) % 4];
    Matrix2 R = Matrix2::Identity();
    const Matrix2 quarter = (Matrix2() << 0, -1, 1, 0).finished();
    int turns = 0;
    while (turns < 4 && (R * from - to).cwiseAbs().maxCoeff() > 0.5) R = quarter * R, ++turns;
    if (turns == 4) throw SolverError("spectral_quadrangulate: the two sides of line " + std::to_string(l) + " have different counts");
    rotation[l] = R;
    translation[l] = corner_uv[q][(kq + 1) % 4] - R * corner_uv[p][kp];
  }
  // Vertex roles: a corner (held), inside a line (its first cell's chart holds the unknowns), or
  // inside a cell.
  std::vector<int> line_of(n, -1);
  for (int l = 0; l < n_lines; ++l)
    for (std::size_t k = 1; k + 1 < lines[l].size(); ++k) line_of[lines[l][k]] = l;
  const auto is_corner = [&](int v) { return C.vertex_type[v] != static_cast<int>(CriticalType::regular); };
  std::vector<int> unknown(n, -1);
  int n_free = 0;
  for (Eigen::Index v = 0; v < n; ++v)
    if (!is_corner(static_cast<int>(v))) unknown[v] = n_free++;
  // Copies: one per (cell, vertex) of the cut mesh; x_copy = A y_unknown + c.
  std::unordered_map<std::uint64_t, int> copy_of;
  FaceMatrix Fc(m, 3);
  std::vector<int> copy_vertex, copy_patch;
  for (Eigen::Index f = 0; f < m; ++f) {
    const int p = C.face_patch[f];
    for (int k = 0; k < 3; ++k) {
      const int v = S.F(f, k);
      const auto [it, inserted] = copy_of.emplace((static_cast<std::uint64_t>(p) << 32) | static_cast<std::uint32_t>(v),
                                                  static_cast<int>(copy_vertex.size()));
      if (inserted) copy_vertex.push_back(v), copy_patch.push_back(p);
      Fc(f, k) = it->second;
    }
  }
  const Eigen::Index nc = static_cast<Eigen::Index>(copy_vertex.size());
  std::vector<Eigen::Triplet<double>> z_triplets;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(2 * nc);
  VertexMatrix P(nc, 3);
  for (Eigen::Index i = 0; i < nc; ++i) {
    const int v = copy_vertex[i], p = copy_patch[i];
    P.row(i) = S.V.row(v);
    if (is_corner(v)) {
      int k = 0;
      while (k < 4 && C.patch_corners(p, k) != v) ++k;
      if (k == 4) throw SolverError("spectral_quadrangulate: critical vertex " + std::to_string(v) + " is no corner of its cell");
      c.segment<2>(2 * i) = corner_uv[p][k];
      continue;
    }
    const int l = line_of[v];
    Matrix2 A = Matrix2::Identity();
    if (l >= 0 && p != sides[l][0].first) {
      A = rotation[l];
      c.segment<2>(2 * i) = translation[l];
    }
    for (int r = 0; r < 2; ++r)
      for (int s = 0; s < 2; ++s)
        if (A(r, s) != 0) z_triplets.emplace_back(2 * i + r, 2 * unknown[v] + s, A(r, s));
  }
  Eigen::SparseMatrix<double> Z(2 * nc, 2 * n_free), K;
  Z.setFromTriplets(z_triplets.begin(), z_triplets.end());
  // The target gradients: each face's Jacobian J in its cell's own harmonic map (map_cell, scaled
  // onto the chart [0, n] × [0, m]), orientation-preserving everywhere, blended with its conformal
  // part √det J · R (J = R S, the polar decomposition) as (1 − β) J + β √det J · R. The cell maps
  // agree along every line (both sides by arc length), so at β = 0 they are themselves the
  // minimizer (the per-cell maps, kinked across the lines); β > 0 makes the target non-integrable
  // and the solve smooths the iso-lines across the lines. The Dirichlet energy alone (zero
  // target, the previous coupled map, with only the corners to hold it) folded 1,334 triangles on
  // spot and 495 on kitten at 2,000 quads (2026-12-04), 966 of spot's nearest a saddle corner.
  std::vector<Eigen::Matrix2d> jacobian(m, Eigen::Matrix2d::Zero());
  std::vector<std::array<Eigen::Vector3d, 2>> frame(m);
  std::vector<char> has_target(m, 0);
  {
    std::vector<std::vector<int>> patch_faces(patches);
    for (Eigen::Index f = 0; f < m; ++f) patch_faces[C.face_patch[f]].push_back(static_cast<int>(f));
    std::vector<int> local(n, -1);
    for (Eigen::Index p = 0; p < patches; ++p) {
      const CellMap map = map_cell(S, C, counts, p, patch_faces[p], local);
      const double width = count[C.patch_sides(p, 0)], height = count[C.patch_sides(p, 1)];
      for (std::size_t i = 0; i < patch_faces[p].size(); ++i) {
        const int f = patch_faces[p][i];
        const Eigen::Vector3d q[3] = {S.V.row(S.F(f, 0)), S.V.row(S.F(f, 1)), S.V.row(S.F(f, 2))};
        const Eigen::Vector3d cross = (q[1] - q[0]).cross(q[2] - q[0]);
        const double double_area = cross.norm();
        if (!(double_area > 0)) continue;
        const Eigen::Vector3d normal = cross / double_area;
        Eigen::Vector3d gu = Eigen::Vector3d::Zero(), gv = Eigen::Vector3d::Zero();
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector3d gradient = normal.cross(q[(k + 2) % 3] - q[(k + 1) % 3]) / double_area;
          gu += width * map.uv(map.F(i, k), 0) * gradient;
          gv += height * map.uv(map.F(i, k), 1) * gradient;
        }
        frame[f][0] = (q[1] - q[0]).normalized();
        frame[f][1] = normal.cross(frame[f][0]);
        jacobian[f] << gu.dot(frame[f][0]), gu.dot(frame[f][1]), gv.dot(frame[f][0]), gv.dot(frame[f][1]);
        has_target[f] = 1;
      }
    }
  }
  VertexMatrix target_u = VertexMatrix::Zero(m, 3), target_v = VertexMatrix::Zero(m, 3);
  const auto set_targets = [&](double beta) {
    for (Eigen::Index f = 0; f < m; ++f) {
      if (!has_target[f]) continue;
      Eigen::Matrix2d J = jacobian[f];
      const Eigen::JacobiSVD<Eigen::Matrix2d> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Eigen::Matrix2d R = svd.matrixU() * svd.matrixV().transpose();
      if (R.determinant() > 0) J = (1 - beta) * J + beta * std::sqrt(svd.singularValues().prod()) * R;
      target_u.row(f) = (J(0, 0) * frame[f][0] + J(0, 1) * frame[f][1]).transpose();
      target_v.row(f) = (J(1, 0) * frame[f][0] + J(1, 1) * frame[f][1]).transpose();
    }
  };
  detail::Cholesky solver;
  detail::configure_cholmod(solver);
  bool analyzed = false;
  Eigen::VectorXd rhs;
  const auto solve = [&](const Eigen::VectorXd& w) {
    detail::assemble_energy(P, Fc, target_u, target_v, w, 2 * nc, K, rhs);
    const Eigen::SparseMatrix<double> H = Z.transpose() * K * Z;
    const Eigen::VectorXd g = Z.transpose() * (rhs - K * c);
    if (!analyzed) solver.analyzePattern(H), analyzed = true;
    solver.factorize(H);
    if (solver.info() != Eigen::Success) throw SolverError("spectral_quadrangulate: CHOLMOD failed to factorize the coupled map");
    const Eigen::VectorXd x = Z * Eigen::VectorXd(solver.solve(g)) + c;
    if (!x.allFinite()) throw SolverError("spectral_quadrangulate: the coupled map is not finite");
    CornerUV uv(m, 6);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) uv(f, 2 * k) = x[2 * Fc(f, k)], uv(f, 2 * k + 1) = x[2 * Fc(f, k) + 1];
    return uv;
  };
  // The blends, smoothest first, until one is flip-free after the stiffening repair (the map with
  // the fewest flips left is kept). β = 0 is not tried: it is cell_grids' map. Measured
  // 2026-12-04 at 2,000 quads (flips as solved → after repair): β = 0.6 spot 262 → 45, kitten
  // 127 → 0; β = 0.3 spot 42 → 0, rocker-arm 322 → 14, fertility 129 → 2; β = 0.15 rocker-arm
  // 122 → 0, fertility 41 → 0.
  CornerUV uv;
  bool first = true;
  for (const double beta : COUPLED_CONFORMAL_BLENDS) {
    progress.report(0.0, "coupled map of the cells");
    set_targets(beta);
    CornerUV trial = solve(Eigen::VectorXd::Ones(m));
    std::vector<char> trial_flipped;
    const Eigen::Index before = detail::count_flipped(trial, &trial_flipped);
    Eigen::Index after = before;
    const int rounds = detail::repair_by_stiffening(
        S.F, n, 10, 5.0, Eigen::VectorXd::Ones(m), trial, after, trial_flipped, solve,
        [&](int round) { progress.report(0.2 + 0.03 * round, "coupled map: repair"); });
    if (first || after < stats.flipped_after) {
      stats.flipped_before = before, stats.flipped_after = after, stats.repair_rounds = rounds;
      stats.conformal_blend = beta;
      uv = std::move(trial);
      first = false;
    }
    if (stats.flipped_after == 0) break;
  }
  progress.report(0.5, "quad extraction");
  const Eigen::Map<const CornerUVMatrix> corners(uv.data(), 3 * m, 2);
  QuadExtraction grid = extract_quads(S.V, S.F, corners, progress.subrange(0.5, 1.0));
  stats.complete = grid.report.complete();
  SpectralQuadrangulation out;
  out.V = std::move(grid.V);
  out.Q = std::move(grid.Q);
  // Each cell corner's node: the node found in a face at that corner, at its (u, v) there.
  std::vector<int> corner_node(n, -1);
  for (Eigen::Index i = 0; i < grid.node_face.size(); ++i) {
    const int f = grid.node_face[i];
    for (int k = 0; k < 3; ++k) {
      const int v = S.F(f, k);
      if (is_corner(v) && uv(f, 2 * k) == grid.node_uv(i, 0) && uv(f, 2 * k + 1) == grid.node_uv(i, 1)) corner_node[v] = static_cast<int>(i);
    }
  }
  out.patch_corners.resize(patches, 4);
  for (Eigen::Index p = 0; p < patches; ++p) {
    for (int k = 0; k < 4; ++k) {
      int& node = corner_node[C.patch_corners(p, k)];
      if (node < 0 && out.V.rows() > 0)  // not found by its (u, v) (a mirrored read): the nearest node
        (out.V.rowwise() - S.V.row(C.patch_corners(p, k))).rowwise().squaredNorm().minCoeff(&node);
      out.patch_corners(p, k) = node;
    }
  }
  // A quad's cell: the one holding most of its corners' faces (ties: the lowest).
  out.quad_patch.resize(out.Q.rows());
  for (Eigen::Index q = 0; q < out.Q.rows(); ++q) {
    std::array<int, 4> cell{};
    for (int k = 0; k < 4; ++k) cell[k] = C.face_patch[grid.node_face[out.Q(q, k)]];
    std::sort(cell.begin(), cell.end());
    int best = cell[0], best_run = 0;
    for (int k = 0; k < 4;) {
      int j = k;
      while (j < 4 && cell[j] == cell[k]) ++j;
      if (j - k > best_run) best_run = j - k, best = cell[k];
      k = j;
    }
    out.quad_patch[q] = best;
  }
  return out;
}

/// 0-dimensional persistence of the extrema of f (ties broken by index, as `above`): sweeping the
/// vertices upwards (maxima: downwards), a vertex with no swept neighbour starts a component at
/// its minimum; where two components meet, the one of the higher minimum dies there, its
/// persistence |f(meeting vertex) − f(minimum)|. Per vertex: that persistence at minima (maxima),
/// +∞ at the global one, −1 elsewhere.
std::vector<double> extremum_persistence(const Rings& rings, const Eigen::VectorXd& f, bool maxima) {
  const int n = static_cast<int>(f.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return maxima ? above(f, a, b) : above(f, b, a); });
  std::vector<int> parent(n, -1), oldest(n, -1);
  std::vector<double> persistence(n, -1.0);
  std::vector<char> swept(n, 0);
  for (const int v : order) {
    swept[v] = 1;
    parent[v] = v;
    oldest[v] = v;
    bool joined = false;
    for (int j = 0; j < rings.size(v); ++j) {
      const int u = rings.begin(v)[j];
      if (!swept[u]) continue;
      const int ru = find_root(parent, u), rv = find_root(parent, v);
      if (!joined) {
        parent[rv] = ru;  // v joins its first swept neighbour's component
        joined = true;
        continue;
      }
      if (ru == rv) continue;
      // The younger extremum (swept later) dies at v.
      const bool u_older = maxima ? above(f, oldest[ru], oldest[rv]) : above(f, oldest[rv], oldest[ru]);
      const int survivor = u_older ? ru : rv, dying = u_older ? rv : ru;
      persistence[oldest[dying]] = std::abs(f[v] - f[oldest[dying]]);
      parent[dying] = survivor;
    }
    if (!joined) persistence[v] = std::numeric_limits<double>::infinity();  // a new extremum, until it dies
  }
  return persistence;
}

/// The extrema kept by persistence-based simplification: of each kind those with persistence at
/// least `threshold` (the global ones always), then of both kinds together the `limit` of highest
/// persistence (≥ 1 of each kind). Per vertex 1 when kept.
std::vector<char> persistent_extrema(const Rings& rings, const Eigen::VectorXd& f, double threshold, Eigen::Index limit) {
  const std::vector<double> up = extremum_persistence(rings, f, true), down = extremum_persistence(rings, f, false);
  const int n = static_cast<int>(f.size());
  std::vector<std::pair<double, int>> ranked;
  std::vector<char> keep(n, 0);
  for (int v = 0; v < n; ++v) {
    const double p = std::max(up[v], down[v]);
    if (std::isinf(p)) keep[v] = 1;
    else if (p >= threshold) ranked.emplace_back(p, v);
  }
  std::sort(ranked.begin(), ranked.end(), std::greater<>());
  Eigen::Index kept = 2;
  for (const auto& [p, v] : ranked)
    if (kept < limit) keep[v] = 1, ++kept;
  return keep;
}

/// Topological simplification of f to the extrema in `keep` (Tierny and Pascucci, "Generalized
/// topological simplification of scalar fields on surfaces", 2012): a sweep upwards from the kept
/// minima raises every vertex reached below the sweep's level just above it, so that each vertex
/// but a kept minimum has a lower neighbour; then the same downwards from the kept maxima; repeated
/// until no other extremum is left (each sweep can create extrema of the other kind). The values
/// change only in the cancelled extrema's basins. Returns the number of sweep rounds, or −1 when
/// 12 rounds did not converge (f is then left as it was).
int simplify_to(const Rings& rings, Eigen::VectorXd& f, const std::vector<char>& keep) {
  const int n = static_cast<int>(f.size());
  const double delta = std::max(f.maxCoeff() - f.minCoeff(), 1e-300) * 1e-9;
  Eigen::VectorXd g = f;
  std::vector<char> visited(n);
  Eigen::VectorXi type, multiplicity;
  const auto extra_extrema = [&] {
    classify(rings, g, type, multiplicity);
    int extra = 0;
    for (int v = 0; v < n; ++v)
      extra += (type[v] == static_cast<int>(CriticalType::maximum) || type[v] == static_cast<int>(CriticalType::minimum)) &&
               !keep[v];
    return extra;
  };
  for (int round = 0; round < 12; ++round) {
    if (extra_extrema() == 0) {
      f = g;
      return round;
    }
    for (const bool minima : {true, false}) {
      const CriticalType seed = minima ? CriticalType::minimum : CriticalType::maximum;
      // A min-heap on (s·g, index), s = +1 for the upward sweep, −1 downwards.
      const double s = minima ? 1.0 : -1.0;
      using Item = std::pair<double, int>;
      const auto later = [&](const Item& a, const Item& b) {
        return a.first > b.first || (a.first == b.first && (minima ? a.second > b.second : a.second < b.second));
      };
      std::priority_queue<Item, std::vector<Item>, decltype(later)> heap(later);
      std::fill(visited.begin(), visited.end(), 0);
      for (int v = 0; v < n; ++v)
        if (keep[v] && type[v] == static_cast<int>(seed)) heap.push({s * g[v], v});
      double level = -std::numeric_limits<double>::infinity();
      while (!heap.empty()) {
        const auto [value, v] = heap.top();
        heap.pop();
        if (visited[v]) continue;
        visited[v] = 1;
        if (!(s * g[v] > level)) g[v] = s * (level + delta);
        level = s * g[v];
        for (int j = 0; j < rings.size(v); ++j) {
          const int u = rings.begin(v)[j];
          if (!visited[u]) heap.push({s * g[u], u});
        }
      }
      if (minima) classify(rings, g, type, multiplicity);
    }
  }
  return -1;
}

}  // namespace

MorseSmaleComplex morse_smale_complex(const VertexRef& input_V, const FaceRef& F,
                                      const Eigen::Ref<const Eigen::VectorXd>& f) {
  const auto normalized = parametrization::detail::normalized(input_V);
  const auto checked = parametrization::detail::check_mesh(normalized.V, F, parametrization::detail::Requirement::any,
                                                           "morse_smale_complex");
  if (!checked.boundary_loops.empty())
    throw InputError("morse_smale_complex: the mesh has " + std::to_string(checked.boundary_loops.size()) +
                     " boundary loop(s); the complex is traced on closed surfaces");
  if (f.size() != input_V.rows())
    throw InputError("morse_smale_complex: f has " + std::to_string(f.size()) + " values for " +
                     std::to_string(input_V.rows()) + " vertices");
  for (Eigen::Index i = 0; i < f.size(); ++i)
    if (!std::isfinite(f[i])) throw InputError("morse_smale_complex: f[" + std::to_string(i) + "] is not finite");
  Surface S{normalized.V, F, f};
  const Rings rings = one_rings(S.F, static_cast<int>(S.V.rows()));
  int stuck = -1;
  return trace_complex(S, rings, stuck, 0, false);
}

SpectralQuadrangulation spectral_quadrangulate(const VertexRef& input_V, const FaceRef& F,
                                               const SpectralOptions& options, const Progress& progress) {
  const auto normalized = parametrization::detail::normalized(input_V);
  const auto checked = parametrization::detail::check_mesh(normalized.V, F, parametrization::detail::Requirement::any,
                                                           "spectral_quadrangulate");
  if (!checked.boundary_loops.empty())
    throw InputError("spectral_quadrangulate: the mesh has " + std::to_string(checked.boundary_loops.size()) +
                     " boundary loop(s); spectral quadrangulation handles closed surfaces");
  const Eigen::Index n = input_V.rows();
  if (options.target_faces < 0 || options.target_faces > (Eigen::Index(1) << 24))
    throw InputError("spectral_quadrangulate: target_faces must be in [1, 2^24]");
  if (options.target_patches < 0 || options.target_patches > 100000)
    throw InputError("spectral_quadrangulate: target_patches must be in [1, 100000]");
  if (options.eigenvector < 0 || options.eigenvector >= n - 1)
    throw InputError("spectral_quadrangulate: eigenvector = " + std::to_string(options.eigenvector) +
                     " outside [1, #V − 2] = [1, " + std::to_string(n - 2) + "]");
  const VertexMatrix& V = normalized.V;
  double area = 0.0, edges = 0.0;
  for (Eigen::Index face = 0; face < F.rows(); ++face) {
    const Eigen::RowVector3d a = V.row(F(face, 0)), b = V.row(F(face, 1)), c = V.row(F(face, 2));
    area += 0.5 * (b - a).cross(c - a).norm();
    edges += (b - a).norm() + (c - b).norm() + (a - c).norm();
  }
  const double h = options.target_faces > 0 ? std::sqrt(area / options.target_faces)
                                            : 2.0 * edges / (3.0 * F.rows());
  const double quads = area / (h * h);
  const Eigen::Index target_patches =
      options.target_patches > 0 ? options.target_patches
                                 : std::clamp<Eigen::Index>(std::llround(quads / 25.0), 8, 240);
  // Eigenpairs up to the one asked for, or enough that some have ~target_patches cells (the
  // count grows about linearly with the index; a band of indices around it is tried).
  const Eigen::Index k = options.eigenvector > 0
                             ? options.eigenvector + 1
                             : std::min<Eigen::Index>(n - 1, std::clamp<Eigen::Index>(target_patches / 2 + 8, 12, 128));
  progress.report(0.0, "eigenpairs");
  const geometry::LaplacianEigenpairs eigen =
      geometry::laplacian_eigenpairs(input_V, F, k, geometry::MassMatrixType::voronoi, progress.subrange(0.0, 0.6));
  const Rings rings = one_rings(FaceMatrix(F), static_cast<int>(n));
  // Persistence-based simplification (§5.2.1, as Dong et al.): extrema of persistence below
  // 3% of the function's range are cancelled with their saddles, and of the rest the most
  // persistent are kept, as many as give about target_patches cells (a quad complex of E extrema
  // and simple saddles has 2(E − χ) cells).
  const Eigen::Index euler = static_cast<Eigen::Index>(checked.euler_characteristic);
  const Eigen::Index extrema_limit = std::max<Eigen::Index>(3, target_patches / 2 + euler);
  std::vector<std::vector<char>> kept(k);
  const auto keep_for = [&](Eigen::Index i) -> const std::vector<char>& {
    if (kept[i].empty()) {
      const auto column = eigen.vectors.col(i);
      kept[i] = persistent_extrema(rings, column, 0.03 * (column.maxCoeff() - column.minCoeff()), extrema_limit);
    }
    return kept[i];
  };
  std::vector<Eigen::Index> candidates;
  std::vector<Eigen::Index> cells(k, 0);  // predicted cells per eigenvector: 2 (kept extrema − χ)
  if (options.eigenvector > 0) {
    candidates.push_back(options.eigenvector);
  } else {
    for (Eigen::Index i = 1; i < k; ++i) {
      const std::vector<char>& keep = keep_for(i);
      cells[i] = 2 * (std::count(keep.begin(), keep.end(), char(1)) - euler);
      if (cells[i] > 0) candidates.push_back(i);
    }
    std::stable_sort(candidates.begin(), candidates.end(), [&](Eigen::Index a, Eigen::Index b) {
      return std::abs(cells[a] - target_patches) < std::abs(cells[b] - target_patches);
    });
    if (candidates.size() > 40) candidates.resize(40);
  }
  progress.report(0.6, "Morse-Smale complex");
  std::string last_problem = "no eigenvector among the first " + std::to_string(k) + " has a saddle";
  Eigen::Index tried = 0, traced_faces = 0;
  // Candidate `index` traced at levels first_level .. last_level of refinement (the levels below
  // are subdivided without tracing): its quads when a complex there is complete and maps, else
  // nothing (last_problem says why); `deferred` when it was still stuck at last_level < 2, so a
  // deeper level might complete it.
  //
  // `keep` (null: keep_for(index)) are the extrema kept by the simplification; `cancellations`
  // counts the rounds of two-cell cancellation made before this call (see below).
  std::function<std::optional<SpectralQuadrangulation>(Eigen::Index, int, int, bool&, const std::vector<char>*, int)>
      attempt;
  attempt = [&](Eigen::Index index, int first_level, int last_level, bool& deferred,
                const std::vector<char>* keep, int cancellations) -> std::optional<SpectralQuadrangulation> {
    deferred = false;
    if (keep == nullptr) keep = &keep_for(index);
    Eigen::VectorXd function = eigen.vectors.col(index);
    Eigen::VectorXi before_type, before_multiplicity;
    classify(rings, function, before_type, before_multiplicity);
    const Eigen::Index extrema_before =
        (before_type.array() == static_cast<int>(CriticalType::maximum)).count() +
        (before_type.array() == static_cast<int>(CriticalType::minimum)).count();
    const int rounds = simplify_to(rings, function, *keep);
    Surface S = star_split(Surface{V, FaceMatrix(F), function});
    for (int level = 0; level < first_level; ++level) S = star_split(subdivide(S));
    for (int level = first_level;; ++level) {
      const Rings surface_rings = one_rings(S.F, static_cast<int>(S.V.rows()));
      bool stuck = false;
      MorseSmaleComplex C;
      Surface T;
      for (int order = 0; order < 4; ++order) {
        Surface work = S;
        int stuck_saddle = -1;
        traced_faces += S.F.rows();
        C = trace_complex(work, surface_rings, stuck_saddle, order, true);
        stuck = stuck || stuck_saddle >= 0;
        if (C.complete()) {
          T = std::move(work);
          if (split_chords(T, C) > 0) build_cells(T, C);
        }
        if (C.complete()) break;
      }
      // An extremum that only two lines reach is a corner of two cells, each with an angle of
      // about 180° there that its map puts on a 90° corner of the square: the quads at it fold.
      // Such extrema are cancelled (dropped from the kept extrema, so the simplification removes
      // each with a saddle next to it) and the complex traced again at this level, while that
      // completes and maps (at most three rounds; otherwise this complex is kept).
      Eigen::Index two_cell = 0;
      if (C.complete()) {
        std::vector<int> lines_at(T.V.rows(), 0);
        for (const auto& line : C.lines) ++lines_at[line.back()];
        std::vector<char> fewer = *keep;
        Eigen::Index maxima_left = C.maxima, minima_left = C.minima, dropped = 0;
        for (Eigen::Index v = 0; v < n; ++v) {
          if (lines_at[v] != 2) continue;
          ++two_cell;
          const bool maximum = C.vertex_type[v] == static_cast<int>(CriticalType::maximum);
          Eigen::Index& left = maximum ? maxima_left : minima_left;
          if (cancellations < 3 && rounds >= 0 && fewer[v] && left > 1) fewer[v] = 0, --left, ++dropped;
        }
        if (dropped > 0) {
          bool still_stuck = false;
          if (auto fewer_cells = attempt(index, level, level, still_stuck, &fewer, cancellations + 1)) {
            fewer_cells->cancelled_two_cell_extrema += dropped;
            return fewer_cells;
          }
        }
      }
      if (C.complete()) {
        SpectralQuadrangulation out;
        out.two_cell_extrema = two_cell;
        const LineCounts counts = line_counts(T, C, h, quads);
        CoupledStats coupled;
        if (options.coupled) out = coupled_grid(T, C, counts, progress.subrange(0.65, 0.9), coupled);
        // Where the coupled map keeps flips its extraction cannot untangle (an incomplete grid),
        // this candidate's cells are mapped one by one instead.
        if (!coupled.complete) {
          try {
            out = cell_grids(T, C, counts, progress.subrange(0.65, 1.0));
          } catch (const SolverError& error) {  // a folded map: the next candidate
            last_problem = "eigenvector " + std::to_string(index) + ": " + error.what();
            return std::nullopt;
          }
        }
        out.coupled = coupled.complete;
        out.flipped_before = coupled.flipped_before;
        out.flipped_after = coupled.flipped_after;
        out.repair_rounds = coupled.repair_rounds;
        // Grid nodes that coincide (a degenerate map; 1e-12 of the unit-diagonal frame) make this
        // candidate fail.
        bool degenerate = false;
        for (Eigen::Index q = 0; q < out.Q.rows() && !degenerate; ++q)
          for (int c = 0; c < 4 && !degenerate; ++c)
            degenerate = !((out.V.row(out.Q(q, c)) - out.V.row(out.Q(q, (c + 1) % 4))).squaredNorm() > 1e-24);
        if (degenerate) {
          last_problem = "eigenvector " + std::to_string(index) + ": two grid nodes of a cell coincide";
          return std::nullopt;
        }
        out.V = normalized.frame.vertices_to_input(out.V, "spectral_quadrangulate: vertex");
        out.eigenvector = index;
        out.eigenvalue = eigen.values[index];
        out.maxima = C.maxima;
        out.minima = C.minima;
        out.saddles = C.saddles;
        out.multi_saddles = (C.saddle_multiplicity.array() > 1).count();
        out.saddle_vertices = (C.saddle_multiplicity.array() > 0).count();
        out.refinements = level;
        out.detours = C.detours;
        out.gap_routes = C.gap_routes;
        out.candidates_tried = tried;
        out.traced_faces = traced_faces;
        out.cancelled_extrema = extrema_before - C.maxima - C.minima;
        out.simplification_rounds = rounds;
        progress.report(1.0, "done");
        return out;
      }
      last_problem = "eigenvector " + std::to_string(index) + ": " + C.problem;
      if (!stuck || level == 2 || S.F.rows() * 4 > 4000000) return std::nullopt;
      if (level == last_level) {
        deferred = true;
        return std::nullopt;
      }
      S = star_split(subdivide(S));
      progress.report(0.6, "Morse-Smale complex");
    }
  };
  // Refinement is deferred past the candidates nearest the target: a candidate's level-1 and
  // level-2 traces (4 and 16 times the faces) are made only when no candidate completed at the
  // level before. Measured at 2,000 quads on spot, kitten, fertility, rocker-arm, cheburashka,
  // pmp-bunny and bumpy-cube: a level-2 trace took 75-85% of a failing candidate's time on
  // pmp-bunny (~1.5-2 s of ~2.3 s) and fertility and completed once in 65 tries (spot's first
  // candidate); pmp-bunny traced 25 candidates to level 2 before its 26th completed at level 0.
  // The candidates about as near the target as the first (|cells − target| at most the first's
  // plus 10% of its cells) keep all three levels at once, so that a coarser complex further down
  // the list does not replace theirs: rocker-arm's third candidate completes at level 1; with only
  // the first at full depth its 16th (34 cells instead of 48, 7 inverted quads instead of 1)
  // completed at level 0 instead. With this rule the seven meshes keep their eigenvectors.
  std::vector<Eigen::Index> deferred_candidates;
  const auto deviation = [&](Eigen::Index i) { return std::abs(cells[i] - target_patches); };
  for (std::size_t rank = 0; rank < candidates.size(); ++rank) {
    const Eigen::Index index = candidates[rank];
    const bool full_depth =
        rank == 0 || 10 * deviation(index) <= 10 * deviation(candidates.front()) + cells[candidates.front()];
    ++tried;
    bool deferred = false;
    if (auto out = attempt(index, 0, full_depth ? 2 : 0, deferred, nullptr, 0)) return std::move(*out);
    if (deferred) deferred_candidates.push_back(index);
  }
  for (int level = 1; level <= 2; ++level) {
    std::vector<Eigen::Index> still_stuck;
    for (const Eigen::Index index : deferred_candidates) {
      bool deferred = false;
      if (auto out = attempt(index, level, level, deferred, nullptr, 0)) return std::move(*out);
      if (deferred) still_stuck.push_back(index);
    }
    deferred_candidates.swap(still_stuck);
  }
  throw SolverError("spectral_quadrangulate: no complete Morse-Smale complex among " + std::to_string(tried) +
                    " eigenvector(s); " + last_problem);
}

}  // namespace meshsmith::quadrangulation
