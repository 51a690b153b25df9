// Intrinsic Delaunay cotangent Laplacian (laplacian.h): edge flips on edge lengths only.
//
// How it works. The triangulation is held as a Δ-complex, not as a halfedge mesh of the project
// (core/mesh.h): after intrinsic flips two edges may join the same pair of vertices, and OpenMesh
// refuses such flips. Each face stores its three vertices and the three edges opposite its
// corners; each edge stores its length and the (face, corner) of its one or two sides. A flip of
// edge ab, shared by faces (c, a, b) and (d, b, a), lays the two triangles out in the plane from
// their five lengths, measures the new diagonal cd, and rewrites the two faces as (c, a, d) and
// (d, b, c); no vertex moves, so the surface's metric is unchanged (Bobenko & Springborn 2007;
// Fisher, Springborn, Bobenko & Schröder 2007). Edges are checked from a stack (initially every
// interior edge); a flip pushes the four edges around the quad. Every flip of a non-Delaunay
// edge lowers the Dirichlet energy of every piecewise-linear function, so the loop ends; a cap of
// 100·#E + 10⁶ flips turns a floating-point cycle (never seen) into a SolverError.
//
// Boundary. A boundary edge has one cotangent, negative when its opposite angle is obtuse, and
// no flip reaches it. Such an edge ab of triangle (c, a, b) is split intrinsically at the foot h
// of the altitude from c (strictly inside ab, as the angles at a and b are acute): the halves
// (c, a, h) and (c, h, b) are right-angled at h, so ah and hb get the positive cotangents of
// the angles at c, and the new edge ch those of the acute angles at a and b; flips then restore
// the Delaunay property (a refinement in the manner of Sharp & Crane 2020, whose insertions are
// circumcentres and segment midpoints; the altitude foot needs one split per edge and no
// cascade at sharp boundary corners). The Laplacian of the refined triangulation, on the
// original and the inserted vertices, has only non-negative weights. Each inserted vertex h (on
// edge ab at (1 − t) a + t b) is then lumped onto a and b: its value is taken as the linear
// interpolant (1 − t) f_a + t f_b, and every weight w of an edge hj goes to ja and jb in the
// proportions 1 − t and t (to ab as t² w and (1 − t)² w for j = a, b) — the exact restriction of
// the energy minus the terms w t(1 − t)(f_a − f_b)², which are what make the plain weight of ab
// negative. The result is #V×#V with non-negative weights, symmetric, rows summing to zero,
// negative semi-definite; every interior vertex keeps linear precision (its row gets
// w (x_h − x_j) = w [(1 − t)(x_a − x_j) + t (x_b − x_j)] exactly), and the energy bounds that
// of the interpolated function on the refined triangulation from above. Where no boundary edge
// is split it equals the unrefined intrinsic Delaunay Laplacian (and libigl's) exactly.
//
// Numbers. Lengths are measured on the normalized coordinates (core/normalization.h) by a
// stable norm, and every triangle's quantities are computed on its lengths divided by its
// longest one, so slivers and meshes of size 1e±300 give finite cotangents. Areas use Kahan's
// form of Heron's formula. Only the cotangents leave this file; they are scale-invariant, so no
// mapping back is needed.
#include <meshsmith/geometry/laplacian.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/topology/edge_incidence.h>

#include "triangle_corners.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include <Eigen/SparseCore>

