// Dual loops (§5.3; Campen, Bommes & Kobbelt 2012), on the primal edge graph of a closed mesh.
//
// Direction classes. Away from singularities a cross field is locally combable, so every regular
// vertex gets a frame: class c at vertex v stands for class c + o_v(f) of the cross of each face f
// around v (o_v walked around the fan through the period jumps; at a regular vertex the walk
// closes, the monodromy being the index mod 4). A loop is a path of states (vertex, class); the
// edge v → w carries class c to c + o_v(f) − o_w(f) (f the face left of v → w, the same through
// the right face at regular vertices). Class c and c + 2 are one family traversed both ways, so
// "family" below is the parity of the class, transported the same way.
//
// Tracing. The metric of an edge v → w travelled in class c is |w − v|·sqrt(cos²δ + a² sin²δ),
// δ the angle between the edge and the cross direction (mean over the two faces of the edge),
// edges with |δ| above max_deviation are not taken (so a loop never turns back), and a factor
// 1 + 4·max(0, 1 − d/(spacing/2)) penalizes passing at distance d < spacing/2 of a loop of its
// own family. The loop through seed s in class c is the shortest path of states from (s, c) back to
// (s, c) (Dijkstra over 4#V states; 6 directions per vertex, so loops zig-zag within ±30° of
// the field, which the anisotropic cost keeps on average along it — the curriculum's "ellipse
// that grows fast along the field"). A vertex on a loop is entered only by a crossing move
// u → v → w: u and w on opposite sides of that loop at v and the class at v orthogonal to the
// loop's (or, with parallel_crossing_penalty ≥ 0, of its family at that extra cost: a loop that
// separates a dipole often has to cross a loop of its own family somewhere — on bumpy-cube four
// dipoles stayed together without it); vertices where two loops cross, loop edges and singular
// vertices are closed. A path that
// visits a vertex twice (a self-overlap) is rejected and the seed marked as tried.
//
// Regions are the face components across non-loop edges; χ of a region counts its faces, its
// edges (a loop edge once per side) and its vertex sectors (a loop vertex has one sector per pair
// of consecutive loop edges around it), so a region that touches itself at a vertex is counted as
// cut there. The dual: one vertex per region, one quad per crossing (the regions of its four
// sectors, counter-clockwise), checked for repeated corners, edges not shared by exactly two
// quads in opposite directions, vertices whose quads do not close into one fan, and χ. Layout
// vertices of valence 2 left when the selection stops are removed by dropping a loop at them
// (see "valence-2 layout vertices" below).
#include <meshsmith/quadrangulation/dual_loops.h>

#include "field_geometry.h"

#include <meshsmith/core/errors.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <string>
#include <utility>

