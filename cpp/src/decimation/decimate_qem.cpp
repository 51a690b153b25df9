// Incremental decimation by edge collapses (§4.2): a compact corner-based half-edge mesh, error
// quadrics, an addressable 4-ary heap updated in place, pluggable costs and fairness
// criteria around one greedy loop.
#include <meshsmith/core/errors.h>
#include <meshsmith/core/parallel.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/decimation/decimate.h>
#include <meshsmith/decimation/quadric.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace meshsmith::decimation {
namespace {

using Vec3 = Eigen::Vector3d;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kDegree = 3.14159265358979323846 / 180.0;

// ---------------------------------------------------------------------------------------------
// Half-edge mesh on the faces' corners: half-edge h = 3f + k runs from corner k of face f to
// corner k+1, so next/prev are arithmetic and only `opposite` is stored.
// ---------------------------------------------------------------------------------------------

inline int next_halfedge(int h) { return (h % 3 == 2) ? h - 2 : h + 1; }
inline int prev_halfedge(int h) { return (h % 3 == 0) ? h + 2 : h - 1; }

struct HalfedgeMesh {
  std::vector<Vec3> position;        // per working vertex
  std::vector<int> corner_vertex;    // 3#F: start vertex of each half-edge
  std::vector<int> opposite;         // 3#F: twin half-edge, −1 on the boundary
  std::vector<int> vertex_halfedge;  // per vertex: an outgoing half-edge of a live face, or −1
  std::vector<std::uint8_t> boundary;    // per vertex
  std::vector<std::uint8_t> face_alive;  // per face
  std::vector<int> split_origin;     // per working vertex: input vertex (empty: identity)

  int from(int h) const { return corner_vertex[h]; }
  int to(int h) const { return corner_vertex[next_halfedge(h)]; }
  /// The half-edge that stands for the undirected edge of h (its smaller twin).
  int canonical(int h) const { const int o = opposite[h]; return (o >= 0 && o < h) ? o : h; }

  /// fn(h) for every outgoing half-edge h of v (each once), around the fan in either direction.
  template <typename Fn>
  void for_each_outgoing(int v, const Fn& fn) const {
    const int start = vertex_halfedge[v];
    if (start < 0) return;
    int h = start;
    while (true) {  // clockwise: h → twin of prev(h)
      fn(h);
      const int o = opposite[prev_halfedge(h)];
      if (o < 0) break;
      if (o == start) return;
      h = o;
    }
    for (int o = opposite[start]; o >= 0;) {  // the open fan: the other way from start
      const int g = next_halfedge(o);
      fn(g);
      o = opposite[g];
    }
  }

  /// fn(u) for every neighbour u of v; a neighbour may be reported twice.
  template <typename Fn>
  void for_each_neighbour(int v, const Fn& fn) const {
    for_each_outgoing(v, [&](int h) {
      fn(to(h));
      fn(from(prev_halfedge(h)));
    });
  }