namespace meshsmith::geometry {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();
/// A weight counts as negative below −kFlipTolerance·(1 + |cot α| + |cot β|): co-circular quads
/// (a regular grid's diagonals) have weights of ±1e-16 that flipping would only shuffle.
constexpr double kFlipTolerance = 1e-12;
/// Rounds of boundary refinement (refine_boundary); one suffices on every shared mesh.
constexpr int kRefinementRounds = 8;

/// |p − q| without overflow or underflow of the squares.
double distance(const double* p, const double* q) {
  const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
  const double scale = std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
  if (scale == 0.0) return 0.0;
  const double x = d[0] / scale, y = d[1] / scale, z = d[2] / scale;
  return scale * std::sqrt(x * x + y * y + z * z);
}

/// The cotangents of a triangle with edge lengths a, b, c (a opposite corner 0, ...), computed
/// on the lengths divided by the longest. `degenerate`: twice its area ≤ 8ε·(longest edge)², the
/// rule of cotan_laplacian (triangle_corners.h); then the cotangents are what the formula gives
/// with the area clamped to that bound (large, of the right sign: good enough to decide a flip).
struct TriangleCotangents {
  double cot[3];
  bool degenerate;
};

TriangleCotangents cotangents(double a, double b, double c) {
  TriangleCotangents result{};
  const double longest = std::max({a, b, c});
  if (!(longest > 0.0)) {
    result.degenerate = true;
    return result;
  }
  const double l[3] = {a / longest, b / longest, c / longest};
  double s[3] = {l[0], l[1], l[2]};
  std::sort(s, s + 3, [](double x, double y) { return x > y; });
  // Kahan: 16 A² = (a + (b + c))(c − (a − b))(c + (a − b))(a + (b − c)), a ≥ b ≥ c.
  const double product = (s[0] + (s[1] + s[2])) * (s[2] - (s[0] - s[1])) * (s[2] + (s[0] - s[1])) *
                         (s[0] + (s[1] - s[2]));
  const double area = 0.25 * std::sqrt(std::max(product, 0.0));
  const double floor = 4.0 * kEpsilon;  // 2·area ≤ 8ε·1²
  result.degenerate = !(area > floor);
  const double used = std::max(area, floor);
  for (int k = 0; k < 3; ++k) {
    const double opposite = l[k], u = l[(k + 1) % 3], v = l[(k + 2) % 3];
    result.cot[k] = (u * u + v * v - opposite * opposite) / (4.0 * used);
  }
  return result;
}

/// Where a boundary vertex was inserted: on edge ab, at (1 − t) a + t b along it.
struct Split {
  int a, b;
  double t;
};

class IntrinsicTriangulation {
 public:
  IntrinsicTriangulation(const VertexMatrix& V, const FaceMatrix& F)
      : faces_(F), face_edges_(F.rows(), 3), vertices_(static_cast<int>(V.rows())) {
    const topology::EdgeIncidence incidence = topology::edge_incidence(F, V.rows());
    const Eigen::Index n_edges = incidence.n_edges();
    length_.resize(n_edges);
    sides_.assign(n_edges, {-1, -1});
    for (Eigen::Index e = 0; e < n_edges; ++e) {
      const int count = incidence.side_count(e);
      const int i = incidence.edges(e, 0), j = incidence.edges(e, 1);
      if (count > 2) {
        throw InputError("intrinsic Delaunay: edge (" + std::to_string(i) + ", " + std::to_string(j) + ") has " +
                         std::to_string(count) + " faces: the mesh must be edge-manifold (split non-manifold "
                         "vertices first)");
      }
      length_[e] = distance(V.row(i).data(), V.row(j).data());
      for (int k = 0; k < count; ++k) {
        const int side = incidence.edge_sides[incidence.edge_offsets[e] + k];
        const int f = side / 3, corner = (side % 3 + 2) % 3;  // side k of f is opposite corner k+2
        sides_[e][k] = 3 * f + corner;
        face_edges_(f, corner) = static_cast<int>(e);
      }
      if (count == 2) {
        const int s0 = incidence.edge_sides[incidence.edge_offsets[e]];
        const int s1 = incidence.edge_sides[incidence.edge_offsets[e] + 1];
        if (F(s0 / 3, s0 % 3) == F(s1 / 3, s1 % 3)) {
          throw InputError("intrinsic Delaunay: faces " + std::to_string(s0 / 3) + " and " + std::to_string(s1 / 3) +
                           " traverse edge (" + std::to_string(i) + ", " + std::to_string(j) +
                           ") in the same direction: orient the mesh consistently first");
        }
      }
    }
  }

  /// Flips every interior edge with a negative cot weight until none is left.
  void make_delaunay() {
    std::vector<int> edges;
    for (Eigen::Index e = static_cast<Eigen::Index>(length_.size()) - 1; e >= 0; --e) edges.push_back(static_cast<int>(e));
    flip_from(edges);
  }

  /// Splits every boundary edge whose opposite angle is obtuse (its one cot weight negative) at
  /// the foot of the altitude from the opposite corner, then restores the Delaunay property by
  /// flips; repeated (at most `rounds` times) while such edges are left. The two halves of the
  /// triangle are right-angled at the foot, so the split edge's halves get the positive
  /// cotangents of the acute angles at the opposite corner. Returns the number of vertices
  /// inserted (numbered from the original vertex count on).
  int refine_boundary(int rounds) {
    int inserted = 0;
    for (int round = 0; round < rounds; ++round) {
      std::vector<int> obtuse;
      for (std::size_t e = 0; e < length_.size(); ++e) {
        if (sides_[e][1] < 0 && sides_[e][0] >= 0 && splittable(static_cast<int>(e))) obtuse.push_back(static_cast<int>(e));
      }
      if (obtuse.empty()) break;
      const Eigen::Index faces = faces_.rows();
      faces_.conservativeResize(faces + static_cast<Eigen::Index>(obtuse.size()), 3);
      face_edges_.conservativeResize(faces_.rows(), 3);
      std::vector<int> touched;
      for (std::size_t k = 0; k < obtuse.size(); ++k) {
        split(obtuse[k], static_cast<int>(faces + static_cast<Eigen::Index>(k)), &touched);
        ++inserted;
      }
      flip_from(touched);
    }
    return inserted;
  }