namespace meshsmith::quadrangulation {

namespace {

using detail::FieldMesh;
using detail::kPi;
using detail::kQuarter;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

int mod4(int x) { return ((x % 4) + 4) % 4; }

/// The one-rings of a closed oriented manifold in counter-clockwise order and the vertex frames.
struct Rings {
  std::vector<int> begin;     ///< #V+1 offsets
  std::vector<int> neighbor;  ///< ring entry i of v: the vertex w_i
  std::vector<int> face;      ///< the face (v, w_i, w_{i+1}), left of v → w_i
  std::vector<int> edge;      ///< the undirected edge v – w_i
  std::vector<int> shift;     ///< class shift c_w − c_v along v → w_i
  std::vector<double> cost;   ///< 4 per entry: the metric of v → w_i in class c (∞: not taken)
  std::vector<int> corner_offset;  ///< 3#F: o_v(f) at each corner
  std::vector<char> regular;  ///< #V: index 0 and a fan walk that closes
  int degree(int v) const { return begin[v + 1] - begin[v]; }
  int position(int v, int w) const {
    for (int i = begin[v]; i < begin[v + 1]; ++i)
      if (neighbor[i] == w) return i - begin[v];
    return -1;
  }
};

int corner_of(const FaceRef& F, int f, int v) {
  for (int k = 0; k < 3; ++k)
    if (F(f, k) == v) return 3 * f + k;
  return -1;
}

Rings build_rings(const FieldMesh& mesh, const FaceRef& F, const Eigen::VectorXd& theta, const std::vector<int>& index,
                  double anisotropy, double max_deviation) {
  const auto& incidence = mesh.checked.incidence;
  const Eigen::Index n = mesh.V.rows(), m = F.rows();
  std::vector<int> start(n, -1);
  for (Eigen::Index c = 0; c < 3 * m; ++c)
    if (start[F(c / 3, c % 3)] < 0) start[F(c / 3, c % 3)] = static_cast<int>(c);
  // Class shift of the face crosses across each side: class c of f ↔ class c + j of the other face.
  auto face_jump = [&](int e, int f) {
    const int g = mesh.other_face(e, f);
    const double x = theta[g] - theta[f] - mesh.transport(e, f);
    return -static_cast<int>(std::lround((x - detail::quarter_residual(x)) / kQuarter));
  };
  Rings rings;
  rings.begin.assign(n + 1, 0);
  rings.corner_offset.assign(3 * m, 0);
  rings.regular.assign(n, 0);
  for (Eigen::Index v = 0; v < n; ++v) {
    rings.begin[v] = static_cast<int>(rings.neighbor.size());
    int f = start[v] / 3, k = start[v] % 3, offset = 0;
    for (Eigen::Index step = 0; step <= m; ++step) {
      rings.corner_offset[3 * f + k] = offset;
      rings.neighbor.push_back(F(f, (k + 1) % 3));
      rings.face.push_back(f);
      rings.edge.push_back(incidence.side_edge[3 * f + k]);
      const int e = incidence.side_edge[3 * f + (k + 2) % 3];  // the next face ccw lies across b → v
      offset = mod4(offset + face_jump(e, f));
      f = mesh.other_face(e, f);
      k = corner_of(F, f, static_cast<int>(v)) % 3;
      if (3 * f + k == start[v]) break;
    }
    rings.regular[v] = index[v] == 0 && offset == 0;
  }
  rings.begin[n] = static_cast<int>(rings.neighbor.size());
  const std::size_t entries = rings.neighbor.size();
  rings.shift.resize(entries);
  rings.cost.assign(4 * entries, kInfinity);
  const double cos_max = std::cos(max_deviation);
  for (Eigen::Index v = 0; v < n; ++v) {
    const int deg = rings.degree(static_cast<int>(v));
    for (int i = 0; i < deg; ++i) {
      const int entry = rings.begin[v] + i, w = rings.neighbor[entry];
      const int f = rings.face[entry], g = rings.face[rings.begin[v] + (i + deg - 1) % deg];  // left, right
      const int ov_f = rings.corner_offset[corner_of(F, f, static_cast<int>(v))];
      const int ow_f = rings.corner_offset[corner_of(F, f, w)];
      const int ov_g = rings.corner_offset[corner_of(F, g, static_cast<int>(v))];
      rings.shift[entry] = mod4(ov_f - ow_f);
      if (!rings.regular[v] || !rings.regular[w]) continue;
      const Eigen::Vector3d d = mesh.V.row(w) - mesh.V.row(v);
      const double length = d.norm(), phi_f = mesh.angle_in_face(f, d), phi_g = mesh.angle_in_face(g, d);
      for (int c = 0; c < 4; ++c) {
        const double delta_f = detail::wrap_angle(phi_f - theta[f] - (c + ov_f) * kQuarter);
        const double delta_g = detail::wrap_angle(phi_g - theta[g] - (c + ov_g) * kQuarter);
        const double delta = delta_f + 0.5 * detail::wrap_angle(delta_g - delta_f);
        const double cosine = std::cos(delta), sine = std::sin(delta);
        if (cosine < cos_max) continue;
        rings.cost[4 * entry + c] = length * std::sqrt(cosine * cosine + anisotropy * anisotropy * sine * sine);
      }
    }
  }
  return rings;
}

/// Per vertex and family, the edge-path distance to the nearest loop of that family.
struct FamilyDistance {
  std::vector<double> d;  ///< 2#V
  explicit FamilyDistance(Eigen::Index n) : d(2 * n, kInfinity) {}
  /// Lowers d by a Dijkstra sweep from the (vertex, family) sources at distance 0.
  void add_sources(const Rings& rings, const std::vector<double>& lengths, const std::vector<std::pair<int, int>>& sources) {
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (const auto& [v, family] : sources) {
      d[2 * v + family] = 0.0;
      heap.emplace(0.0, 2 * v + family);
    }
    while (!heap.empty()) {
      const auto [dist, state] = heap.top();
      heap.pop();
      if (dist > d[state]) continue;
      const int v = state / 2, family = state % 2;
      for (int entry = rings.begin[v]; entry < rings.begin[v + 1]; ++entry) {
        const int next = 2 * rings.neighbor[entry] + (family + rings.shift[entry]) % 2;
        const double candidate = dist + lengths[entry];
        if (candidate < d[next]) d[next] = candidate, heap.emplace(candidate, next);
      }
    }
  }
};

/// Per vertex: the loops through it (0, 1 or 2) and, on one loop, its neighbours there and class.
struct LoopVertex {
  int loops = 0;
  int previous = -1, next = -1, cls = 0;
};

struct Regions {
  Eigen::VectorXi label;
  int count = 0;
  std::vector<int> euler, singular, corners;
};

}  // namespace

DualLoopLayout dual_loop_layout(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta,
                                const DualLoopOptions& options, const Progress& progress) {
  const auto shared_mesh = detail::field_mesh(V, F, "dual_loop_layout");
  const FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "dual_loop_layout");
  const auto& checked = mesh.checked;
  if (!checked.boundary_loops.empty()) {
    throw InputError("dual_loop_layout: the mesh has " + std::to_string(checked.boundary_loops.size()) +
                     " boundary loop(s) (the first through vertex " + std::to_string(checked.boundary_loops[0][0]) +
                     "); dual loops are traced on closed meshes only (fill_holes first)");
  }
  if (std::isnan(options.parallel_crossing_penalty) || std::isinf(options.parallel_crossing_penalty))
    throw InputError("dual_loop_layout: parallel_crossing_penalty must be finite (negative: not allowed)");
  if (!(options.anisotropy >= 1) || !std::isfinite(options.anisotropy))
    throw InputError("dual_loop_layout: anisotropy must be a finite number ≥ 1");
  if (!(options.max_deviation_degrees > 0 && options.max_deviation_degrees < 90))
    throw InputError("dual_loop_layout: max_deviation must be in (0, 90) degrees");
  if (!std::isfinite(options.spacing)) throw InputError("dual_loop_layout: spacing must be finite");
  if (options.max_loops < 1 || options.max_failed_seeds < 0)
    throw InputError("dual_loop_layout: max_loops must be ≥ 1 and max_failed_seeds ≥ 0");
  const Eigen::Index n = mesh.V.rows(), m = F.rows();
  const double unit = std::ldexp(1.0, mesh.frame.exponent);  // input length of one normalized unit
  const double spacing = options.spacing > 0 ? options.spacing / unit : std::sqrt(mesh.area.sum()) / 4;
  progress.report(0.0, "dual loops");