  int valence(int v) const {
    int outgoing = 0;
    for_each_outgoing(v, [&](int) { ++outgoing; });
    return outgoing + (boundary[v] ? 1 : 0);
  }
};

/// Builds the half-edge mesh of F (faces with a repeated index dropped). Two half-edges are twins
/// only when their edge has exactly these two, in opposite directions; every vertex whose faces
/// then form more than one fan is split into one working vertex per fan (copies appended).
HalfedgeMesh build_halfedge_mesh(const VertexRef& V, const FaceRef& F) {
  HalfedgeMesh mesh;
  const int n = static_cast<int>(V.rows());
  std::vector<int> faces;
  faces.reserve(static_cast<std::size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (a == b || b == c || c == a) continue;
    faces.insert(faces.end(), {a, b, c});
  }
  const int halfedges = static_cast<int>(faces.size());
  mesh.corner_vertex = std::move(faces);
  mesh.opposite.assign(halfedges, -1);

  // Twins: bucket the half-edges by their smaller end vertex (counting sort), then within each
  // bucket pair the edges that have exactly two half-edges, in opposite directions.
  std::vector<int> bucket_start(static_cast<std::size_t>(n) + 1, 0);
  for (int h = 0; h < halfedges; ++h)
    ++bucket_start[std::min(mesh.corner_vertex[h], mesh.corner_vertex[next_halfedge(h)]) + 1];
  for (int v = 0; v < n; ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<int> bucket(halfedges);
  {
    std::vector<int> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (int h = 0; h < halfedges; ++h)
      bucket[fill[std::min(mesh.corner_vertex[h], mesh.corner_vertex[next_halfedge(h)])]++] = h;
  }
  auto other_end = [&](int h, int v) {
    const int u = mesh.corner_vertex[h], w = mesh.corner_vertex[next_halfedge(h)];
    return u == v ? w : u;
  };
  for (int v = 0; v < n; ++v) {
    const int begin = bucket_start[v], end = bucket_start[v + 1];
    for (int i = begin; i < end; ++i) {
      const int g = bucket[i], far = other_end(g, v);
      int partners = 0, partner = -1;
      for (int j = begin; j < end; ++j)
        if (j != i && other_end(bucket[j], v) == far) { ++partners; partner = bucket[j]; }
      if (partners == 1 && mesh.corner_vertex[g] != mesh.corner_vertex[partner]) mesh.opposite[g] = partner;
    }
  }

  // One working vertex per fan: walk each fan from an unvisited outgoing half-edge.
  mesh.vertex_halfedge.assign(n, -1);
  std::vector<int> origin(n);
  for (int v = 0; v < n; ++v) origin[v] = v;
  std::vector<std::uint8_t> visited(halfedges, 0);
  std::vector<int> fan;
  for (int start = 0; start < halfedges; ++start) {
    if (visited[start]) continue;
    const int v = mesh.corner_vertex[start];
    fan.clear();
    // Walk clockwise to the fan's end (or around), then collect counter-clockwise from there.
    int first = start;
    for (int o = mesh.opposite[prev_halfedge(first)]; o >= 0 && o != start; o = mesh.opposite[prev_halfedge(first)])
      first = o;
    int h = first;
    while (true) {
      fan.push_back(h);
      const int o = mesh.opposite[h];
      if (o < 0) break;
      h = next_halfedge(o);
      if (h == first) break;
    }
    int id = v;
    if (mesh.vertex_halfedge[v] >= 0) {  // v already has a fan: this one gets a copy
      id = static_cast<int>(origin.size());
      origin.push_back(v);
      mesh.vertex_halfedge.push_back(-1);
    }
    mesh.vertex_halfedge[id] = first;
    for (const int g : fan) {
      visited[g] = 1;
      mesh.corner_vertex[g] = id;
    }
  }
  const int working = static_cast<int>(origin.size());
  mesh.position.resize(working);
  for (int v = 0; v < working; ++v) mesh.position[v] = V.row(origin[v]).transpose();
  if (working != n) mesh.split_origin = std::move(origin);

  mesh.boundary.assign(working, 0);
  for (int h = 0; h < halfedges; ++h)
    if (mesh.opposite[h] < 0) {
      mesh.boundary[mesh.corner_vertex[h]] = 1;
      mesh.boundary[mesh.corner_vertex[next_halfedge(h)]] = 1;
    }
  mesh.face_alive.assign(halfedges / 3, 1);
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Quadrics (§4.2.2, error quadrics): face planes weighted by area / mean area, plus constraint
// planes through boundary edges, perpendicular to their face.
// ---------------------------------------------------------------------------------------------

constexpr double kBoundaryConstraintWeight = 10.0;

std::vector<Quadric> initial_quadrics(const HalfedgeMesh& mesh, bool boundary_planes, const Progress& progress) {
  const int faces = static_cast<int>(mesh.face_alive.size());
  std::vector<Vec3> area_normal(faces);  // (twice the area) × unit normal
  parallel_for_with_progress(faces, progress, "face planes", [&](Eigen::Index f) {
    const Vec3& p = mesh.position[mesh.corner_vertex[3 * f]];
    const Vec3& q = mesh.position[mesh.corner_vertex[3 * f + 1]];
    const Vec3& r = mesh.position[mesh.corner_vertex[3 * f + 2]];
    area_normal[f] = (q - p).cross(r - p);
  });
  double total = 0;
  for (const Vec3& a : area_normal) total += a.norm();
  const double mean_double_area = (faces > 0 && total > 0) ? total / faces : 1.0;

  std::vector<Quadric> face_quadric(faces);
  parallel_for_with_progress(faces, progress, "face quadrics", [&](Eigen::Index f) {
    const double double_area = area_normal[f].norm();
    if (!(double_area > 0)) return;  // a zero-area face has no plane
    const Vec3 normal = area_normal[f] / double_area;
    face_quadric[f] = Quadric::from_plane(normal, mesh.position[mesh.corner_vertex[3 * f]],
                                          double_area / mean_double_area);
  });
  std::vector<Quadric> quadric(mesh.position.size());
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) quadric[mesh.corner_vertex[3 * f + k]] += face_quadric[f];

  if (boundary_planes) {
    for (int h = 0; h < 3 * faces; ++h) {
      if (mesh.opposite[h] >= 0) continue;
      const Vec3& p = mesh.position[mesh.from(h)];
      const Vec3& q = mesh.position[mesh.to(h)];
      const Vec3 along = q - p;
      const Vec3 side = along.cross(area_normal[h / 3]);
      const double length = side.norm();
      if (!(length > 0)) continue;
      const Quadric constraint = Quadric::from_plane(
          side / length, p, kBoundaryConstraintWeight * along.squaredNorm() / mean_double_area);
      quadric[mesh.from(h)] += constraint;
      quadric[mesh.to(h)] += constraint;
    }
  }
  return quadric;
}

/// Quadric::minimizer with a closed-form fast path: when the smallest eigenvalue of A is surely
/// above the pseudo-inverse's cut (λ_min ≥ det A / p₂ with p₂ the sum of the principal 2×2 minors,
/// since p₂ ≥ λ_max·λ_mid, and λ_max ≤ tr A; so det A > 10⁻³ p₂ tr A implies λ_min > 10⁻³ λ_max),
/// the inverse gives the same point without an eigen-decomposition.
Vec3 optimal_position(const Quadric& q, const Vec3& reference) {
  const double c00 = q.a11 * q.a22 - q.a12 * q.a12;
  const double c01 = q.a02 * q.a12 - q.a01 * q.a22;
  const double c02 = q.a01 * q.a12 - q.a02 * q.a11;
  const double c11 = q.a00 * q.a22 - q.a02 * q.a02;
  const double c12 = q.a01 * q.a02 - q.a00 * q.a12;
  const double c22 = q.a00 * q.a11 - q.a01 * q.a01;
  const double det = q.a00 * c00 + q.a01 * c01 + q.a02 * c02;
  const double trace = q.a00 + q.a11 + q.a22;
  const double minors = c00 + c11 + c22;
  if (trace > 0 && minors > 0 && det > 1e-3 * minors * trace) {
    const double s = -1.0 / det;
    return {s * (c00 * q.b0 + c01 * q.b1 + c02 * q.b2), s * (c01 * q.b0 + c11 * q.b1 + c12 * q.b2),
            s * (c02 * q.b0 + c12 * q.b1 + c22 * q.b2)};
  }
  // Rank-one path (flat regions, where the pseudo-inverse keeps only the largest eigenvalue λ₁):
  // power iteration from A's column of largest diagonal gives the top eigenvector u and
  // λ₁ = uᵀAu; when the other two sum to tr A − λ₁ ≤ ½·10⁻³ λ₁, both are surely below the cut
  // and the minimiser is reference + u·uᵀ(−b − A·reference)/λ₁. Each step shrinks the error in
  // u by λ₂/λ₁ < ½·10⁻³, so four reach round-off.
  if (trace > 0) {
    const Eigen::Matrix3d a = q.A();
    Eigen::Index largest;
    a.diagonal().maxCoeff(&largest);
    Vec3 u = a.col(largest);
    for (int step = 0; step < 4; ++step) u = (a * u).normalized();
    const Vec3 au = a * u;
    const double lambda = u.dot(au);
    if (lambda > 0 && std::isfinite(lambda) && trace - lambda <= 0.5e-3 * lambda) {
      const Vec3 residual = -q.b() - a * reference;
      return reference + u * (u.dot(residual) / lambda);
    }
  }
  return q.minimizer(reference);
}

// ---------------------------------------------------------------------------------------------
// The decimator: candidates, costs, fairness criteria, the collapse itself, and the loop.
// ---------------------------------------------------------------------------------------------

/// A collapse of half-edge h: from(h) is removed and merges into to(h), which moves to `target`.
struct Candidate {
  double cost = kInfinity;
  int halfedge = -1;
  Vec3 target = Vec3::Zero();
};

class Decimator {
 public:
  Decimator(HalfedgeMesh& mesh, const QemOptions& options)
      : mesh_(mesh), options_(options), mark_(mesh.position.size(), 0) {
    if (options_.max_normal_deviation_deg > 0)
      min_normal_cosine_ = std::cos(options_.max_normal_deviation_deg * kDegree);
  }

  void set_quadrics(std::vector<Quadric> quadric) { quadric_ = std::move(quadric); }

  /// The best collapse of the edge of half-edge h (either direction, as the operator and the
  /// boundary rule allow); cost = ∞ when none is allowed.
  Candidate evaluate(int h) const {
    const int u = mesh_.from(h), v = mesh_.to(h);
    bool u_may_go, v_may_go;  // may u (v) be the removed vertex?
    if (!removable_ends(h, u_may_go, v_may_go)) return {};
    if (options_.collapse == CollapseOperator::halfedge || !(u_may_go && v_may_go)) {
      Candidate best;
      if (u_may_go) best = endpoint_candidate(h, false);
      if (v_may_go) {
        const Candidate reversed = endpoint_candidate(h, true);
        if (reversed.cost < best.cost) best = reversed;
      }
      return best;
    }
    const Quadric q = quadric_[u] + quadric_[v];
    const Vec3 target = optimal_position(q, 0.5 * (mesh_.position[u] + mesh_.position[v]));
    return {cost_of(u, v, target), h, target};
  }

  // Multiple-choice and the heap store candidates by half-edge; a boundary half-edge collapsed
  // backwards (its `to` removed) is stored as ~h, resolved here.
  struct Resolved { int removed, kept, halfedge_removed_to_kept, twin; };
  Resolved resolve(int stored) const {
    if (stored >= 0) return {mesh_.from(stored), mesh_.to(stored), stored, mesh_.opposite[stored]};
    const int h = ~stored;  // boundary half-edge u→v with v removed: the face is on the right
    return {mesh_.to(h), mesh_.from(h), -1, h};
  }

  /// Link condition, topology guards and the fairness criteria for the collapse `c`.
  bool is_admissible(const Candidate& c) {
    const Resolved r = resolve(c.halfedge);
    const int a = r.removed, b = r.kept;
    // The faces that die: f0 of a→b (third vertex l) and f1 of b→a (third vertex r).
    const int h0 = r.halfedge_removed_to_kept, h1 = r.twin;
    int left = -1, right = -1;
    if (h0 >= 0) {
      left = mesh_.from(prev_halfedge(h0));
      if (mesh_.opposite[next_halfedge(h0)] < 0 && mesh_.opposite[prev_halfedge(h0)] < 0) return false;
    }
    if (h1 >= 0) {
      right = mesh_.from(prev_halfedge(h1));
      if (mesh_.opposite[next_halfedge(h1)] < 0 && mesh_.opposite[prev_halfedge(h1)] < 0) return false;
    }
    if (left == right) return false;  // two faces on the same three vertices
    const bool interior_edge = h0 >= 0 && h1 >= 0;
    if (interior_edge && mesh_.boundary[a] && mesh_.boundary[b]) return false;

    // Link condition: the common neighbours of a and b are exactly the opposite vertices. One
    // pass marks a's neighbours (stamp) and counts them; the pass over b's counts its neighbours
    // (marking them stamp + 1) and the common ones.
    stamp_ += 2;
    const int seen_by_a = stamp_, seen_by_b = stamp_ + 1;
    int valence_a = 0, valence_b = 0, common = 0;
    bool link_ok = true;
    mesh_.for_each_neighbour(a, [&](int x) {
      if (mark_[x] != seen_by_a) { mark_[x] = seen_by_a; ++valence_a; }
    });
    mesh_.for_each_neighbour(b, [&](int x) {
      if (mark_[x] == seen_by_b) return;
      if (mark_[x] == seen_by_a) {
        ++common;
        if (x != left && x != right) link_ok = false;
      }
      mark_[x] = seen_by_b;
      ++valence_b;
    });
    if (!link_ok) return false;
    // A tetrahedron (closed, both valence 3) cannot lose a vertex and stay a surface.
    if (interior_edge && valence_a == 3 && valence_b == 3) return false;
    if (options_.max_valence > 0 && valence_a + valence_b - 2 - common > options_.max_valence) return false;

    // Fairness on the faces that survive around a (and around b when it moves).
    const int dead0 = h0 >= 0 ? h0 / 3 : -1, dead1 = h1 >= 0 ? h1 / 3 : -1;
    bool fair = true;
    auto check_faces_around = [&](int v) {
      mesh_.for_each_outgoing(v, [&](int h) {
        if (!fair) return;
        const int f = h / 3;
        if (f == dead0 || f == dead1) return;
        const Vec3& p = mesh_.position[mesh_.to(h)];
        const Vec3& q = mesh_.position[mesh_.from(prev_halfedge(h))];
        fair = face_stays_fair(mesh_.position[v], c.target, p, q);
      });
    };
    check_faces_around(a);
    if (fair && c.target != mesh_.position[b]) check_faces_around(b);
    return fair;
  }

  /// Performs the collapse `c` (admissible) and returns its record.
  CollapseRecord collapse(const Candidate& c) {
    const Resolved r = resolve(c.halfedge);
    const int a = r.removed, b = r.kept;
    died.clear();
    CollapseRecord record;
    record.removed = a;
    record.kept = b;
    record.removed_position = mesh_.position[a];
    record.kept_position_before = mesh_.position[b];
    record.kept_position_after = c.target;
    if (r.halfedge_removed_to_kept >= 0) record.left = mesh_.from(prev_halfedge(r.halfedge_removed_to_kept));
    if (r.twin >= 0) record.right = mesh_.from(prev_halfedge(r.twin));

    mesh_.for_each_outgoing(a, [&](int h) { mesh_.corner_vertex[h] = b; });
    if (r.halfedge_removed_to_kept >= 0) remove_face(r.halfedge_removed_to_kept, b);
    if (r.twin >= 0) remove_face(r.twin, b);
    mesh_.vertex_halfedge[a] = -1;
    mesh_.position[b] = c.target;
    mesh_.boundary[b] = mesh_.boundary[a] || mesh_.boundary[b];
    quadric_[b] += quadric_[a];
    return record;
  }

  /// Starts loading what evaluating an edge at v reads of v (its quadric and position): a ring's
  /// vertices are fetched together instead of one cache miss after the other.
  void prefetch_vertex(int v) const {
    const char* quadric = reinterpret_cast<const char*>(&quadric_[v]);
    __builtin_prefetch(quadric);
    __builtin_prefetch(quadric + sizeof(Quadric) - 1);
    __builtin_prefetch(&mesh_.position[v]);
  }

  int removed_faces_of(const Candidate& c) const {
    const Resolved r = resolve(c.halfedge);
    return (r.halfedge_removed_to_kept >= 0) + (r.twin >= 0);
  }

  /// The faces removed by the last collapse (the multiple-choice variant drops them from its list).
  std::vector<int> died;

 private:
  /// Which ends of the edge of h may be removed (keep_boundary: a boundary vertex only along a
  /// boundary edge, into a boundary vertex); false when the edge may not collapse at all.
  bool removable_ends(int h, bool& u_may_go, bool& v_may_go) const {
    u_may_go = v_may_go = true;
    if (!options_.keep_boundary) return true;
    const bool ub = mesh_.boundary[mesh_.from(h)], vb = mesh_.boundary[mesh_.to(h)];
    if (mesh_.opposite[h] >= 0 && ub && vb) return false;  // an interior edge between two boundary vertices
    u_may_go = !ub || vb;
    v_may_go = !vb || ub;
    return true;
  }

  /// The half-edge collapse of h's edge that removes from(h) (reversed: to(h)) into the other end.
  Candidate endpoint_candidate(int h, bool reversed) const {
    const int u = mesh_.from(h), v = mesh_.to(h), o = mesh_.opposite[h];
    if (!reversed) return {cost_of(u, v, mesh_.position[v]), h, mesh_.position[v]};
    // A boundary edge has no twin to name the reversed collapse: it is stored as ~h.
    return {cost_of(v, u, mesh_.position[u]), o >= 0 ? o : ~h, mesh_.position[u]};
  }

  /// Removes the face of half-edge h (whose start vertex now reads `kept`), gluing the twins of
  /// its two other sides together and repointing the vertices' outgoing half-edges.
  void remove_face(int h, int kept) {
    const int h1 = next_halfedge(h), h2 = prev_halfedge(h);
    const int o1 = mesh_.opposite[h1], o2 = mesh_.opposite[h2];  // o1: t→kept, o2: kept→t
    const int t = mesh_.from(h2);
    if (o1 >= 0) mesh_.opposite[o1] = o2;
    if (o2 >= 0) mesh_.opposite[o2] = o1;
    mesh_.vertex_halfedge[t] = o1 >= 0 ? o1 : next_halfedge(o2);
    mesh_.vertex_halfedge[kept] = o2 >= 0 ? o2 : next_halfedge(o1);
    mesh_.face_alive[h / 3] = 0;
    died.push_back(h / 3);
  }

  /// The error metric of merging `removed` into `kept` at `target` (§4.2.2).
  double cost_of(int removed, int kept, const Vec3& target) const {
    switch (options_.cost) {
      case CollapseCost::quadric:
        return (quadric_[removed] + quadric_[kept]).error(target);
      case CollapseCost::plane_distance:
        return plane_distance_cost(removed, kept, target);
      case CollapseCost::volume_change:
        return volume_change_cost(removed, kept, target);
    }
    return kInfinity;
  }

  double plane_distance_cost(int removed, int kept, const Vec3& target) const {
    Vec3 sum = Vec3::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    int count = 0;
    auto add = [&](int x) {
      const Vec3& p = mesh_.position[x];
      sum += p;
      second += p * p.transpose();
      ++count;
    };
    mesh_.for_each_neighbour(removed, add);  // duplicates only reweight the fit slightly
    mesh_.for_each_neighbour(kept, add);
    const Vec3 centroid = sum / count;
    const Eigen::Matrix3d covariance = second / count - centroid * centroid.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(covariance);
    const double distance = eigen.eigenvectors().col(0).dot(target - centroid);
    return distance * distance;
  }

  double volume_change_cost(int removed, int kept, const Vec3& target) const {
    double volume = 0;
    auto sweep = [&](int v) {
      const Vec3& from = mesh_.position[v];
      if (from == target) return;
      mesh_.for_each_outgoing(v, [&](int h) {
        const Vec3& p = mesh_.position[mesh_.to(h)];
        const Vec3& q = mesh_.position[mesh_.from(prev_halfedge(h))];
        volume += (target - from).dot((p - from).cross(q - from)) / 6.0;
      });
    };
    sweep(removed);
    sweep(kept);
    return std::abs(volume);
  }

  /// The fairness criteria (§4.2.3) on one surviving face (moving, p, q) whose corner `moving`
  /// goes from `before` to `after`.
  bool face_stays_fair(const Vec3& before, const Vec3& after, const Vec3& p, const Vec3& q) const {
    const Vec3 old_normal = (p - before).cross(q - before);
    const Vec3 new_normal = (p - after).cross(q - after);
    const double dot = old_normal.dot(new_normal);
    const double old_norm = old_normal.norm();
    if (options_.prevent_normal_flips && old_norm > 0 && !(dot > 0)) return false;
    if (min_normal_cosine_ > -1 && old_norm > 0 && dot < min_normal_cosine_ * old_norm * new_normal.norm())
      return false;
    if (options_.min_triangle_quality > 0) {
      const double quality_after = triangle_quality(new_normal.norm(), after, p, q);
      if (quality_after < options_.min_triangle_quality &&
          quality_after < triangle_quality(old_norm, before, p, q))
        return false;
    }
    return true;
  }

  static double triangle_quality(double double_area, const Vec3& a, const Vec3& b, const Vec3& c) {
    const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
    return edges > 0 ? 2.0 * std::sqrt(3.0) * double_area / edges : 0.0;
  }

  HalfedgeMesh& mesh_;
  const QemOptions& options_;
  std::vector<Quadric> quadric_;
  std::vector<int> mark_;
  int stamp_ = 0;
  double min_normal_cosine_ = -2;
};

/// An addressable 4-ary min-heap of 8-byte entries, at most one per edge: the four children of
/// a node share a cache line, so a sift touches half as many lines as a binary heap's would (the
/// queue holds millions), and `slot_` (per half-edge: its entry's index, −1 when none) lets a
/// changed edge's key move in place and a dying edge's entry leave at once.
struct QueueEntry {
  float cost;  // single precision: the key only orders; the collapse re-evaluates in double
  int edge;    // canonical half-edge of the edge
};

class CollapseQueue {
 public:
  CollapseQueue(std::size_t edge_slots, const HalfedgeMesh& mesh) : slot_(edge_slots, -1), mesh_(mesh) {}
  void reserve(std::size_t n) { entries_.reserve(n); }
  bool empty() const { return entries_.empty(); }
  /// Adds without ordering (edge not queued yet); call heapify() before the first pop.
  void append(const QueueEntry& e) {
    slot_[e.edge] = static_cast<int>(entries_.size());
    entries_.push_back(e);
  }
  void heapify() {
    for (std::size_t i = entries_.size() / 4 + 1; i-- > 0;) sift_down(i);
  }
  /// Inserts the edge's entry, or moves its key when it has one.
  void set(const QueueEntry& e) {
    const int i = slot_[e.edge];
    if (i < 0) {
      entries_.push_back(e);
      sift_up(entries_.size() - 1);
      return;
    }
    const QueueEntry old = entries_[i];
    entries_[i].cost = e.cost;
    if (less(e, old)) sift_up(i);
    else if (less(old, e)) sift_down(i);
  }
  /// Drops the edge's entry, if it has one.
  void remove(int edge) {
    const int i = slot_[edge];
    if (i < 0) return;
    slot_[edge] = -1;
    const QueueEntry last = entries_.back();
    entries_.pop_back();
    if (static_cast<std::size_t>(i) == entries_.size()) return;
    entries_[i] = last;
    slot_[last.edge] = i;
    sift_up(i);
    sift_down(slot_[last.edge]);
  }
  const QueueEntry& top() const { return entries_.front(); }
  void prefetch(int edge) const { __builtin_prefetch(&slot_[edge]); }
  /// The smallest key below the top (+∞ when the top is alone).
  float runner_up_cost() const {
    float best = std::numeric_limits<float>::infinity();
    for (std::size_t c = 1; c < std::min<std::size_t>(5, entries_.size()); ++c) best = std::min(best, entries_[c].cost);
    return best;
  }
  void pop() { remove(entries_.front().edge); }

 private:
  void place(std::size_t i, const QueueEntry& e) {
    entries_[i] = e;
    slot_[e.edge] = static_cast<int>(i);
  }
  void sift_up(std::size_t i) {
    const QueueEntry moving = entries_[i];
    while (i > 0) {
      const std::size_t parent = (i - 1) / 4;
      if (!less(moving, entries_[parent])) break;
      place(i, entries_[parent]);
      i = parent;
    }
    place(i, moving);
  }
  void sift_down(std::size_t i) {
    const std::size_t n = entries_.size();
    if (i >= n) return;
    const QueueEntry moving = entries_[i];
    while (true) {
      const std::size_t first = 4 * i + 1;
      if (first >= n) break;
      // The grandchildren (16 entries, two cache lines) are fetched while the children compare.
      const std::size_t grandchildren = 4 * first + 1;
      if (grandchildren < n) {
        __builtin_prefetch(entries_.data() + grandchildren);
        __builtin_prefetch(entries_.data() + std::min(grandchildren + 8, n - 1));
      }
      std::size_t best = first;
      const std::size_t last = std::min(first + 4, n);
      for (std::size_t c = first + 1; c < last; ++c)
        if (less(entries_[c], entries_[best])) best = c;
      if (!less(entries_[best], moving)) break;
      place(i, entries_[best]);
      i = best;
    }
    place(i, moving);
  }
  /// Key order; ties (many exactly flat collapses cost 0) go to the shorter edge, then the smaller
  /// half-edge, so the order does not depend on the heap's layout.
  bool less(const QueueEntry& x, const QueueEntry& y) const {
    if (x.cost != y.cost) return x.cost < y.cost;
    const double lx = (mesh_.position[mesh_.from(x.edge)] - mesh_.position[mesh_.to(x.edge)]).squaredNorm();
    const double ly = (mesh_.position[mesh_.from(y.edge)] - mesh_.position[mesh_.to(y.edge)]).squaredNorm();
    return lx < ly || (lx == ly && x.edge < y.edge);
  }
  std::vector<QueueEntry> entries_;
  std::vector<int> slot_;
  const HalfedgeMesh& mesh_;
};

void check_options(const QemOptions& options) {
  if (options.target_faces < 0)
    throw InputError("decimate: target_faces must be >= 0, got " + std::to_string(options.target_faces));
  if (!(options.max_error >= 0) || !std::isfinite(options.max_error))
    throw InputError("decimate: max_error must be a finite value >= 0, got " + std::to_string(options.max_error));
  if (options.target_faces == 0 && options.max_error == 0)
    throw InputError("decimate: no stop rule: give target_faces > 0 or max_error > 0");
  if (options.candidates < 0)
    throw InputError("decimate: candidates must be >= 0, got " + std::to_string(options.candidates));
  if (options.max_valence < 0)
    throw InputError("decimate: max_valence must be >= 0, got " + std::to_string(options.max_valence));
  if (!(options.min_triangle_quality >= 0 && options.min_triangle_quality <= 1))
    throw InputError("decimate: min_triangle_quality must be in [0, 1], got " +
                     std::to_string(options.min_triangle_quality));
  if (!(options.max_normal_deviation_deg >= 0 && options.max_normal_deviation_deg <= 180))
    throw InputError("decimate: max_normal_deviation_deg must be in [0, 180], got " +
                     std::to_string(options.max_normal_deviation_deg));
}

/// splitmix64: the multiple-choice variant's random stream.
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t operator()() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
};

}  // namespace

