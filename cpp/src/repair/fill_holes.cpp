// Hole filling (fill_holes.h). Works on a normalized copy of the vertices (core/normalization.h:
// one exact power-of-two scaling, so angles, area comparisons and the √2 rule do not depend on the
// units). Per loop: the weight table of the dynamic programme over chords (i, k) of the loop
// polygon, the triangles read back from it, the patch built as its own TriMesh (one vertex per loop
// position, so a loop through a pinched vertex still gives a disk), refined there, then appended.
#include "hole_delaunay.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/mesh.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/repair/fill_holes.h>
#include <meshsmith/smoothing/fairing.h>
#include <meshsmith/topology/boundary.h>
#include <meshsmith/topology/components.h>
#include <meshsmith/topology/edge_incidence.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace meshsmith::repair {
namespace {

using Vec = Eigen::Vector3d;

std::int64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::int64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}
std::int64_t side_key(int a, int b) {
  return (static_cast<std::int64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

/// Unit normal of (a, b, c); zero for a degenerate triangle.
Vec unit_normal(const Vec& a, const Vec& b, const Vec& c) {
  Vec n = (b - a).cross(c - a);
  const double length = n.norm();
  return length > 0.0 ? Vec(n / length) : Vec::Zero();
}

/// Cosine of the dihedral angle between two unit normals (1: flat); -1 when either is degenerate.
double dihedral_cosine(const Vec& n, const Vec& m) {
  if (n.isZero() || m.isZero()) return -1.0;
  return n.dot(m);
}

/// Unit Newell normal of the closed polygon through the points of `loop` (oriented by its order).
template <typename PointOf>
Vec newell_normal(const std::vector<int>& loop, PointOf point) {
  Vec n = Vec::Zero();
  for (std::size_t j = 0; j < loop.size(); ++j) n += point(loop[j]).cross(point(loop[(j + 1) % loop.size()]));
  const double length = n.norm();
  return length > 0.0 ? Vec(n / length) : Vec::Zero();
}

/// Liepa's weight: the largest dihedral angle (kept as its cosine: larger is better), then area.
struct Weight {
  double cosine = 2.0;   // 2: no angle yet (a loop edge)
  double area = 0.0;
  bool valid = false;
};
bool better(const Weight& a, const Weight& b) {
  if (!b.valid) return a.valid;
  if (!a.valid) return false;
  if (a.cosine != b.cosine) return a.cosine > b.cosine;
  return a.area < b.area;
}

/// One hole as the dynamic programme sees it: loop positions p[0..n), their mesh vertices, and for
/// each loop edge (i, i+1 mod n) the normal of the mesh face on it, in the patch's own orientation.
struct Polygon {
  std::vector<Vec> p;
  std::vector<int> vertex;
  std::vector<Vec> outer_normal;
  int size() const { return static_cast<int>(p.size()); }
};

/// Whether triangles (i, m, k) of the polygon use a side between two mesh vertices twice (the
/// polygon passes a vertex twice, and chords from both copies can map to one edge).
bool repeats_a_side(const std::vector<std::array<int, 3>>& triangles, const Polygon& polygon) {
  std::unordered_set<std::int64_t> sides;
  for (const auto& t : triangles)
    for (int s = 0; s < 3; ++s)
      if (!sides.insert(side_key(polygon.vertex[t[s]], polygon.vertex[t[(s + 1) % 3]])).second) return true;
  return false;
}

/// Chords (i, k) that a patch may not use: an edge the mesh already has, or both ends on one vertex.
struct ChordRule {
  const Polygon& polygon;
  const std::unordered_set<std::int64_t>& edges;   // mesh edges between boundary vertices, and patch edges
  bool allowed(int i, int k) const {
    if (k == i + 1 || (i == 0 && k == polygon.size() - 1)) return true;   // a loop edge
    const int a = polygon.vertex[i], b = polygon.vertex[k];
    return a != b && edges.find(edge_key(a, b)) == edges.end();
  }
  bool triangle_allowed(int i, int m, int k) const {
    const int a = polygon.vertex[i], b = polygon.vertex[m], c = polygon.vertex[k];
    return a != b && b != c && a != c;
  }
};

/// The best triangle on chord (i, k) and the normal of that triangle, for the parent's angle.
struct Chord {
  Weight weight;
  int apex = -1;
  Vec normal = Vec::Zero();
};

/// Weight of triangle (i, m, k) over the chords (i, m) and (m, k) already solved.
Weight combine(const Polygon& polygon, int i, int m, int k, const Chord& left, const Chord& right, Vec& normal) {
  Weight w;
  if (!left.weight.valid || !right.weight.valid) return w;
  normal = unit_normal(polygon.p[i], polygon.p[m], polygon.p[k]);
  double cosine = std::min({left.weight.cosine, right.weight.cosine, dihedral_cosine(normal, left.normal),
                            dihedral_cosine(normal, right.normal)});
  const int n = polygon.size();
  if (i == 0 && k == n - 1) cosine = std::min(cosine, dihedral_cosine(normal, polygon.outer_normal[n - 1]));
  w.cosine = cosine;
  w.area = left.weight.area + right.weight.area +
           0.5 * (polygon.p[m] - polygon.p[i]).cross(polygon.p[k] - polygon.p[i]).norm();
  w.valid = true;
  return w;
}

Chord loop_edge(const Polygon& polygon, int i) {
  Chord c;
  c.weight.valid = true;
  c.normal = polygon.outer_normal[i];
  return c;
}

/// Triangles (i, m, k) of the solved polygon, read from the apex of each chord from (0, n − 1).
template <typename ApexOf>
std::vector<std::array<int, 3>> read_triangles(int n, ApexOf apex_of) {
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::pair<int, int>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, k] = stack.back();
    stack.pop_back();
    if (k - i < 2) continue;
    const int m = apex_of(i, k);
    triangles.push_back({i, m, k});
    stack.emplace_back(i, m);
    stack.emplace_back(m, k);
  }
  return triangles;
}