  DualLoopLayout out;
  const auto index = detail::vertex_indices(mesh, F, theta);
  for (Eigen::Index v = 0; v < n; ++v)
    if (index[v] != 0) out.singularities.vertices.push_back(static_cast<int>(v)), out.singularities.indices.push_back(index[v]);
  const Rings rings = build_rings(mesh, F, theta, index, options.anisotropy, options.max_deviation_degrees * kPi / 180);
  const std::size_t entries = rings.neighbor.size();
  std::vector<double> lengths(entries);
  for (std::size_t entry = 0; entry < entries; ++entry) {
    const int v = static_cast<int>(std::upper_bound(rings.begin.begin(), rings.begin.end(), static_cast<int>(entry)) -
                                   rings.begin.begin()) - 1;
    lengths[entry] = (mesh.V.row(rings.neighbor[entry]) - mesh.V.row(v)).norm();
  }
  // Distance to the nearest singularity (both families at once: a plain sweep on family 0).
  std::vector<double> to_singular(n, kInfinity);
  {
    FamilyDistance sweep(n);
    std::vector<std::pair<int, int>> sources;
    for (int v : out.singularities.vertices) sources.emplace_back(v, 0), sources.emplace_back(v, 1);
    sweep.add_sources(rings, lengths, sources);
    for (Eigen::Index v = 0; v < n; ++v) to_singular[v] = std::min(sweep.d[2 * v], sweep.d[2 * v + 1]);
  }

  const auto& incidence = checked.incidence;
  std::vector<LoopVertex> on_loop(n);
  std::vector<char> loop_edge(incidence.n_edges(), 0);
  FamilyDistance distance(n);
  std::vector<std::vector<int>> loop_vertices;
  std::vector<double> loop_length;
  std::vector<int> loop_seed, loop_class;
  std::vector<int> crossing_vertex;
  Eigen::Index parallel_crossings = 0;