  /// ½ cot of each corner's angle (#F×3), 0 for degenerate triangles, as cotan_laplacian's.
  detail::CornerMatrix half_cotangents() const {
    detail::CornerMatrix result(faces_.rows(), 3);
    for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
      const TriangleCotangents t = face_cotangents(static_cast<int>(f));
      for (int c = 0; c < 3; ++c) result(f, c) = t.degenerate ? 0.0 : 0.5 * t.cot[c];
    }
    return result;
  }

  const FaceMatrix& faces() const { return faces_; }
  /// The inserted vertices (numbered from the original vertex count on, in this order).
  const std::vector<Split>& splits() const { return splits_; }

  /// The per-face weights, with each edge's round-off negatives (|w| under the flip tolerance)
  /// moved to zero: both halves of such an edge are shifted by the same amount.
  void clamp_round_off(detail::CornerMatrix& half) const {
    for (std::size_t e = 0; e < length_.size(); ++e) {
      double weight = 0.0, magnitude = 0.0;
      for (int k = 0; k < 2; ++k) {
        if (sides_[e][k] < 0) continue;
        const double w = half(sides_[e][k] / 3, sides_[e][k] % 3);
        weight += w;
        magnitude += std::abs(2.0 * w);
      }
      if (weight < 0.0 && weight >= -kFlipTolerance * (1.0 + magnitude)) {
        const int count = sides_[e][1] >= 0 ? 2 : 1;
        for (int k = 0; k < count; ++k) half(sides_[e][k] / 3, sides_[e][k] % 3) -= weight / count;
      }
    }
  }

 private:
  /// The flip loop of make_delaunay from the given edges (boundary edges are skipped).
  void flip_from(const std::vector<int>& edges) {
    const Eigen::Index n_edges = static_cast<Eigen::Index>(length_.size());
    std::vector<int> stack;
    std::vector<char> queued(n_edges, 0);
    for (int e : edges) {  // the last one is checked first
      if (sides_[e][1] >= 0 && !queued[e]) {
        stack.push_back(e);
        queued[e] = 1;
      }
    }
    const double cap = 100.0 * static_cast<double>(n_edges) + 1e6;
    double flips = 0.0;
    while (!stack.empty()) {
      const int e = stack.back();
      stack.pop_back();
      queued[e] = 0;
      if (!needs_flip(e) || !flip(e)) continue;
      if (++flips > cap) {
        throw SolverError("intrinsic Delaunay: more than " + number_text(cap) +
                          " edge flips without reaching a Delaunay triangulation (a floating-point cycle)");
      }
      for (int k = 0; k < 2; ++k) {
        const int f = sides_[e][k] / 3;
        for (int c = 0; c < 3; ++c) {
          const int other = face_edges_(f, c);
          if (other != e && sides_[other][1] >= 0 && !queued[other]) {
            stack.push_back(other);
            queued[other] = 1;
          }
        }
      }
    }
  }

  /// Whether boundary edge e has a negative cot weight (beyond round-off) in a proper triangle,
  /// so that the altitude's foot lies strictly inside it.
  bool splittable(int e) const {
    const int f = sides_[e][0] / 3, corner = sides_[e][0] % 3;
    if (faces_(f, 0) == faces_(f, 1) || faces_(f, 1) == faces_(f, 2) || faces_(f, 2) == faces_(f, 0)) return false;
    const TriangleCotangents t = face_cotangents(f);
    if (t.degenerate) return false;
    const double alpha = t.cot[corner];
    return alpha < -kFlipTolerance * (1.0 + std::abs(alpha)) && t.cot[(corner + 1) % 3] > 0.0 &&
           t.cot[(corner + 2) % 3] > 0.0;
  }