/// The exact dynamic programme over every chord: O(n³) time, O(n²) memory. Empty if no
/// triangulation obeys the chord rule.
std::vector<std::array<int, 3>> triangulate_exact(const Polygon& polygon, const ChordRule& rule, const Progress& progress) {
  const int n = polygon.size();
  std::vector<Chord> table(static_cast<std::size_t>(n) * n);
  auto at = [&](int i, int k) -> Chord& { return table[static_cast<std::size_t>(i) * n + k]; };
  for (int i = 0; i + 1 < n; ++i) at(i, i + 1) = loop_edge(polygon, i);
  for (int span = 2; span < n; ++span) {
    progress.report(static_cast<double>(span) / n, "filling holes");
    for (int i = 0; i + span < n; ++i) {
      const int k = i + span;
      if (!rule.allowed(i, k)) continue;
      Chord& best = at(i, k);
      for (int m = i + 1; m < k; ++m) {
        if (!rule.triangle_allowed(i, m, k)) continue;
        Vec normal;
        const Weight w = combine(polygon, i, m, k, at(i, m), at(m, k), normal);
        if (better(w, best.weight)) {
          best.weight = w;
          best.apex = m;
          best.normal = normal;
        }
      }
    }
  }
  if (n < 3 || !at(0, n - 1).weight.valid) return {};
  return read_triangles(n, [&](int i, int k) { return at(i, k).apex; });
}