QemResult decimate_qem(const VertexRef& V, const FaceRef& F, const QemOptions& options, const Progress& progress) {
  validate_mesh(V, F);
  check_options(options);
  if (V.rows() >= std::numeric_limits<int>::max() / 4 || F.rows() >= std::numeric_limits<int>::max() / 4)
    throw InputError("decimate: mesh too large (more than 2^29 vertices or faces)");

  HalfedgeMesh mesh = build_halfedge_mesh(V, F);
  const int face_slots = static_cast<int>(mesh.face_alive.size());
  if (face_slots == 0)
    throw InputError("decimate: every face of F has a repeated vertex index: no triangle to decimate");
  Decimator decimator(mesh, options);
  decimator.set_quadrics(initial_quadrics(mesh, options.keep_boundary, progress.subrange(0.0, 0.1)));

  QemResult result;
  Eigen::Index faces = face_slots;
  const Eigen::Index target = options.target_faces;
  const double max_error = options.max_error > 0 ? options.max_error : kInfinity;
  const Progress loop_progress = progress.subrange(0.2, 0.98);
  const Eigen::Index to_remove = target > 0 ? std::max<Eigen::Index>(faces - target, 1) : faces;
  auto report = [&] {
    loop_progress.report(std::min(1.0, static_cast<double>(face_slots - faces) / static_cast<double>(to_remove)),
                         "collapses");
  };
  auto perform = [&](const Candidate& c) {
    faces -= decimator.removed_faces_of(c);
    CollapseRecord record = decimator.collapse(c);
    result.max_collapse_error = std::max(result.max_collapse_error, c.cost);
    ++result.collapse_count;
    if (options.record_collapses) result.collapses.push_back(record);
    return record;
  };
  auto done = [&] { return target > 0 && faces <= target; };

  if (options.candidates == 0) {
    // Full priority queue, updated eagerly: a collapse re-costs every edge around the kept vertex
    // (the only ones whose quadric, position or boundary flag changed) and moves its key in place;
    // the entries of the edges that die or are glued (renamed) leave before the collapse. Each
    // edge has at most one entry, so no dead entries are popped. The top is still re-evaluated
    // and goes back if its cost grew past the next key (costs that depend on the wider ring).
    // An edge rejected by the checks leaves the queue until an edge at one of its ends collapses.
    CollapseQueue heap(3 * static_cast<std::size_t>(face_slots), mesh);
    {
      std::vector<float> cost(3 * static_cast<std::size_t>(face_slots), std::numeric_limits<float>::infinity());
      parallel_for_with_progress(3 * static_cast<Eigen::Index>(face_slots), progress.subrange(0.1, 0.2),
                                 "edge costs", [&](Eigen::Index h) {
        if (mesh.canonical(static_cast<int>(h)) == h) cost[h] = static_cast<float>(decimator.evaluate(static_cast<int>(h)).cost);
      });
      heap.reserve(cost.size() / 2 + 16);
      for (std::size_t h = 0; h < cost.size(); ++h)
        if (cost[h] < std::numeric_limits<float>::infinity()) heap.append({cost[h], static_cast<int>(h)});
      heap.heapify();
    }
    auto requeue = [&](int edge) {
      const double c = decimator.evaluate(edge).cost;
      if (c < kInfinity) heap.set({static_cast<float>(c), edge});
      else heap.remove(edge);
    };
    auto drop_face_edges = [&](int h) {  // the edges of h's face, which dies or is glued away
      if (h < 0) return;
      const int first = 3 * (h / 3);
      for (int g = first; g < first + 3; ++g) {
        heap.remove(g);
        if (mesh.opposite[g] >= 0) heap.remove(mesh.opposite[g]);
      }
    };
    std::vector<int> ring;
    ring.reserve(64);
    while (!done() && !heap.empty()) {
      const int e = heap.top().edge;
      const Candidate c = decimator.evaluate(e);
      if (c.cost < kInfinity && static_cast<float>(c.cost) > heap.runner_up_cost()) {
        heap.set({static_cast<float>(c.cost), e});  // its cost grew: not the cheapest now
        continue;
      }
      heap.pop();
      if (c.cost > max_error) break;
      if (!(c.cost < kInfinity) || !decimator.is_admissible(c)) continue;  // re-queued when its ring changes
      const Decimator::Resolved dying = decimator.resolve(c.halfedge);
      drop_face_edges(dying.halfedge_removed_to_kept);
      drop_face_edges(dying.twin);
      const CollapseRecord record = perform(c);
      // The kept vertex's edges: gathered (their far ends and heap slots fetched meanwhile), then
      // re-costed.
      ring.clear();
      mesh.for_each_outgoing(record.kept, [&](int h) {
        ring.push_back(mesh.canonical(h));
        decimator.prefetch_vertex(mesh.to(h));
        heap.prefetch(ring.back());
        const int incoming = prev_halfedge(h);
        if (mesh.opposite[incoming] < 0) {
          ring.push_back(incoming);
          decimator.prefetch_vertex(mesh.from(incoming));
          heap.prefetch(incoming);
        }
      });
      for (const int edge : ring) requeue(edge);
      report();
    }
  } else {
    // Multiple choice (Wu & Kobbelt 2002): the best of k random live edges each step. Live faces
    // are kept in a list with O(1) removal so the sampling stays uniform as faces die.
    std::vector<int> live(face_slots), slot_of(face_slots);
    for (int f = 0; f < face_slots; ++f) live[f] = slot_of[f] = f;
    SplitMix64 random{options.seed};
    const int patience = 1000;  // consecutive steps without an admissible collapse below the bound
    int misses = 0;
    std::vector<Candidate> drawn(options.candidates);
    while (!done() && !live.empty() && misses < patience) {
      for (Candidate& c : drawn) {
        const auto pick = random();
        const int f = live[pick % live.size()];
        c = decimator.evaluate(mesh.canonical(3 * f + static_cast<int>((pick >> 40) % 3)));
      }
      // The cheapest admissible one: the checks only for as many as needed, cheapest first.
      std::sort(drawn.begin(), drawn.end(), [](const Candidate& x, const Candidate& y) { return x.cost < y.cost; });
      Candidate best;
      for (const Candidate& c : drawn) {
        if (!(c.cost < kInfinity && c.cost <= max_error)) break;
        if (decimator.is_admissible(c)) { best = c; break; }
      }
      if (!(best.cost < kInfinity)) { ++misses; continue; }
      misses = 0;
      perform(best);
      for (const int f : decimator.died) {
        const int s = slot_of[f];
        live[s] = live.back();
        slot_of[live[s]] = s;
        live.pop_back();
      }
      report();
    }
  }
  loop_progress.report(1.0, "collapses");
  result.target_reached = done();

  // Compact the live faces and their vertices.
  std::vector<int> new_index(mesh.position.size(), -1);
  Eigen::Index output_vertices = 0;
  for (int f = 0; f < face_slots; ++f)
    if (mesh.face_alive[f])
      for (int k = 0; k < 3; ++k) {
        int& slot = new_index[mesh.corner_vertex[3 * f + k]];
        if (slot < 0) slot = static_cast<int>(output_vertices++);
      }
  result.V.resize(output_vertices, 3);
  result.vertex_origin.resize(output_vertices);
  for (std::size_t v = 0; v < new_index.size(); ++v)
    if (new_index[v] >= 0) {
      result.V.row(new_index[v]) = mesh.position[v].transpose();
      result.vertex_origin(new_index[v]) = mesh.split_origin.empty() ? static_cast<int>(v) : mesh.split_origin[v];
    }
  result.F.resize(faces, 3);
  Eigen::Index row = 0;
  for (int f = 0; f < face_slots; ++f)
    if (mesh.face_alive[f]) {
      for (int k = 0; k < 3; ++k) result.F(row, k) = new_index[mesh.corner_vertex[3 * f + k]];
      ++row;
    }
  if (!mesh.split_origin.empty())
    result.split_vertex_origin = Eigen::Map<const Eigen::VectorXi>(mesh.split_origin.data(),
                                                                   static_cast<Eigen::Index>(mesh.split_origin.size()));
  progress.report(1.0, "decimate");
  return result;
}

}  // namespace meshsmith::decimation