  /// Splits boundary edge e = ab of face f = (c, a, b) at the foot h of the altitude from c:
  /// f ← (c, a, h), new face g ← (c, h, b); e becomes ah, new edges hb (boundary) and ch. The
  /// edges that may now need a flip are appended to `touched`.
  void split(int e, int g, std::vector<int>* touched) {
    const int f = sides_[e][0] / 3, i = sides_[e][0] % 3;
    const int c = faces_(f, i), a = faces_(f, (i + 1) % 3), b = faces_(f, (i + 2) % 3);
    const int e_bc = face_edges_(f, (i + 1) % 3), e_ca = face_edges_(f, (i + 2) % 3);
    const double ab = length_[e], ca = length_[e_ca], bc = length_[e_bc];
    // |ah| = (ab² + ca² − bc²) / (2 ab), on lengths divided by ab.
    const double x = ca / ab, y = bc / ab;
    const double t = std::clamp(0.5 * (1.0 + (x - y) * (x + y)), 0.0, 1.0);
    const double height = std::sqrt(std::max((x - t) * (x + t), 0.0));
    const int h = vertices_++;
    splits_.push_back({a, b, t});
    const int e_hb = static_cast<int>(length_.size()), e_ch = e_hb + 1;
    length_.push_back(ab * (1.0 - t));
    length_.push_back(ab * height);
    sides_.push_back({3 * g + 0, -1});
    sides_.push_back({3 * f + 1, 3 * g + 2});
    length_[e] = ab * t;
    // f ← (c, a, h): corner 0 faces ah (e), corner 1 faces hc, corner 2 faces ca.
    // g ← (c, h, b): corner 0 faces hb, corner 1 faces bc, corner 2 faces ch.
    faces_.row(f) << c, a, h;
    faces_.row(g) << c, h, b;
    face_edges_.row(f) << e, e_ch, e_ca;
    face_edges_.row(g) << e_hb, e_bc, e_ch;
    sides_[e] = {3 * f + 0, -1};
    move_side(e_ca, 3 * f + (i + 2) % 3, 3 * f + 2);
    move_side(e_bc, 3 * f + (i + 1) % 3, 3 * g + 1);
    touched->insert(touched->end(), {e_ca, e_bc, e_ch});
  }

  TriangleCotangents face_cotangents(int f) const {
    return cotangents(length_[face_edges_(f, 0)], length_[face_edges_(f, 1)], length_[face_edges_(f, 2)]);
  }

  bool needs_flip(int e) const {
    if (sides_[e][1] < 0) return false;
    const int s0 = sides_[e][0], s1 = sides_[e][1];
    if (s0 / 3 == s1 / 3) return false;  // a face glued to itself: nothing to flip into
    const double alpha = face_cotangents(s0 / 3).cot[s0 % 3];
    const double beta = face_cotangents(s1 / 3).cot[s1 % 3];
    return alpha + beta < -kFlipTolerance * (1.0 + std::abs(alpha) + std::abs(beta));
  }

  /// Flips edge e if its quad lays out strictly convex; returns whether it did.
  bool flip(int e) {
    const int f = sides_[e][0] / 3, i = sides_[e][0] % 3;
    const int g = sides_[e][1] / 3, j = sides_[e][1] % 3;
    // f = (c, a, b) from corner i, g = (d, b, a) from corner j.
    const int c = faces_(f, i), a = faces_(f, (i + 1) % 3), b = faces_(f, (i + 2) % 3);
    const int d = faces_(g, j);
    const int e_bc = face_edges_(f, (i + 1) % 3), e_ca = face_edges_(f, (i + 2) % 3);
    const int e_ad = face_edges_(g, (j + 1) % 3), e_db = face_edges_(g, (j + 2) % 3);
    const double ab = length_[e];
    if (!(ab > 0.0)) return false;
    // Layout on lengths divided by |ab|: a = (0, 0), b = (1, 0), c above, d below.
    const double ca = length_[e_ca] / ab, bc = length_[e_bc] / ab;
    const double ad = length_[e_ad] / ab, db = length_[e_db] / ab;
    const double cx = 0.5 * (1.0 + ca * ca - bc * bc), dx = 0.5 * (1.0 + ad * ad - db * db);
    const double cy = std::sqrt(std::max(ca * ca - cx * cx, 0.0));
    const double dy = -std::sqrt(std::max(ad * ad - dx * dx, 0.0));
    if (!(cy - dy > 0.0)) return false;
    const double crossing = cx + (dx - cx) * cy / (cy - dy);  // where cd meets the line ab
    if (!(crossing > 0.0 && crossing < 1.0)) return false;     // not strictly convex
    const double cd = ab * std::hypot(cx - dx, cy - dy);
    if (!(cd > 0.0) || !std::isfinite(cd)) return false;
    // f ← (c, a, d): corner 0 faces ad, corner 1 faces dc (e), corner 2 faces ca.
    // g ← (d, b, c): corner 0 faces bc, corner 1 faces cd (e), corner 2 faces db.
    faces_.row(f) << c, a, d;
    faces_.row(g) << d, b, c;
    face_edges_.row(f) << e_ad, e, e_ca;
    face_edges_.row(g) << e_bc, e, e_db;
    length_[e] = cd;
    sides_[e] = {3 * f + 1, 3 * g + 1};
    move_side(e_ad, 3 * g + (j + 1) % 3, 3 * f + 0);
    move_side(e_ca, 3 * f + (i + 2) % 3, 3 * f + 2);
    move_side(e_bc, 3 * f + (i + 1) % 3, 3 * g + 0);
    move_side(e_db, 3 * g + (j + 2) % 3, 3 * g + 2);
    return true;
  }