/// The search space of Zou et al.: the triangles whose three edges are edges of the 3D Delaunay
/// triangulation of the loop's vertices or edges of the loop. Taking the loop's edges in as well
/// keeps a loop whose edges are not all Delaunay (a zig-zag of nearly cocircular quadrilaterals, as
/// a staircase cut through a grid leaves) inside the restricted search. Empty if the Delaunay
/// triangulation is degenerate (hole_delaunay.h).
std::vector<std::array<int, 3>> delaunay_search_space(const Polygon& polygon) {
  const int n = polygon.size();
  // A vertex the loop passes twice (a pinched vertex, the ends of an island's bridge) is one
  // Delaunay site; its edges go to each of its loop positions.
  std::unordered_map<int, int> site_of;
  std::vector<Vec> sites;
  std::vector<std::vector<int>> positions;
  for (int i = 0; i < n; ++i) {
    const auto [it, inserted] = site_of.emplace(polygon.vertex[i], static_cast<int>(sites.size()));
    if (inserted) {
      sites.push_back(polygon.p[i]);
      positions.emplace_back();
    }
    positions[it->second].push_back(i);
  }
  const auto site_edges = detail::delaunay_loop_edges(sites);
  if (site_edges.empty()) return {};
  std::vector<std::array<int, 2>> edges;
  edges.reserve(site_edges.size() + n);
  for (const auto& [s, t] : site_edges)
    for (const int i : positions[s])
      for (const int k : positions[t]) edges.push_back({std::min(i, k), std::max(i, k)});
  for (int i = 0; i < n; ++i) edges.push_back({std::min(i, (i + 1) % n), std::max(i, (i + 1) % n)});
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  // Neighbours above each vertex, ascending (edges are sorted): a triangle a < b < c is found once,
  // from its edge (a, b), as a common upper neighbour c of a and b.
  std::vector<int> offsets(n + 1, 0), upper(edges.size());
  for (const auto& e : edges) ++offsets[e[0] + 1];
  for (int v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
  for (std::size_t j = 0; j < edges.size(); ++j) upper[j] = edges[j][1];
  std::vector<std::array<int, 3>> triangles;
  for (const auto& [a, b] : edges) {
    const int* p = upper.data() + offsets[a];
    const int* p_end = upper.data() + offsets[a + 1];
    const int* q = upper.data() + offsets[b];
    const int* q_end = upper.data() + offsets[b + 1];
    while (p != p_end && q != q_end) {
      if (*p < *q) ++p;
      else if (*q < *p) ++q;
      else { triangles.push_back({a, b, *p}); ++p; ++q; }
    }
  }
  return triangles;
}

/// The dynamic programme restricted to delaunay_search_space. Empty if it holds no triangulation
/// of the polygon that obeys the chord rule.
std::vector<std::array<int, 3>> triangulate_delaunay(const Polygon& polygon, const ChordRule& rule) {
  const int n = polygon.size();
  auto candidates = delaunay_search_space(polygon);
  if (candidates.empty()) return {};
  // By chord span, so that both sub-chords of a triangle are solved before it.
  std::sort(candidates.begin(), candidates.end(), [](const auto& s, const auto& t) {
    const int ds = s[2] - s[0], dt = t[2] - t[0];
    if (ds != dt) return ds < dt;
    return s < t;
  });
  std::unordered_map<std::int64_t, Chord> solved;
  solved.reserve(2 * candidates.size());
  const Chord missing;
  auto chord = [&](int i, int k) -> Chord {
    if (k == i + 1) return loop_edge(polygon, i);
    const auto found = solved.find(side_key(i, k));
    return found == solved.end() ? missing : found->second;
  };
  for (const auto& [i, m, k] : candidates) {
    if (!rule.allowed(i, k) || !rule.triangle_allowed(i, m, k)) continue;
    Vec normal;
    const Weight w = combine(polygon, i, m, k, chord(i, m), chord(m, k), normal);
    if (!w.valid) continue;
    Chord& best = solved[side_key(i, k)];
    if (better(w, best.weight)) {
      best.weight = w;
      best.apex = m;
      best.normal = normal;
    }
  }
  const auto top = solved.find(side_key(0, n - 1));
  if (top == solved.end() || !top->second.weight.valid) return {};
  return read_triangles(n, [&](int i, int k) { return solved.at(side_key(i, k)).apex; });
}

/// Refinement of one patch (Liepa 2003, §3.2): split a triangle at its centroid c when, for each
/// corner v, density·|c − v| exceeds both σ(c) (the mean σ of the corners) and σ(v) (for a loop
/// vertex, the mean length of its edges in the mesh); relax by flipping the edges that are not
/// locally Delaunay (opposite angles summing above π); repeat until no triangle splits.
/// The loop's vertices (the first n of `patch`) stay where they are, no flip makes an edge between
/// two of them, so the patch adds no edge the mesh may already have.
/// Refinement stops splitting a patch at this many faces (a hole whose rim has near-zero edges
/// would otherwise ask for a number of faces without bound).
constexpr std::size_t kMaxRefinedFaces = std::size_t(1) << 21;

void refine_patch(TriMesh& patch, int loop_vertices, std::vector<double>& sigma, double density) {
  auto is_loop = [&](TriMesh::VertexHandle v) { return v.idx() < loop_vertices; };
  auto angle_at = [&](TriMesh::VertexHandle apex, TriMesh::VertexHandle a, TriMesh::VertexHandle b) {
    const Vec p = Eigen::Map<const Vec>(patch.point(apex).data());
    const Vec u = Eigen::Map<const Vec>(patch.point(a).data()) - p;
    const Vec w = Eigen::Map<const Vec>(patch.point(b).data()) - p;
    return std::atan2(u.cross(w).norm(), u.dot(w));
  };
  auto relax = [&](TriMesh::EdgeHandle e) {
    if (patch.is_boundary(e)) return false;
    const auto h = patch.halfedge_handle(e, 0), g = patch.halfedge_handle(e, 1);
    const auto a = patch.to_vertex_handle(h), b = patch.to_vertex_handle(g);
    const auto c = patch.to_vertex_handle(patch.next_halfedge_handle(h));
    const auto d = patch.to_vertex_handle(patch.next_halfedge_handle(g));
    if (is_loop(c) && is_loop(d)) return false;
    if (angle_at(c, a, b) + angle_at(d, a, b) <= M_PI * (1.0 + 1e-12)) return false;
    if (!patch.is_flip_ok(e)) return false;
    patch.flip(e);
    return true;
  };
  auto relax_all = [&] {
    // Delaunay flips terminate on a plane; a cap keeps a curved patch from cycling on ties.
    for (int pass = 0; pass < 100; ++pass) {
      bool flipped = false;
      for (auto e : patch.edges()) flipped = relax(e) || flipped;
      if (!flipped) break;
    }
  };
  // Each pass at least halves the longest edges' excess over σ; 64 passes bound a patch of any size.
  for (int pass = 0; pass < 64; ++pass) {
    bool split = false;
    const std::size_t faces = patch.n_faces();
    for (std::size_t fi = 0; fi < faces && patch.n_faces() < kMaxRefinedFaces; ++fi) {
      const TriMesh::FaceHandle f(static_cast<int>(fi));
      TriMesh::VertexHandle corner[3];
      int c = 0;
      for (auto v : patch.fv_range(f)) corner[c++] = v;
      Vec centroid = Vec::Zero();
      double sigma_c = 0.0;
      for (const auto v : corner) {
        centroid += Eigen::Map<const Vec>(patch.point(v).data());
        sigma_c += sigma[v.idx()];
      }
      centroid /= 3.0;
      sigma_c /= 3.0;
      bool wanted = true;
      for (const auto v : corner) {
        const double d = density * (centroid - Eigen::Map<const Vec>(patch.point(v).data())).norm();
        if (!(d > sigma_c && d > sigma[v.idx()])) wanted = false;
      }
      if (!wanted) continue;
      TriMesh::HalfedgeHandle sides[3];
      c = 0;
      for (auto h : patch.fh_range(f)) sides[c++] = h;
      patch.split(f, TriMesh::Point(centroid.x(), centroid.y(), centroid.z()));
      sigma.push_back(sigma_c);
      for (const auto h : sides) relax(patch.edge_handle(h));
      split = true;
    }
    if (!split) break;
    relax_all();
  }
  relax_all();
}

/// The patch measures of HolePatch (max_dihedral_angle, edge_length_ratio) on the final positions
/// X (normalized, input vertices then new ones) and faces (input then patches).
void measure_patch(HolePatch& patch, const std::vector<int>& loop, const VertexMatrix& X, const FaceRef& F_in,
                   const std::vector<std::array<int, 3>>& new_faces, const std::unordered_map<std::int64_t, int>& boundary_side,
                   const topology::EdgeIncidence& incidence, const std::vector<int>& vertex_edge_offsets,
                   const std::vector<int>& vertex_edges) {
  auto point = [&](int v) { return Vec(X.row(v).transpose()); };
  const int first = patch.face_begin - static_cast<int>(F_in.rows());
  std::unordered_map<std::int64_t, int> side_face;   // patch side a -> b: its face, local
  for (int f = 0; f < patch.faces; ++f) {
    const auto& t = new_faces[first + f];
    for (int s = 0; s < 3; ++s) side_face[side_key(t[s], t[(s + 1) % 3])] = f;
  }
  auto normal_of = [&](const std::array<int, 3>& t) { return unit_normal(point(t[0]), point(t[1]), point(t[2])); };
  double worst = 1.0;
  double inner_sum = 0.0, loop_sum = 0.0;
  int inner_count = 0, loop_count = 0;
  for (int f = 0; f < patch.faces; ++f) {
    const auto& t = new_faces[first + f];
    const Vec n = normal_of(t);
    for (int s = 0; s < 3; ++s) {
      const int a = t[s], b = t[(s + 1) % 3];
      const double length = (point(a) - point(b)).norm();
      const auto twin = side_face.find(side_key(b, a));
      if (twin != side_face.end()) {
        if (twin->second < f) continue;   // each inner edge once
        worst = std::min(worst, dihedral_cosine(n, normal_of(new_faces[first + twin->second])));
        inner_sum += length;
        ++inner_count;
      } else {
        const auto outer = boundary_side.find(side_key(b, a));
        if (outer == boundary_side.end()) continue;
        worst = std::min(worst, dihedral_cosine(n, normal_of({b, a, outer->second})));
        loop_sum += length;
        ++loop_count;
      }
    }
  }
  patch.max_dihedral_angle = std::acos(std::clamp(worst, -1.0, 1.0)) * 180.0 / M_PI;
  // The ring: every mesh edge at a loop vertex, once.
  std::unordered_set<int> ring;
  for (const int v : loop)
    for (int j = vertex_edge_offsets[v]; j < vertex_edge_offsets[v + 1]; ++j) ring.insert(vertex_edges[j]);
  double ring_sum = 0.0;
  for (const int e : ring) ring_sum += (point(incidence.edges(e, 0)) - point(incidence.edges(e, 1))).norm();
  const double patch_mean = inner_count ? inner_sum / inner_count : loop_sum / std::max(loop_count, 1);
  const double ring_mean = ring.empty() ? 0.0 : ring_sum / static_cast<double>(ring.size());
  patch.edge_length_ratio = ring_mean > 0.0 ? patch_mean / ring_mean : std::numeric_limits<double>::quiet_NaN();
}

/// Fairs the new vertices of one patch (rows [first_new, first_new + count) of `points`, the
/// normalized input vertices W followed by new_points): the bi-Laplacian system on the patch's
/// faces and the mesh faces at its loop's vertices (their full one-rings: what Δ² at a new vertex
/// reaches), every vertex but the new ones held.
void fair_patch(const VertexMatrix& W, std::vector<Vec>& new_points, int first_new, int count,
                const std::vector<std::array<int, 3>>& patch_faces, const std::vector<int>& loop, const FaceRef& F,
                const std::vector<int>& face_offsets, const std::vector<int>& vertex_faces) {
  const int n_input = static_cast<int>(W.rows());
  std::unordered_map<int, int> local;
  std::vector<int> global;
  auto index = [&](int v) {
    const auto [it, inserted] = local.emplace(v, static_cast<int>(global.size()));
    if (inserted) global.push_back(v);
    return it->second;
  };
  std::vector<std::array<int, 3>> faces;
  for (const auto& t : patch_faces) faces.push_back({index(t[0]), index(t[1]), index(t[2])});
  std::unordered_set<int> ring;
  for (const int v : loop)
    for (int j = face_offsets[v]; j < face_offsets[v + 1]; ++j) ring.insert(vertex_faces[j]);
  std::vector<int> ring_faces(ring.begin(), ring.end());
  std::sort(ring_faces.begin(), ring_faces.end());
  for (const int f : ring_faces) faces.push_back({index(F(f, 0)), index(F(f, 1)), index(F(f, 2))});
  VertexMatrix X(static_cast<Eigen::Index>(global.size()), 3);
  std::vector<int> held;
  for (std::size_t k = 0; k < global.size(); ++k) {
    const int v = global[k];
    const bool is_new = v >= first_new && v < first_new + count;
    if (is_new) X.row(static_cast<Eigen::Index>(k)) = new_points[v - n_input].transpose();
    else X.row(static_cast<Eigen::Index>(k)) = W.row(v);
    if (!is_new) held.push_back(static_cast<int>(k));
  }
  FaceMatrix G(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t k = 0; k < faces.size(); ++k) G.row(static_cast<Eigen::Index>(k)) << faces[k][0], faces[k][1], faces[k][2];
  const VertexMatrix faired = smoothing::bilaplacian(X, G, held);
  for (std::size_t k = 0; k < global.size(); ++k) {
    const int v = global[k];
    if (v >= first_new && v < first_new + count) new_points[v - n_input] = faired.row(static_cast<Eigen::Index>(k)).transpose();
  }
}

}  // namespace