  // ---- tracing -------------------------------------------------------------------------------
  std::vector<double> dist(4 * n);
  std::vector<int> pred(4 * n), pred_mid(4 * n), settled_class(n);
  Eigen::Index failed_open = 0, failed_overlap = 0;
  auto separation = [&](int w, int family) {
    const double d = distance.d[2 * w + family];
    return 1.0 + 4.0 * std::max(0.0, 1.0 - d / (0.5 * spacing));
  };
  // The loop through (s, c) as a vertex sequence, or empty if none (or a self-overlapping one).
  // exclusive: one class per vertex — the first state settled at a vertex closes it to the other
  // classes, so the search tree's paths never visit a vertex twice (the shortest path over all
  // four classes can spiral around a singularity back through its own vertices); tried second,
  // because it also closes vertices behind the seed to the class the loop needs to come back in.
  auto trace = [&](int s, int c, bool exclusive, bool& overlap) -> std::vector<int> {
    overlap = false;
    std::fill(dist.begin(), dist.end(), kInfinity);
    std::fill(pred.begin(), pred.end(), -1);
    std::fill(pred_mid.begin(), pred_mid.end(), -1);
    std::fill(settled_class.begin(), settled_class.end(), -1);
    if (exclusive) settled_class[s] = c;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    const int target = 4 * s + c;
    auto relax = [&](int from, double base, int to, double cost, int mid) {
      if (to / 4 == s && to != target) return;  // through the seed in another class: an overlap
      if (settled_class[to / 4] >= 0 && settled_class[to / 4] != to % 4) return;
      const double candidate = base + cost;
      if (candidate < dist[to]) dist[to] = candidate, pred[to] = from, pred_mid[to] = mid, heap.emplace(candidate, to);
    };
    auto expand = [&](int state, double base) {
      const int u = state / 4, cu = state % 4;
      for (int entry = rings.begin[u]; entry < rings.begin[u + 1]; ++entry) {
        const double cost = rings.cost[4 * entry + cu];
        if (cost == kInfinity || loop_edge[rings.edge[entry]]) continue;
        const int w = rings.neighbor[entry], cw = mod4(cu + rings.shift[entry]);
        const LoopVertex& at = on_loop[w];
        if (at.loops == 0) {
          relax(state, base, 4 * w + cw, cost * separation(w, cw % 2), -1);
          continue;
        }
        if (at.loops != 1 || w == s) continue;  // two loops per crossing at most
        const bool parallel = (cw - at.cls) % 2 == 0;  // the same family: not orthogonal
        if (parallel && !(options.parallel_crossing_penalty >= 0)) continue;
        const double extra = parallel ? options.parallel_crossing_penalty * spacing : 0.0;
        const int deg = rings.degree(w), pa = rings.position(w, at.previous), pb = rings.position(w, at.next);
        // p strictly inside the counter-clockwise arc from the loop's previous vertex to its next one
        auto inside = [&](int p) { return p != pa && (p - pa + deg) % deg < (pb - pa + deg) % deg; };
        const int pu = rings.position(w, u);
        const bool u_inside = inside(pu);
        for (int next = rings.begin[w]; next < rings.begin[w + 1]; ++next) {
          const int x = rings.neighbor[next], px = next - rings.begin[w];
          if (px == pa || px == pb || inside(px) == u_inside || on_loop[x].loops > 0) continue;
          const double cost2 = rings.cost[4 * next + cw];
          if (cost2 == kInfinity || loop_edge[rings.edge[next]]) continue;
          const int cx = mod4(cw + rings.shift[next]);
          relax(state, base, 4 * x + cx, cost + cost2 * separation(x, cx % 2) + extra, w);
        }
      }
    };
    expand(target, 0.0);
    const double budget = 200.0 * options.anisotropy * spacing + 50.0 * std::sqrt(mesh.area.sum());
    while (!heap.empty()) {
      const auto [d, state] = heap.top();
      heap.pop();
      if (d > dist[state]) continue;
      if (state == target) break;
      if (d > budget) break;
      if (settled_class[state / 4] >= 0 && settled_class[state / 4] != state % 4) continue;
      if (exclusive) settled_class[state / 4] = state % 4;
      expand(state, d);
    }
    if (pred[target] < 0 || !(dist[target] <= budget)) return {};
    std::vector<int> path;  // backwards from the target, mids included
    int state = target;
    do {
      path.push_back(state / 4);
      if (pred_mid[state] >= 0) path.push_back(pred_mid[state]);
      state = pred[state];
    } while (state != target && state >= 0 && path.size() <= static_cast<std::size_t>(4 * n));
    std::reverse(path.begin(), path.end());  // starts at s (after the first move), ends just before s ... rotate
    std::vector<int> sorted = path;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end() || path.size() < 3) {
      overlap = true;
      return {};
    }
    return path;
  };

  // Records a traced loop: its vertices from the seed on, their classes (re-derived along the path
  // from the seed's class, as the trace carried them), its edges, and the family distances.
  auto add_loop = [&](const std::vector<int>& path, int s, int c, bool with_distance = true) {
    // Rotate so that the path starts at the seed.
    std::vector<int> loop = path;
    std::rotate(loop.begin(), std::find(loop.begin(), loop.end(), s), loop.end());
    const std::size_t k = loop.size();
    std::vector<std::pair<int, int>> sources;
    double length = 0.0;
    int cls = c;
    for (std::size_t i = 0; i < k; ++i) {
      const int v = loop[i], w = loop[(i + 1) % k], p = loop[(i + k - 1) % k];
      LoopVertex& at = on_loop[v];
      if (at.loops == 1) {
        crossing_vertex.push_back(v);  // the first loop's neighbours and class stay recorded
        parallel_crossings += (cls - at.cls) % 2 == 0;
      } else {
        at.previous = p, at.next = w, at.cls = cls;
      }
      ++at.loops;
      sources.emplace_back(v, cls % 2);
      const int entry = rings.begin[v] + rings.position(v, w);
      loop_edge[rings.edge[entry]] = 1;
      length += lengths[entry];
      cls = mod4(cls + rings.shift[entry]);
    }
    if (with_distance) distance.add_sources(rings, lengths, sources);
    loop_vertices.push_back(std::move(loop));
    loop_length.push_back(length);
    loop_seed.push_back(s);
    loop_class.push_back(c);
  };
  // The arrangement of the loops `keep` (indices into the current ones, in their order, so a
  // vertex keeps the record of the first loop through it), from scratch.
  auto rebuild = [&](const std::vector<int>& keep, bool with_distance) {
    std::vector<std::vector<int>> paths;
    std::vector<int> seeds, classes;
    for (int id : keep) paths.push_back(loop_vertices[id]), seeds.push_back(loop_seed[id]), classes.push_back(loop_class[id]);
    std::fill(on_loop.begin(), on_loop.end(), LoopVertex{});
    std::fill(loop_edge.begin(), loop_edge.end(), 0);
    if (with_distance) distance = FamilyDistance(n);
    crossing_vertex.clear();
    parallel_crossings = 0;
    loop_vertices.clear(), loop_length.clear(), loop_seed.clear(), loop_class.clear();
    for (std::size_t k = 0; k < paths.size(); ++k) add_loop(paths[k], seeds[k], classes[k], with_distance);
  };

  // ---- regions -------------------------------------------------------------------------------
  std::vector<char> singular(n, 0);
  for (int v : out.singularities.vertices) singular[v] = 1;
  auto compute_regions = [&]() {
    Regions r;
    r.label.setConstant(m, -1);
    for (Eigen::Index f0 = 0; f0 < m; ++f0) {
      if (r.label[f0] >= 0) continue;
      std::vector<int> stack{static_cast<int>(f0)};
      r.label[f0] = r.count;
      while (!stack.empty()) {
        const int f = stack.back();
        stack.pop_back();
        for (int k = 0; k < 3; ++k) {
          const int e = incidence.side_edge[3 * f + k];
          if (loop_edge[e]) continue;
          const int g = mesh.other_face(e, f);
          if (r.label[g] < 0) r.label[g] = r.count, stack.push_back(g);
        }
      }
      ++r.count;
    }
    std::vector<long long> faces(r.count, 0), loop_sides(r.count, 0), sectors(r.count, 0);
    r.singular.assign(r.count, 0);
    r.corners.assign(r.count, 0);
    for (Eigen::Index f = 0; f < m; ++f) {
      ++faces[r.label[f]];
      for (int k = 0; k < 3; ++k) loop_sides[r.label[f]] += loop_edge[incidence.side_edge[3 * f + k]];
    }
    for (Eigen::Index v = 0; v < n; ++v) {
      const int b = rings.begin[v], deg = rings.degree(static_cast<int>(v));
      int cuts = 0;
      for (int i = 0; i < deg; ++i) cuts += loop_edge[rings.edge[b + i]];
      if (cuts == 0) {
        ++sectors[r.label[rings.face[b]]];
        if (singular[v]) ++r.singular[r.label[rings.face[b]]];
        continue;
      }
      // One sector per loop edge: the faces from that edge counter-clockwise to the next.
      for (int i = 0; i < deg; ++i) {
        if (!loop_edge[rings.edge[b + i]]) continue;
        const int region = r.label[rings.face[b + i]];
        ++sectors[region];
        if (on_loop[v].loops >= 2) ++r.corners[region];
      }
    }
    r.euler.resize(r.count);
    for (int i = 0; i < r.count; ++i) r.euler[i] = static_cast<int>(sectors[i] - (3 * faces[i] + loop_sides[i]) / 2 + faces[i]);
    return r;
  };

  // ---- the dual and its defects -----------------------------------------------------------------
  // Per crossing, the regions of its four sectors counter-clockwise.
  auto layout_quads = [&](const Regions& r) {
    QuadMatrix Q(static_cast<Eigen::Index>(crossing_vertex.size()), 4);
    for (Eigen::Index q = 0; q < Q.rows(); ++q) {
      const int v = crossing_vertex[q], b = rings.begin[v], deg = rings.degree(v);
      int corner = 0;
      for (int i = 0; i < deg && corner < 4; ++i)
        if (loop_edge[rings.edge[b + i]]) Q(q, corner++) = r.label[rings.face[b + i]];
      if (corner != 4) throw SolverError("dual_loop_layout: crossing at vertex " + std::to_string(v) + " has " +
                                         std::to_string(corner) + " loop edges instead of 4; please report this mesh");
    }
    return Q;
  };
  struct Defects {
    Eigen::Index degenerate_quads = 0, non_manifold_edges = 0, non_manifold_vertices = 0, low_valence_vertices = 0, edges = 0;
    std::vector<char> region;  ///< regions at a defect of the dual
  };
  auto layout_defects = [&](const QuadMatrix& Q, int n_regions) {
    Defects found;
    found.region.assign(n_regions, 0);
    std::map<std::pair<int, int>, int> directed;
    for (Eigen::Index q = 0; q < Q.rows(); ++q) {
      std::array<int, 4> c{Q(q, 0), Q(q, 1), Q(q, 2), Q(q, 3)};
      std::array<int, 4> sorted = c;
      std::sort(sorted.begin(), sorted.end());
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
        ++found.degenerate_quads;
        for (int x : c) found.region[x] = 1;
      }
      for (int k = 0; k < 4; ++k) ++directed[{c[k], c[(k + 1) % 4]}];
    }
    for (const auto& [edge, count] : directed) {
      if (edge.first > edge.second && directed.count({edge.second, edge.first})) continue;  // the pair once
      ++found.edges;
      const auto twin = directed.find({edge.second, edge.first});
      if (count != 1 || twin == directed.end() || twin->second != 1) {
        ++found.non_manifold_edges;
        found.region[edge.first] = found.region[edge.second] = 1;
      }
    }
    // Around each layout vertex, "next" maps a quad's incoming neighbour to its outgoing one: one cycle.
    std::vector<std::map<int, int>> fan(n_regions);
    std::vector<char> bad(n_regions, 0);
    for (Eigen::Index q = 0; q < Q.rows(); ++q)
      for (int k = 0; k < 4; ++k)
        if (!fan[Q(q, k)].emplace(Q(q, (k + 1) % 4), Q(q, (k + 3) % 4)).second) bad[Q(q, k)] = 1;
    for (int i = 0; i < n_regions; ++i) {
      if (fan[i].empty()) {
        bad[i] = 1;
      } else if (!bad[i]) {
        const int start = fan[i].begin()->first;
        int at = start;
        std::size_t steps = 0;
        do {
          const auto it = fan[i].find(at);
          if (it == fan[i].end()) break;
          at = it->second;
          ++steps;
        } while (at != start && steps <= fan[i].size());
        bad[i] = at != start || steps != fan[i].size();
      }
      found.non_manifold_vertices += bad[i];
      // A layout vertex of valence 2 (a region with two corners) is manifold but degenerate: its
      // two quads share two consecutive edges.
      const bool low = !fan[i].empty() && fan[i].size() < 3;
      found.low_valence_vertices += low;
      if (bad[i] || low) found.region[i] = 1;
    }
    return found;
  };

  // Separation indicators (§5.3): in a region holding several singularities, the shortest edge
  // path (inside the region) from one of them to the nearest other; its middle vertices are the
  // seeds of a loop that separates them.
  auto indicator_seeds = [&](const Regions& r, int region, std::vector<int>& seeds_out) {
    std::vector<int> sources;
    for (int v : out.singularities.vertices)
      if (on_loop[v].loops == 0 && r.label[rings.face[rings.begin[v]]] == region) sources.push_back(v);
    if (sources.size() < 2) return;
    std::vector<double> d(n, kInfinity);
    std::vector<int> from(n, -1);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    d[sources[0]] = 0.0;
    heap.emplace(0.0, sources[0]);
    int reached = -1;
    while (!heap.empty()) {
      const auto [dv, v] = heap.top();
      heap.pop();
      if (dv > d[v]) continue;
      if (v != sources[0] && singular[v]) { reached = v; break; }
      for (int entry = rings.begin[v]; entry < rings.begin[v + 1]; ++entry) {
        const int w = rings.neighbor[entry];
        if (loop_edge[rings.edge[entry]] || on_loop[w].loops > 0 || r.label[rings.face[entry]] != region) continue;
        if (dv + lengths[entry] < d[w]) d[w] = dv + lengths[entry], from[w] = v, heap.emplace(d[w], w);
      }
    }
    if (reached < 0) return;
    std::vector<int> path;
    for (int v = reached; v >= 0; v = from[v]) path.push_back(v);
    const int middle = static_cast<int>(path.size()) / 2;
    for (int offset = 0; offset <= middle; ++offset)
      for (int sign : {1, -1}) {
        const int i = middle + sign * offset;
        if (i > 0 && i + 1 < static_cast<int>(path.size()) && rings.regular[path[i]] && (offset || sign == 1))
          seeds_out.push_back(path[i]);
      }
  };

  // ---- greedy selection ----------------------------------------------------------------------
  std::vector<char> tried(2 * n, 0);
  Regions regions = compute_regions();
  Eigen::Index failed = 0, seeds = 0;
  bool exhausted = false;  // max_failed_seeds reached in the last selection
  double reported = 0.0;   // progress (the loop count falls when a loop is dropped)
  const double cover = 0.75 * spacing;
  // Adds loops until the regions are valid and the surface covered, or a limit is reached.
  auto select = [&]() {
    Eigen::Index failed_here = 0;
    while (static_cast<int>(loop_vertices.size()) < options.max_loops && failed_here <= options.max_failed_seeds) {
      std::vector<char> bad_region = layout_defects(layout_quads(regions), regions.count).region;
      bool any_bad = false;
      for (int i = 0; i < regions.count; ++i) {
        if (regions.euler[i] != 1 || regions.singular[i] > 1) bad_region[i] = 1;
        any_bad |= bad_region[i] != 0;
      }
      // Seeds on separation indicators first, in region order; then the farthest in a bad region.
      int best = -1;
      for (int i = 0; i < regions.count && best < 0; ++i) {
        if (regions.singular[i] < 2) continue;
        std::vector<int> candidates;
        indicator_seeds(regions, i, candidates);
        for (int v : candidates) {
          for (int family = 0; family < 2 && best < 0; ++family)
            if (!tried[2 * v + family] && on_loop[v].loops == 0) best = 2 * v + family;
          if (best >= 0) break;
        }
      }
      std::vector<char> vertex_in_bad(n, 0);
      for (Eigen::Index f = 0; f < m; ++f)
        if (bad_region[regions.label[f]]) for (int k = 0; k < 3; ++k) vertex_in_bad[F(f, k)] = 1;
      double worst = 0.0;
      double best_score = best >= 0 ? kInfinity : -1.0;
      for (Eigen::Index v = 0; v < n; ++v) {
        if (!rings.regular[v] || on_loop[v].loops > 0) continue;
        for (int family = 0; family < 2; ++family) {
          const double d = distance.d[2 * v + family];
          worst = std::max(worst, std::min(d, 2 * to_singular[v]));
          if (tried[2 * v + family] || (any_bad && !vertex_in_bad[v])) continue;
          const double score = std::min(d, 2 * to_singular[v]);
          if (score > best_score) best_score = score, best = static_cast<int>(2 * v + family);
        }
      }
      if (!any_bad && worst <= cover) break;
      if (best < 0) break;  // no seed left where one is needed: reported below
      tried[best] = 1;
      ++seeds;
      bool overlap = false, overlap_exclusive = false;
      std::vector<int> path = trace(best / 2, best % 2, false, overlap);
      if (path.empty() && overlap) path = trace(best / 2, best % 2, true, overlap_exclusive);
      if (path.empty()) {
        ++failed, ++failed_here;
        ++(overlap ? failed_overlap : failed_open);
        continue;
      }
      add_loop(path, best / 2, best % 2);
      regions = compute_regions();
      reported = std::max(reported, std::min(0.95, static_cast<double>(loop_vertices.size()) / options.max_loops));
      progress.report(reported, "dual loops");
    }
    exhausted = failed_here > options.max_failed_seeds;
  };
  select();

  // ---- valence-2 layout vertices: dropping a loop at them --------------------------------------
  // A region with two corners is a bigon between two loops that cross twice in a row (mostly two
  // loops of one family, where parallel crossings are allowed); once the selection has stopped no
  // loop through it is found. Dropping one of the loops at its corners removes both crossings.
  // A drop is kept outright when every region stays a disk with at most one singularity and the
  // dual has fewer defects. Where valence 2 is all that is left (every region valid), the most
  // promising drops (fewest faults) are also tried with the selection run again — it seeds in the
  // regions the drop left faulty, never from a seed tried before — and kept only when the result
  // has fewer faults, else undone. Faults: regions that are not disks or hold several
  // singularities, plus defects of the dual (valence-2 vertices, repeated corners, non-manifold
  // edges and vertices, |χ − χ_input|). Measured on fertility (merge=1.5, refine=1,
  // parallel_crossing_penalty=4, max_failed_seeds=300): 23 loops left 2 valence-2 vertices; no
  // drop alone kept the regions valid (each of the three that removed one merged two cones into a
  // region); a drop with the selection run again gave a complete layout (24 loops, 172 quads,
  // χ −6, no valence 2), 2.2 → 4.8 s (load 3.5).
  struct Faults {
    Eigen::Index regions = 0, defects = 0, low = 0;
    Eigen::Index total() const { return regions + defects; }
  };
  auto faults_of = [&](const Regions& r) {
    Faults f;
    for (int i = 0; i < r.count; ++i) f.regions += r.euler[i] != 1 || r.singular[i] > 1;
    const QuadMatrix Q = layout_quads(r);
    const Defects d = layout_defects(Q, r.count);
    const long long euler = static_cast<long long>(r.count) - static_cast<long long>(d.edges) + Q.rows();
    f.low = d.low_valence_vertices;
    f.defects = d.low_valence_vertices + d.non_manifold_edges + d.non_manifold_vertices + d.degenerate_quads +
                static_cast<Eigen::Index>(std::llabs(euler - checked.euler_characteristic));
    return f;
  };
  auto all_loops = [&]() {
    std::vector<int> ids(loop_vertices.size());
    std::iota(ids.begin(), ids.end(), 0);
    return ids;
  };
  auto without = [&](int drop) {
    std::vector<int> keep = all_loops();
    keep.erase(std::remove(keep.begin(), keep.end(), drop), keep.end());
    return keep;
  };
  // Per loop through a corner of a valence-2 region: the faults of the arrangement without it,
  // best first (ties: the later loop).
  auto drop_trials = [&]() {
    const QuadMatrix Q = layout_quads(regions);
    std::vector<int> valence(regions.count, 0);
    for (Eigen::Index q = 0; q < Q.rows(); ++q)
      for (int k = 0; k < 4; ++k) ++valence[Q(q, k)];
    std::vector<char> corner(n, 0);
    for (Eigen::Index q = 0; q < Q.rows(); ++q)
      for (int k = 0; k < 4; ++k)
        if (valence[Q(q, k)] > 0 && valence[Q(q, k)] < 3) corner[crossing_vertex[q]] = 1;
    std::vector<std::pair<Faults, int>> trials;
    const auto saved_vertices = loop_vertices;
    const auto saved_seed = loop_seed, saved_class = loop_class;
    for (int id = 0; id < static_cast<int>(saved_vertices.size()); ++id) {
      if (std::none_of(saved_vertices[id].begin(), saved_vertices[id].end(), [&](int v) { return corner[v] != 0; })) continue;
      rebuild(without(id), false);
      trials.emplace_back(faults_of(compute_regions()), id);
      loop_vertices = saved_vertices, loop_seed = saved_seed, loop_class = saved_class;
    }
    rebuild(all_loops(), false);  // the distances are still those of all loops
    std::stable_sort(trials.begin(), trials.end(), [](const auto& x, const auto& y) {
      return x.first.total() != y.first.total() ? x.first.total() < y.first.total() : x.second > y.second;
    });
    return trials;
  };
  auto prune = [&]() {
    for (Faults now = faults_of(regions); now.regions == 0 && now.low > 0;) {
      const auto trials = drop_trials();
      const auto kept = std::find_if(trials.begin(), trials.end(), [&](const auto& t) {
        return t.first.regions == 0 && t.first.defects < now.defects;
      });
      if (kept == trials.end()) break;
      rebuild(without(kept->second), true);
      regions = compute_regions();
      now = kept->first;
    }
  };
  prune();
  constexpr int kReselectRounds = 4, kReselectDrops = 3;
  for (int round = 0; round < kReselectRounds; ++round) {
    const Faults before = faults_of(regions);
    if (before.low == 0 || before.regions > 0) break;  // only where valence 2 is what is left of the regions' faults
    const auto trials = drop_trials();
    bool improved = false;
    for (std::size_t k = 0; k < trials.size() && k < static_cast<std::size_t>(kReselectDrops) && !improved; ++k) {
      const auto saved_vertices = loop_vertices;
      const auto saved_seed = loop_seed, saved_class = loop_class;
      rebuild(without(trials[k].second), true);
      regions = compute_regions();
      select();
      prune();
      improved = faults_of(regions).total() < before.total();
      if (!improved) {
        loop_vertices = saved_vertices, loop_seed = saved_seed, loop_class = saved_class;
        rebuild(all_loops(), true);
        regions = compute_regions();
      }
    }
    if (!improved) break;
  }

  // ---- the dual layout -----------------------------------------------------------------------
  DualLoopReport& report = out.report;
  report.loops = static_cast<Eigen::Index>(loop_vertices.size());
  report.crossings = static_cast<Eigen::Index>(crossing_vertex.size());
  report.regions = regions.count;
  report.region_euler = regions.euler;
  report.region_singularities = regions.singular;
  report.region_corners = regions.corners;
  report.seeds_tried = seeds;
  report.seeds_failed = failed;
  report.seeds_unclosed = failed_open;
  report.seeds_overlapping = failed_overlap;
  report.parallel_crossings = parallel_crossings;
  report.spacing = spacing * unit;
  report.euler_input = checked.euler_characteristic;
  double worst = 0.0;
  for (Eigen::Index v = 0; v < n; ++v) worst = std::max(worst, std::min(distance.d[2 * v], distance.d[2 * v + 1]));
  report.max_distance_to_loops = worst * unit;
  for (int i = 0; i < regions.count; ++i) {
    report.non_disk_regions += regions.euler[i] != 1;
    report.multi_singular_regions += regions.singular[i] > 1;
  }
  out.region = regions.label;
  // Layout vertices: the region's singular vertex, else its vertex farthest from the loops, else (a
  // sliver between loops, every vertex of it on a loop) the centroid of its largest face. The
  // centroid keeps two layout vertices apart: a loop vertex can border several slivers, and the
  // layouts the parallel crossings complete had them share one (kitten 4 pairs, fertility 2: 5
  // quads each with a zero-length edge).
  out.Vq.resize(regions.count, 3);
  out.Vq_vertex.setConstant(regions.count, -1);
  std::vector<double> farthest(regions.count, -1.0);
  for (int v : out.singularities.vertices) {
    const int region = regions.label[rings.face[rings.begin[v]]];
    if (out.Vq_vertex[region] < 0) out.Vq_vertex[region] = v, farthest[region] = kInfinity;
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    if (on_loop[v].loops > 0) continue;
    const int region = regions.label[rings.face[rings.begin[v]]];
    const double d = std::min(distance.d[2 * v], distance.d[2 * v + 1]);
    if (d > farthest[region]) farthest[region] = d, out.Vq_vertex[region] = static_cast<int>(v);
  }
  std::vector<int> largest_face(regions.count, -1);
  for (Eigen::Index f = 0; f < m; ++f) {
    int& largest = largest_face[regions.label[f]];
    if (largest < 0 || mesh.area[f] > mesh.area[largest]) largest = static_cast<int>(f);
  }
  for (int i = 0; i < regions.count; ++i) {
    if (out.Vq_vertex[i] >= 0) {
      out.Vq.row(i) = V.row(out.Vq_vertex[i]);
      continue;
    }
    const int f = largest_face[i];
    const Eigen::RowVector3d centroid = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
    out.Vq.row(i) = centroid;
    int nearest = F(f, 0);
    for (int k = 1; k < 3; ++k)
      if ((V.row(F(f, k)) - centroid).squaredNorm() < (V.row(nearest) - centroid).squaredNorm()) nearest = F(f, k);
    out.Vq_vertex[i] = nearest;
  }
  out.Q = layout_quads(regions);
  out.Q_vertex = Eigen::Map<const Eigen::VectorXi>(crossing_vertex.data(), static_cast<Eigen::Index>(crossing_vertex.size()));
  // Loop records with their crossing positions.
  std::vector<char> is_crossing(n, 0);
  for (int v : crossing_vertex) is_crossing[v] = 1;
  Eigen::Index segments = 0;
  for (std::size_t id = 0; id < loop_vertices.size(); ++id) {
    DualLoop loop;
    loop.vertices = loop_vertices[id];
    for (std::size_t i = 0; i < loop.vertices.size(); ++i)
      if (is_crossing[loop.vertices[i]]) loop.crossings.push_back(static_cast<int>(i));
    loop.length = loop_length[id] * unit;
    loop.seed = loop_seed[id];
    segments += static_cast<Eigen::Index>(loop.crossings.size());
    out.loops.push_back(std::move(loop));
  }
  report.segments = segments;
  const Defects defects = layout_defects(out.Q, regions.count);
  report.degenerate_quads = defects.degenerate_quads;
  report.non_manifold_edges = defects.non_manifold_edges;
  report.non_manifold_vertices = defects.non_manifold_vertices;
  report.low_valence_vertices = defects.low_valence_vertices;
  report.euler_layout = static_cast<long long>(regions.count) - static_cast<long long>(defects.edges) + out.Q.rows();
  // Where it fails.
  std::string& why = report.failure;
  auto add = [&](const std::string& text) { why += (why.empty() ? "" : "; ") + text; };
  for (int i = 0; i < regions.count; ++i) {
    if (regions.euler[i] != 1) add("region " + std::to_string(i) + " has χ = " + std::to_string(regions.euler[i]) + " (not a disk)");
    if (regions.singular[i] > 1) {
      // Its singular vertices with their indices, and whether two are mesh neighbours (no edge
      // loop can pass between those).
      std::string list;
      bool adjacent = false;
      for (int v : out.singularities.vertices) {
        if (regions.label[rings.face[rings.begin[v]]] != i) continue;
        if (list.size() < 80) list += (list.empty() ? "" : ", ") + std::to_string(v) + (index[v] > 0 ? " (+" : " (") + std::to_string(index[v]) + ")";
        for (int entry = rings.begin[v]; entry < rings.begin[v + 1]; ++entry)
          adjacent |= singular[rings.neighbor[entry]] && regions.label[rings.face[entry]] == i;
      }
      add("region " + std::to_string(i) + " holds " + std::to_string(regions.singular[i]) + " singularities: vertices " + list +
          (adjacent ? ", two of them neighbours" : ""));
    }
    if (why.size() > 2000) break;
  }
  if (report.crossings == 0) add("no two loops cross");
  if (report.degenerate_quads) add(std::to_string(report.degenerate_quads) + " layout quads repeat a region");
  if (report.non_manifold_edges) add(std::to_string(report.non_manifold_edges) + " layout edges are not shared by two quads");
  if (report.non_manifold_vertices) add(std::to_string(report.non_manifold_vertices) + " layout vertices have no single fan");
  if (report.low_valence_vertices) add(std::to_string(report.low_valence_vertices) + " layout vertices have valence 2");
  if (report.euler_layout != report.euler_input)
    add("the layout's χ is " + std::to_string(report.euler_layout) + ", the input's " + std::to_string(report.euler_input));
  if (!why.empty()) {
    why = "after " + std::to_string(report.loops) + " loops (" + std::to_string(failed) + " of " + std::to_string(seeds) +
          " seeds gave no loop" + (static_cast<int>(report.loops) >= options.max_loops ? ", max_loops reached" : "") +
          (exhausted ? ", max_failed_seeds reached" : "") + "): " + why;
  }
  progress.report(1.0, "dual loops");
  return out;
}

}  // namespace meshsmith::quadrangulation