  void move_side(int edge, int from, int to) {
    for (int k = 0; k < 2; ++k) {
      if (sides_[edge][k] == from) {
        sides_[edge][k] = to;
        return;
      }
    }
  }

  FaceMatrix faces_;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> face_edges_;  // edge opposite each corner
  std::vector<double> length_;
  std::vector<std::array<int, 2>> sides_;  // 3·face + corner opposite the edge; −1: boundary
  int vertices_ = 0;                       // original ones, then those inserted on the boundary
  std::vector<Split> splits_;              // per inserted vertex, in the order of insertion
};

}  // namespace

Eigen::SparseMatrix<double> intrinsic_delaunay_cotan_laplacian(const VertexRef& input_V, const FaceRef& F) {
  detail::validate_surface(input_V, F);
  const VertexMatrix V = normalizing_frame(input_V).normalize_vertices(input_V);
  // Faces with a repeated index have no area and no edge of their own: left out (they add
  // nothing to cotan_laplacian either).
  FaceMatrix proper(F.rows(), 3);
  Eigen::Index count = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (F(f, 0) != F(f, 1) && F(f, 1) != F(f, 2) && F(f, 2) != F(f, 0)) proper.row(count++) = F.row(f);
  }
  proper.conservativeResize(count, 3);
  if (count == 0) return cotan_laplacian(input_V, F);  // every face degenerate: the zero Laplacian
  IntrinsicTriangulation triangulation(V, proper);
  triangulation.make_delaunay();
  triangulation.refine_boundary(kRefinementRounds);
  detail::CornerMatrix half = triangulation.half_cotangents();
  triangulation.clamp_round_off(half);
  // Assembled edge by edge (not by assemble_laplacian): after flips a face may repeat a vertex
  // (an edge from a vertex to itself, whose term w·(x_i − x_i)² is zero and adds nothing).
  // Edges at an inserted vertex are kept in its star until it is lumped onto its edge's ends.
  const FaceMatrix& faces = triangulation.faces();
  const std::vector<Split>& splits = triangulation.splits();
  const int n = static_cast<int>(V.rows());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(n + 12 * faces.rows()));
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, 0.0);
  std::vector<std::map<int, double>> star(splits.size());
  const auto add_edge = [&](int u, int v, double w) {
    if (u == v || w == 0.0) return;
    if (u >= n || v >= n) {
      if (u >= n) star[u - n][v] += w;
      if (v >= n) star[v - n][u] += w;
      return;
    }
    entries.emplace_back(u, v, w);
    entries.emplace_back(v, u, w);
    entries.emplace_back(u, u, -w);
    entries.emplace_back(v, v, -w);
  };
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      add_edge(faces(f, (corner + 1) % 3), faces(f, (corner + 2) % 3), half(f, corner));
    }
  }
  // Lumping, the last inserted vertex first (its edge's ends a, b are original or inserted
  // before it): with f_h = (1 − t) f_a + t f_b, a term w (f_j − f_h)² is
  // w [(1 − t)(f_j − f_a)² + t (f_j − f_b)² − t(1 − t)(f_a − f_b)²]; the first two go to the
  // edges ja and jb, the last (the one that makes the plain weight of ab negative) is dropped;
  // w (f_a − f_h)² = w t² (f_a − f_b)² and w (f_b − f_h)² = w (1 − t)² (f_a − f_b)² go to ab.
  for (int k = static_cast<int>(splits.size()) - 1; k >= 0; --k) {
    const Split& split = splits[k];
    const int h = n + k;
    for (const auto& [j, w] : star[k]) {
      if (j >= n) star[j - n].erase(h);
      if (j == split.a) {
        add_edge(split.a, split.b, split.t * split.t * w);
      } else if (j == split.b) {
        add_edge(split.a, split.b, (1.0 - split.t) * (1.0 - split.t) * w);
      } else {
        add_edge(split.a, j, (1.0 - split.t) * w);
        add_edge(split.b, j, split.t * w);
      }
    }
    star[k].clear();
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(entries.begin(), entries.end());
  L.makeCompressed();
  return L;
}

}  // namespace meshsmith::geometry