FillHolesResult fill_holes(const VertexRef& V, const FaceRef& F, const FillHolesOptions& options,
                           const Progress& progress) {
  validate_mesh(V, F);
  if (options.max_hole_edges < 0) throw InputError("max_hole_edges must be >= 0 (0: no limit)");
  if (!(options.max_hole_diameter >= 0.0) || !std::isfinite(options.max_hole_diameter))
    throw InputError("max_hole_diameter must be a finite number >= 0 (0: no limit)");
  if (!(options.density > 0.0) || !std::isfinite(options.density))
    throw InputError("density must be a finite number > 0");
  const auto incidence = topology::edge_incidence(F, V.rows());
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    const int count = incidence.side_count(e);
    if (count > 2) {
      std::ostringstream message;  // only here: constructing one per edge cost 4 ms on 25k edges
      message << "edge (" << incidence.edges(e, 0) << ", " << incidence.edges(e, 1) << ") has " << count
              << " faces: hole filling needs an edge-manifold mesh (run repair.clean first)";
      throw InputError(message.str());
    }
    if (count == 2) {
      const int s = incidence.edge_sides[incidence.edge_offsets[e]];
      const int t = incidence.edge_sides[incidence.edge_offsets[e] + 1];
      if (F(s / 3, s % 3) == F(t / 3, t % 3)) {
        std::ostringstream message;
        message << "faces " << s / 3 << " and " << t / 3 << " traverse edge (" << incidence.edges(e, 0) << ", "
                << incidence.edges(e, 1) << ") in the same direction: hole filling needs a consistently"
                   " oriented mesh (run repair.clean or repair.orient_faces first)";
        throw InputError(message.str());
      }
    }
  }

  const CoordinateFrame frame = normalizing_frame(V);
  const VertexMatrix W = frame.normalize_vertices(V);
  auto point = [&](int v) { return Vec(W.row(v).transpose()); };

  FillHolesResult result;
  result.loops = topology::boundary_loops(F, incidence);
  const int loop_count = static_cast<int>(result.loops.size());

  // Boundary sides a → b with the third vertex of their face; σ, the mean edge length per vertex.
  std::unordered_map<std::int64_t, int> boundary_side;
  std::unordered_set<std::int64_t> edges;
  std::vector<double> length_sum(V.rows(), 0.0);
  std::vector<int> degree(V.rows(), 0);
  // The chord rule asks only about pairs of boundary vertices: only their edges are hashed.
  std::vector<char> on_boundary(V.rows(), 0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e)
    if (incidence.side_count(e) == 1) on_boundary[incidence.edges(e, 0)] = on_boundary[incidence.edges(e, 1)] = 1;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    const int a = incidence.edges(e, 0), b = incidence.edges(e, 1);
    if (on_boundary[a] && on_boundary[b]) edges.insert(edge_key(a, b));
    const double length = (point(a) - point(b)).norm();
    length_sum[a] += length;
    length_sum[b] += length;
    ++degree[a];
    ++degree[b];
    if (incidence.side_count(e) == 1) {
      const int s = incidence.edge_sides[incidence.edge_offsets[e]];
      boundary_side[side_key(F(s / 3, s % 3), F(s / 3, (s % 3 + 1) % 3))] = F(s / 3, (s % 3 + 2) % 3);
    }
  }
  auto sigma_of = [&](int v) { return degree[v] ? length_sum[v] / degree[v] : 0.0; };

  // Which loops to fill.
  std::vector<char> chosen(loop_count, options.holes.empty() ? 1 : 0);
  for (const int h : options.holes) {
    if (h < 0 || h >= loop_count) {
      std::ostringstream message;
      message << "holes: loop " << h << " is outside [0, " << loop_count << ") (the mesh has " << loop_count
              << " boundary loops)";
      throw InputError(message.str());
    }
    chosen[h] = 1;
  }
  std::vector<double> perimeter(loop_count, 0.0);
  for (int l = 0; l < loop_count; ++l) {
    const auto& loop = result.loops[l];
    for (std::size_t j = 0; j < loop.size(); ++j) perimeter[l] += (point(loop[j]) - point(loop[(j + 1) % loop.size()])).norm();
    if (options.max_hole_edges > 0 && static_cast<int>(loop.size()) > options.max_hole_edges) chosen[l] = 0;
    if (options.max_hole_diameter > 0.0 && chosen[l]) {
      const double limit = frame.to_normalized(options.max_hole_diameter, 1);
      Eigen::AlignedBox3d box;
      for (const int v : loop) box.extend(point(v));
      if (box.sizes().maxCoeff() > limit) {
        chosen[l] = 0;
      } else if (box.diagonal().norm() > limit) {
        for (std::size_t a = 0; a < loop.size() && chosen[l]; ++a)
          for (std::size_t b = a + 1; b < loop.size(); ++b)
            if ((point(loop[a]) - point(loop[b])).norm() > limit) { chosen[l] = 0; break; }
      }
    }
  }
  if (options.keep_border && loop_count) {
    const auto components = topology::connected_components(F, V.rows());
    std::vector<int> longest(components.count, -1);
    for (int l = 0; l < loop_count; ++l) {
      const int c = components.vertex_labels[result.loops[l][0]];
      if (longest[c] < 0 || perimeter[l] > perimeter[longest[c]]) longest[c] = l;
    }
    for (int c = 0; c < components.count; ++c) {
      const int border = longest[c];
      if (border < 0) continue;
      bool dominant = true;
      for (int l = 0; l < loop_count; ++l)
        if (l != border && components.vertex_labels[result.loops[l][0]] == c &&
            perimeter[border] < kBorderRatio * perimeter[l]) dominant = false;
      if (dominant) {
        result.kept_borders.push_back(border);
        chosen[border] = 0;
      }
    }
    std::sort(result.kept_borders.begin(), result.kept_borders.end());
  }

  // Islands: each loop inside a chosen loop of another component (FillHolesOptions::islands' test)
  // joins the smallest such loop; it is then not filled on its own, nor kept as a border.
  std::vector<std::vector<int>> islands_of(loop_count);
  if (options.islands && loop_count > 1) {
    const auto components = topology::connected_components(F, V.rows());
    std::vector<Vec> newell(loop_count, Vec::Zero()), centre(loop_count, Vec::Zero());
    for (int l = 0; l < loop_count; ++l) {
      const auto& loop = result.loops[l];
      for (const int v : loop) centre[l] += point(v);
      centre[l] /= static_cast<double>(loop.size());
      for (std::size_t j = 0; j < loop.size(); ++j)
        newell[l] += (point(loop[j]) - centre[l]).cross(point(loop[(j + 1) % loop.size()]) - centre[l]);
    }
    // A component's extent (its bounding box's diagonal): an island's loop must span its
    // component (a patch bounded by it), not be a small hole in a larger or closed surface.
    std::vector<Eigen::AlignedBox3d> extent(components.count);
    for (Eigen::Index v = 0; v < V.rows(); ++v)
      if (components.vertex_labels[v] >= 0) extent[components.vertex_labels[v]].extend(point(static_cast<int>(v)));
    std::vector<int> host(loop_count, -1);
    for (int i = 0; i < loop_count; ++i) {
      Eigen::AlignedBox3d span;
      for (const int v : result.loops[i]) span.extend(point(v));
      if (extent[components.vertex_labels[result.loops[i][0]]].diagonal().norm() > 1.5 * span.diagonal().norm())
        continue;
      for (int l = 0; l < loop_count; ++l) {
        if (l == i || !chosen[l] || perimeter[i] >= perimeter[l]) continue;
        if (components.vertex_labels[result.loops[i][0]] == components.vertex_labels[result.loops[l][0]]) continue;
        const double area = 0.5 * newell[l].norm();
        if (!(area > 0.0) || newell[l].dot(newell[i]) >= 0.0) continue;
        const Vec normal = newell[l].normalized();
        const Vec u = normal.unitOrthogonal(), w = normal.cross(u);
        auto plane = [&](int v) {
          const Vec d = point(v) - centre[l];
          return std::array<double, 3>{d.dot(u), d.dot(w), d.dot(normal)};
        };
        const auto& outer = result.loops[l];
        std::vector<std::array<double, 3>> ring;
        for (const int v : outer) ring.push_back(plane(v));
        bool inside = true;
        for (const int v : result.loops[i]) {
          const auto q = plane(v);
          if (std::abs(q[2]) > 0.5 * std::sqrt(area)) { inside = false; break; }
          bool odd = false;        // crossing number in the plane
          for (std::size_t j = 0, k = ring.size() - 1; j < ring.size(); k = j++)
            if ((ring[j][1] > q[1]) != (ring[k][1] > q[1]) &&
                q[0] < ring[k][0] + (ring[j][0] - ring[k][0]) * (q[1] - ring[k][1]) / (ring[j][1] - ring[k][1]))
              odd = !odd;
          if (!odd) { inside = false; break; }
        }
        if (inside && (host[i] < 0 || perimeter[l] < perimeter[host[i]])) host[i] = l;
      }
    }
    for (int i = 0; i < loop_count; ++i)
      if (host[i] >= 0 && host[host[i]] < 0) {   // an island's own islands stay separate
        islands_of[host[i]].push_back(i);
        chosen[i] = 0;
        // keep_border keeps an island's only loop as its border: joined to the hole, it is none.
        result.kept_borders.erase(std::remove(result.kept_borders.begin(), result.kept_borders.end(), i),
                                  result.kept_borders.end());
      }
  }

  // Fill.
  std::vector<int> face_offsets, vertex_faces;   // built by the first patch that is faired
  std::vector<Vec> new_points;
  std::vector<std::array<int, 3>> new_faces;
  std::vector<std::vector<int>> patch_loops;     // each patch's loop, its islands spliced in
  const int n_input = static_cast<int>(V.rows());
  int filled_count = 0, to_fill = 0;
  for (int l = 0; l < loop_count; ++l) to_fill += chosen[l];
  for (int l = 0; l < loop_count; ++l) {
    if (!chosen[l]) continue;
    const Progress step = progress.subrange(static_cast<double>(filled_count) / to_fill,
                                            static_cast<double>(filled_count + 1) / to_fill);
    ++filled_count;
    step.report(0.0, "filling holes");
    // The loop, with each island spliced in at the shortest bridge from what is joined so far:
    // ..., a, island from b round to b, a, ... (the bridge a–b is then an inner edge of the patch).
    std::vector<int> loop = result.loops[l];
    std::unordered_set<std::int64_t> bridges;
    for (const int i : islands_of[l]) {
      const auto& island = result.loops[i];
      double shortest = std::numeric_limits<double>::infinity();
      std::size_t at = 0, from = 0;
      for (std::size_t j = 0; j < loop.size(); ++j)
        for (std::size_t k = 0; k < island.size(); ++k) {
          const double d = (point(loop[j]) - point(island[k])).squaredNorm();
          if (d < shortest && !edges.count(edge_key(loop[j], island[k]))) { shortest = d; at = j; from = k; }
        }
      std::vector<int> joined(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(at) + 1);
      for (std::size_t k = 0; k <= island.size(); ++k) joined.push_back(island[(from + k) % island.size()]);
      joined.insert(joined.end(), loop.begin() + static_cast<std::ptrdiff_t>(at), loop.end());
      bridges.insert(edge_key(loop[at], island[from]));
      edges.insert(edge_key(loop[at], island[from]));   // no chord may take the bridge again
      loop = std::move(joined);
    }
    const Vec plane_normal = newell_normal(loop, point);
    const int n = static_cast<int>(loop.size());
    Polygon polygon;
    bool closed = n >= 3;
    for (int j = 0; j < n && closed; ++j) {
      const int a = loop[j], b = loop[(j + 1) % n];
      polygon.p.push_back(point(a));
      polygon.vertex.push_back(a);
      if (bridges.count(edge_key(a, b))) {   // no face on a bridge: the joined polygon's plane
        polygon.outer_normal.push_back(plane_normal);
        continue;
      }
      const auto side = boundary_side.find(side_key(a, b));
      if (side == boundary_side.end()) { closed = false; break; }
      // The mesh face on a → b, reversed, is oriented like the patch's triangles (i, m, k).
      polygon.outer_normal.push_back(unit_normal(point(b), point(a), point(side->second)));
    }
    if (!closed) {
      result.unfilled.push_back({l, n < 3 ? "fewer than three edges"
                                          : "not a closed chain of boundary edges in one direction"});
      continue;
    }
    const ChordRule rule{polygon, edges};
    std::vector<std::array<int, 3>> triangles;
    bool delaunay = false;
    if (options.search == HoleSearch::delaunay) {
      triangles = triangulate_delaunay(polygon, rule);
      delaunay = !triangles.empty();
    }
    if (triangles.empty()) {
      if (n > kMaxExactHoleEdges) {
        std::ostringstream reason;
        reason << "the Delaunay search space holds no valid triangulation and the loop has more than "
               << kMaxExactHoleEdges << " edges for the exact search";
        result.unfilled.push_back({l, reason.str()});
        continue;
      }
      triangles = triangulate_exact(polygon, rule, step.subrange(0.0, 0.8));
    }
    if (!islands_of[l].empty() && (triangles.empty() || repeats_a_side(triangles, polygon))) {
      // The joined polygon's triangulation used an edge twice (through the two copies of a
      // bridge's end): fill the loop and its islands each on its own instead.
      for (const int i : islands_of[l]) chosen[i] = 1;
      to_fill += static_cast<int>(islands_of[l].size());
      islands_of[l].clear();
      for (const auto key : bridges) edges.erase(key);
      --filled_count;
      --l;
      continue;
    }
    if (triangles.empty()) {
      result.unfilled.push_back({l, "every triangulation of the loop repeats a vertex in a face or adds an edge"
                                    " the mesh already has"});
      continue;
    }

    // The patch as its own mesh: vertex j is loop position j, faces reversed to match the mesh.
    TriMesh patch;
    for (const Vec& p : polygon.p) patch.add_vertex(TriMesh::Point(p.x(), p.y(), p.z()));
    for (const auto& [i, m, k] : triangles) {
      const auto face = patch.add_face(TriMesh::VertexHandle(k), TriMesh::VertexHandle(m), TriMesh::VertexHandle(i));
      if (!face.is_valid()) throw SolverError("fill_holes: a hole's triangulation is not a disk (internal error)");
    }
    if (options.refine) {
      std::vector<double> sigma(n);
      for (int j = 0; j < n; ++j) sigma[j] = sigma_of(loop[j]);
      refine_patch(patch, n, sigma, options.density);
    }
    HolePatch record;
    record.loop = l;
    record.loop_edges = n;
    record.delaunay = delaunay;
    record.face_begin = static_cast<int>(F.rows() + new_faces.size());
    record.vertex_begin = static_cast<int>(n_input + new_points.size());
    const int new_base = record.vertex_begin - n;
    auto global = [&](int j) { return j < n ? loop[j] : new_base + j; };
    for (auto v : patch.vertices())
      if (v.idx() >= n) new_points.push_back(Eigen::Map<const Vec>(patch.point(v).data()));
    for (auto f : patch.faces()) {
      std::array<int, 3> face{};
      int c = 0;
      for (auto v : patch.fv_range(f)) face[c++] = global(v.idx());
      new_faces.push_back(face);
      for (int s = 0; s < 3; ++s) edges.insert(edge_key(face[s], face[(s + 1) % 3]));
    }
    record.faces = static_cast<int>(patch.n_faces());
    record.vertices = static_cast<int>(patch.n_vertices()) - n;
    if (options.fair && record.vertices > 0) {
      if (face_offsets.empty()) {
        // Mesh faces by vertex, once: the one-rings the fairing system takes in.
        face_offsets.assign(V.rows() + 1, 0);
        for (Eigen::Index f = 0; f < F.rows(); ++f)
          for (int c = 0; c < 3; ++c) ++face_offsets[F(f, c) + 1];
        for (Eigen::Index v = 0; v < V.rows(); ++v) face_offsets[v + 1] += face_offsets[v];
        vertex_faces.resize(3 * static_cast<std::size_t>(F.rows()));
        std::vector<int> fill(face_offsets.begin(), face_offsets.end() - 1);
        for (Eigen::Index f = 0; f < F.rows(); ++f)
          for (int c = 0; c < 3; ++c) vertex_faces[fill[F(f, c)]++] = static_cast<int>(f);
      }
      const std::vector<std::array<int, 3>> patch_faces(new_faces.end() - record.faces, new_faces.end());
      fair_patch(W, new_points, record.vertex_begin, record.vertices, patch_faces, loop, F, face_offsets, vertex_faces);
    }
    record.islands = islands_of[l];
    result.patches.push_back(record);
    patch_loops.push_back(std::move(loop));
    step.report(1.0, "filling holes");
  }

  for (std::size_t u = 0, count = result.unfilled.size(); u < count; ++u)
    for (const int i : islands_of[result.unfilled[u].loop])
      result.unfilled.push_back({i, "an island of loop " + std::to_string(result.unfilled[u].loop) + ", which was left open"});
  std::sort(result.unfilled.begin(), result.unfilled.end(), [](const auto& a, const auto& b) { return a.loop < b.loop; });

  VertexMatrix added(static_cast<Eigen::Index>(new_points.size()), 3);
  for (std::size_t j = 0; j < new_points.size(); ++j) added.row(static_cast<Eigen::Index>(j)) = new_points[j].transpose();

  if (!result.patches.empty()) {
    // Mesh edges by vertex, for the surrounding rings.
    std::vector<int> offsets(V.rows() + 1, 0), vertex_edges(2 * static_cast<std::size_t>(incidence.n_edges()));
    for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
      ++offsets[incidence.edges(e, 0) + 1];
      ++offsets[incidence.edges(e, 1) + 1];
    }
    for (Eigen::Index v = 0; v < V.rows(); ++v) offsets[v + 1] += offsets[v];
    std::vector<int> fill(offsets.begin(), offsets.end() - 1);
    for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
      vertex_edges[fill[incidence.edges(e, 0)]++] = static_cast<int>(e);
      vertex_edges[fill[incidence.edges(e, 1)]++] = static_cast<int>(e);
    }
    VertexMatrix X(V.rows() + added.rows(), 3);
    X.topRows(V.rows()) = W;
    if (added.rows()) X.bottomRows(added.rows()) = added;
    for (std::size_t p = 0; p < result.patches.size(); ++p)
      measure_patch(result.patches[p], patch_loops[p], X, F, new_faces, boundary_side, incidence, offsets, vertex_edges);
  }
  result.V.resize(V.rows() + added.rows(), 3);
  result.V.topRows(V.rows()) = V;
  if (added.rows()) result.V.bottomRows(added.rows()) = frame.vertices_to_input(added, "a hole-filling vertex");
  result.F.resize(F.rows() + static_cast<Eigen::Index>(new_faces.size()), 3);
  result.F.topRows(F.rows()) = F;
  for (std::size_t j = 0; j < new_faces.size(); ++j)
    result.F.row(F.rows() + static_cast<Eigen::Index>(j)) << new_faces[j][0], new_faces[j][1], new_faces[j][2];
  progress.report(1.0, "filling holes");
  return result;
}

}  // namespace meshsmith::repair
