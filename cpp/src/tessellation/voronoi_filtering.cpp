// Voronoi filtering (§2.1.3): the 2D crust, the approximate medial axis and LFS (§2.1.2), and
// the 3D Cocone reconstruction with its manifold extraction.
#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/points/kd_tree.h>
#include <meshsmith/tessellation/voronoi_filtering.h>

#include "contouring_triangulations.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace meshsmith::tessellation {

namespace {

void check_samples(const Eigen::Ref<const Eigen::MatrixXd>& P, Eigen::Index columns,
                   Eigen::Index minimum, const char* function) {
  if (P.cols() != columns)
    throw InputError(std::string(function) + ": samples must have " + std::to_string(columns) +
                     " columns, got " + std::to_string(P.cols()));
  if (P.rows() < minimum)
    throw InputError(std::string(function) + ": needs at least " + std::to_string(minimum) +
                     " samples, got " + std::to_string(P.rows()));
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (!P.row(i).allFinite())
      throw InputError(std::string(function) + ": sample " + std::to_string(i) + " is not finite");
}

// Delaunay triangulation of full dimension with every point a vertex, or InputError.
detail::Triangulation full_delaunay(const Eigen::Ref<const Eigen::MatrixXd>& P, const char* function,
                                   const Progress& progress = {}) {
  detail::Triangulation t = detail::delaunay_triangulation(P, progress);
  for (std::size_t i = 0; i < t.is_vertex.size(); ++i)
    if (!t.is_vertex[i])
      throw InputError(std::string(function) + ": sample " + std::to_string(i) +
                       " coincides with another sample");
  if (t.dimension < P.cols())
    throw InputError(std::string(function) + (P.cols() == 2 ? ": the samples are collinear"
                                                            : ": the samples are coplanar"));
  return t;
}

Eigen::Vector2d circumcentre(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2) {
  const Eigen::Vector2d a = p1 - p0, b = p2 - p0;
  const double d = 2.0 * (a.x() * b.y() - a.y() * b.x());
  const Eigen::Vector2d offset((b.y() * a.squaredNorm() - a.y() * b.squaredNorm()) / d,
                               (a.x() * b.squaredNorm() - b.x() * a.squaredNorm()) / d);
  return std::isfinite(offset.x()) && std::isfinite(offset.y()) ? Eigen::Vector2d(p0 + offset)
                                                                : Eigen::Vector2d((p0 + p1 + p2) / 3.0);
}

Eigen::Vector3d circumcentre(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                             const Eigen::Vector3d& p2, const Eigen::Vector3d& p3) {
  const Eigen::Vector3d a = p1 - p0, b = p2 - p0, c = p3 - p0;
  const double d = 2.0 * a.dot(b.cross(c));
  const Eigen::Vector3d offset =
      (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) + c.squaredNorm() * a.cross(b)) / d;
  return offset.allFinite() ? Eigen::Vector3d(p0 + offset) : Eigen::Vector3d((p0 + p1 + p2 + p3) / 4.0);
}

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

// What crust() and medial_axis() share: the Delaunay triangulation of the samples, its Voronoi
// vertices (circumcentres, one per triangle) and the crust edges as sorted keys.
struct CrustData {
  detail::Triangulation delaunay;
  Eigen::MatrixXd voronoi_vertices;
  std::vector<std::uint64_t> crust_edges;
};

CrustData crust_data(const Eigen::Ref<const Eigen::MatrixXd>& samples, const char* function) {
  check_samples(samples, 2, 3, function);
  CrustData data;
  data.delaunay = full_delaunay(samples, function);
  const auto& T = data.delaunay.simplices;
  const Eigen::Index n = samples.rows();
  data.voronoi_vertices.resize(T.rows(), 2);
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    data.voronoi_vertices.row(t) = circumcentre(samples.row(T(t, 0)).transpose(),
                                                samples.row(T(t, 1)).transpose(),
                                                samples.row(T(t, 2)).transpose()).transpose();
  Eigen::MatrixXd all(n + T.rows(), 2);
  all << samples, data.voronoi_vertices;
  // Coincident Voronoi vertices (co-circular samples) collapse to one vertex: harmless here.
  const detail::Triangulation filtered = detail::delaunay_triangulation(all);
  for (Eigen::Index t = 0; t < filtered.simplices.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = filtered.simplices(t, k), b = filtered.simplices(t, (k + 1) % 3);
      if (a < n && b < n) data.crust_edges.push_back(edge_key(a, b));
    }
  std::sort(data.crust_edges.begin(), data.crust_edges.end());
  data.crust_edges.erase(std::unique(data.crust_edges.begin(), data.crust_edges.end()),
                         data.crust_edges.end());
  return data;
}

/// The samples on normalized coordinates (core/normalization.h): circumcentres are cubic over
/// quadratic in the coordinates and under- or overflowed from 1e±154 (falling back to the
/// centroid, which changed the medial axis and the crust). Contouring is scale-invariant, so
/// each entry point runs on these and maps lengths and positions back with `frame`.
Eigen::MatrixXd normalized_samples(const Eigen::Ref<const Eigen::MatrixXd>& samples, CoordinateFrame& frame) {
  const PointMatrix rows = samples;
  frame = normalizing_frame(rows);
  return frame.normalize(rows);
}

EdgeMatrix keys_to_edges(const std::vector<std::uint64_t>& keys) {
  EdgeMatrix E(static_cast<Eigen::Index>(keys.size()), 2);
  for (std::size_t e = 0; e < keys.size(); ++e) {
    E(static_cast<Eigen::Index>(e), 0) = static_cast<int>(keys[e] >> 32);
    E(static_cast<Eigen::Index>(e), 1) = static_cast<int>(keys[e] & 0xffffffffu);
  }
  return E;
}

}  // namespace

EdgeMatrix crust(const Eigen::Ref<const Eigen::MatrixXd>& input_samples) {
  CoordinateFrame frame;
  return keys_to_edges(crust_data(normalized_samples(input_samples, frame), "crust").crust_edges);
}

namespace {

MedialAxis medial_axis_normalized(const Eigen::Ref<const Eigen::MatrixXd>& samples) {
  const CrustData data = crust_data(samples, "medial_axis");
  const auto& T = data.delaunay.simplices;
  // Delaunay edge → the (one or two) triangles on it.
  std::vector<std::pair<std::uint64_t, int>> edge_triangles;
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      edge_triangles.emplace_back(edge_key(T(t, k), T(t, (k + 1) % 3)), static_cast<int>(t));
  std::sort(edge_triangles.begin(), edge_triangles.end());
  std::vector<std::pair<int, int>> voronoi_edges;
  for (std::size_t e = 0; e + 1 < edge_triangles.size(); ++e) {
    if (edge_triangles[e].first != edge_triangles[e + 1].first) continue;
    if (!std::binary_search(data.crust_edges.begin(), data.crust_edges.end(), edge_triangles[e].first))
      voronoi_edges.emplace_back(edge_triangles[e].second, edge_triangles[e + 1].second);
    ++e;
  }
  std::vector<int> new_index(static_cast<std::size_t>(T.rows()), -1);
  MedialAxis axis;
  int used = 0;
  for (auto& [a, b] : voronoi_edges)
    for (int* v : {&a, &b}) {
      if (new_index[*v] < 0) new_index[*v] = used++;
      *v = new_index[*v];
    }
  axis.vertices.resize(used, 2);
  for (Eigen::Index t = 0; t < T.rows(); ++t)
    if (new_index[t] >= 0) axis.vertices.row(new_index[t]) = data.voronoi_vertices.row(t);
  axis.edges.resize(static_cast<Eigen::Index>(voronoi_edges.size()), 2);
  for (std::size_t e = 0; e < voronoi_edges.size(); ++e)
    axis.edges.row(static_cast<Eigen::Index>(e)) << voronoi_edges[e].first, voronoi_edges[e].second;
  return axis;
}

/// local_feature_size on normalized samples, in their units.
Eigen::VectorXd local_feature_size_normalized(const Eigen::Ref<const Eigen::MatrixXd>& samples) {
  const MedialAxis axis = medial_axis_normalized(samples);
  const Eigen::Index n = samples.rows();
  Eigen::VectorXd lfs(n);
  if (axis.vertices.rows() == 0) {
    lfs.setConstant(std::numeric_limits<double>::infinity());
    return lfs;
  }
  VertexMatrix axis_points = VertexMatrix::Zero(axis.vertices.rows(), 3);
  axis_points.leftCols(2) = axis.vertices;
  const points::KdTree tree(axis_points);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double sample[3] = {samples(i, 0), samples(i, 1), 0.0};
    double query[3];
    tree.frame().normalize_point(sample, query);
    std::uint32_t nearest = 0;
    double squared = 0.0;
    tree.nearest(query, 1, &nearest, &squared);
    lfs(i) = tree.frame().to_input(std::sqrt(squared), 1, "local_feature_size: a distance");
  }
  return lfs;
}

}  // namespace

MedialAxis medial_axis(const Eigen::Ref<const Eigen::MatrixXd>& input_samples) {
  CoordinateFrame frame;
  MedialAxis axis = medial_axis_normalized(normalized_samples(input_samples, frame));
  axis.vertices = frame.positions_to_input(PointMatrix(axis.vertices), "medial_axis: vertex");
  return axis;
}

Eigen::VectorXd local_feature_size(const Eigen::Ref<const Eigen::MatrixXd>& input_samples) {
  CoordinateFrame frame;
  Eigen::VectorXd lfs = local_feature_size_normalized(normalized_samples(input_samples, frame));
  frame.to_input(lfs.data(), lfs.size(), 1, "local_feature_size: sample");
  return lfs;
}

double sampling_ratio(const Eigen::Ref<const Eigen::MatrixXd>& input_samples) {
  CoordinateFrame frame;
  const Eigen::MatrixXd samples = normalized_samples(input_samples, frame);  // the ratio is scale-invariant
  const EdgeMatrix E = crust(samples);
  const Eigen::VectorXd lfs = local_feature_size_normalized(samples);
  double ratio = 0.0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const double half = 0.5 * (samples.row(E(e, 0)) - samples.row(E(e, 1))).norm();
    const double lower_bound = std::max(lfs(E(e, 0)), lfs(E(e, 1))) - half;
    if (lower_bound <= 0.0) return std::numeric_limits<double>::infinity();
    ratio = std::max(ratio, half / lower_bound);
  }
  return ratio;
}

// ---------------------------------------------------------------------------------------------
// Cocone (3D)

namespace {

struct DelaunayFace {
  std::array<int, 3> corners;  // sorted
  int tet = -1;                // a tetrahedron on this face
  int other_tet = -1;          // the second one, -1 on the convex hull
  int opposite = -1;           // corner of `tet` opposite the face
};

std::vector<DelaunayFace> delaunay_faces(const detail::SimplexMatrix& tets) {
  std::vector<DelaunayFace> all;
  all.reserve(static_cast<std::size_t>(tets.rows()) * 4);
  for (Eigen::Index t = 0; t < tets.rows(); ++t)
    for (int k = 0; k < 4; ++k) {
      DelaunayFace f;
      int c = 0;
      for (int j = 0; j < 4; ++j)
        if (j != k) f.corners[c++] = tets(t, j);
      std::sort(f.corners.begin(), f.corners.end());
      f.tet = static_cast<int>(t);
      f.opposite = tets(t, k);
      all.push_back(f);
    }
  std::sort(all.begin(), all.end(), [](const DelaunayFace& a, const DelaunayFace& b) {
    return a.corners < b.corners;
  });
  std::vector<DelaunayFace> faces;
  for (std::size_t i = 0; i < all.size(); ++i) {
    DelaunayFace f = all[i];
    if (i + 1 < all.size() && all[i + 1].corners == f.corners) f.other_tet = all[++i].tet;
    faces.push_back(f);
  }
  return faces;
}

Eigen::Vector3d row3(const Eigen::Ref<const Eigen::MatrixXd>& P, int i) {
  return P.row(i).transpose();
}

// Does the segment [e0, e1] meet the double cone {x : |cos angle(x - p, n)| <= sin θ}? The caps
// {cos > sin θ} and {cos < -sin θ} are geodesically convex, so the segment misses the cocone
// exactly when both ends lie in the same cap.
bool meets_cocone(const Eigen::Vector3d& p, const Eigen::Vector3d& n, const Eigen::Vector3d& e0,
                  const Eigen::Vector3d& e1, double sin_theta) {
  auto cosine = [&](const Eigen::Vector3d& e) {
    const Eigen::Vector3d d = e - p;
    const double length = d.norm();
    return length > 0.0 ? d.dot(n) / length : 0.0;
  };
  const double c0 = cosine(e0), c1 = cosine(e1);
  return !((c0 > sin_theta && c1 > sin_theta) || (c0 < -sin_theta && c1 < -sin_theta));
}

// Is the loop nearly planar: its points' spread along their least principal direction at most
// `flatness` times that along their largest?
bool is_planar_loop(const Eigen::Ref<const Eigen::MatrixXd>& P, const std::vector<int>& loop,
                    double flatness) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int v : loop) mean += P.row(v).transpose();
  mean /= static_cast<double>(loop.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int v : loop) {
    const Eigen::Vector3d d = P.row(v).transpose() - mean;
    scatter += d * d.transpose();
  }
  const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  return spread(2) > 0.0 && std::sqrt(std::max(spread(0), 0.0) / spread(2)) <= flatness;
}

// Unit surface normals at the points: the pole directions, signed to agree with the area-weighted
// normal of the oriented triangles around each point (a point on no triangle keeps its pole).
std::vector<Eigen::Vector3d> oriented_normals(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                              const std::vector<std::array<int, 3>>& triangles,
                                              const std::vector<Eigen::Vector3d>& pole) {
  std::vector<Eigen::Vector3d> area_normal(pole.size(), Eigen::Vector3d::Zero());
  for (const auto& f : triangles) {
    const Eigen::Vector3d n = (row3(P, f[1]) - row3(P, f[0])).cross(row3(P, f[2]) - row3(P, f[0]));
    for (int c : f) area_normal[c] += n;
  }
  std::vector<Eigen::Vector3d> normal(pole);
  for (std::size_t v = 0; v < pole.size(); ++v)
    if (pole[v].dot(area_normal[v]) < 0.0) normal[v] = -pole[v];
  return normal;
}

// Triangulates holes of an oriented surface by dynamic programming over the boundary loop: the
// minimum-area triangulation of a polygon in space (Barequet & Sharir 1995; Liepa 2003), among
// triangles that do not face against the normals of two of their corners (inward) unless nothing
// else closes the hole. (Measured against ear cutting and against weights that also prefer
// Delaunay faces or fat triangles: pure area follows the source surfaces best, e.g. pmp-bunny's
// flat base 0.70 mean spacings from the source instead of 0.94.)
class HoleTriangulator {
 public:
  HoleTriangulator(const Eigen::Ref<const Eigen::MatrixXd>& P, std::vector<Eigen::Vector3d> normal)
      : P_(P), normal_(std::move(normal)) {}

  std::vector<Eigen::Vector3d>& normals() { return normal_; }

  Eigen::Vector3d normal(const std::array<int, 3>& f) const {
    return (row3(P_, f[1]) - row3(P_, f[0])).cross(row3(P_, f[2]) - row3(P_, f[0]));
  }

  /// Inward: the triangle's orientation disagrees with the normals of two of its corners.
  bool is_inward(const std::array<int, 3>& f) const {
    const Eigen::Vector3d n = normal(f);
    int against = 0;
    for (int c : f) against += n.dot(normal_[c]) < 0.0;
    return against >= 2;
  }

  /// `loop`: the hole's vertices in the direction of the boundary half-edges of the triangles
  /// around it (at least 3, no repeats). `edge_exists(a, b)`: whether ab is an edge of the
  /// surface. Returns the fill triangles, oriented against the loop (consistently with the
  /// surface), with no new edge that exists already; empty when there is no such triangulation.
  template <typename EdgeExists>
  std::vector<std::array<int, 3>> triangulate(const std::vector<int>& loop, EdgeExists edge_exists) const {
    std::vector<std::array<int, 3>> fill = triangulate(loop, edge_exists, false);
    return fill.empty() ? triangulate(loop, edge_exists, true) : fill;
  }

 private:
  double weight(const std::array<int, 3>& f, bool allow_inward) const {
    if (!allow_inward && is_inward(f)) return std::numeric_limits<double>::infinity();
    return 0.5 * normal(f).norm();
  }

  template <typename EdgeExists>
  std::vector<std::array<int, 3>> triangulate(const std::vector<int>& loop, EdgeExists edge_exists,
                                              bool allow_inward) const {
    const int k = static_cast<int>(loop.size());
    const double infinity = std::numeric_limits<double>::infinity();
    // best[i*k + j]: weight of the best triangulation of the sub-polygon loop[i..j] (closed by
    // the chord ij); apex[i*k + j]: its triangle's third corner.
    std::vector<double> best(static_cast<std::size_t>(k) * k, infinity);
    std::vector<int> apex(static_cast<std::size_t>(k) * k, -1);
    for (int i = 0; i + 1 < k; ++i) best[i * k + i + 1] = 0.0;
    for (int length = 2; length < k; ++length)
      for (int i = 0; i + length < k; ++i) {
        const int j = i + length;
        if (!(i == 0 && j == k - 1) && edge_exists(loop[i], loop[j])) continue;  // chord exists
        for (int m = i + 1; m < j; ++m) {
          const double sides = best[i * k + m] + best[m * k + j];
          if (sides == infinity) continue;
          const double total = sides + weight({loop[j], loop[m], loop[i]}, allow_inward);
          if (total < best[i * k + j]) {
            best[i * k + j] = total;
            apex[i * k + j] = m;
          }
        }
      }
    std::vector<std::array<int, 3>> fill;
    if (best[k - 1] == infinity) return fill;
    std::vector<std::pair<int, int>> stack{{0, k - 1}};
    while (!stack.empty()) {
      const auto [i, j] = stack.back();
      stack.pop_back();
      if (j - i < 2) continue;
      const int m = apex[i * k + j];
      fill.push_back({loop[j], loop[m], loop[i]});
      stack.emplace_back(i, m);
      stack.emplace_back(m, j);
    }
    return fill;
  }

  const Eigen::Ref<const Eigen::MatrixXd>& P_;
  std::vector<Eigen::Vector3d> normal_;
};

// Closes the holes of an oriented triangle set bounded by simple loops of at most `max_edges`
// boundary edges, and of at most 4·max_edges edges when the loop is nearly planar (least
// principal spread at most 0.4 of the largest), with `hole_triangulator`.
void fill_small_holes(const Eigen::Ref<const Eigen::MatrixXd>& P,
                      std::vector<std::array<int, 3>>& triangles, int max_edges,
                      const HoleTriangulator& hole_triangulator) {
  const int max_planar_edges = 4 * max_edges;
  std::map<std::uint64_t, int> edge_use;
  std::map<int, std::vector<int>> boundary_next;  // a -> b for boundary half-edges a→b
  for (const auto& f : triangles)
    for (int j = 0; j < 3; ++j) ++edge_use[edge_key(f[j], f[(j + 1) % 3])];
  for (const auto& f : triangles)
    for (int j = 0; j < 3; ++j)
      if (edge_use[edge_key(f[j], f[(j + 1) % 3])] == 1) boundary_next[f[j]].push_back(f[(j + 1) % 3]);
  auto edge_exists = [&](int a, int b) {
    const auto it = edge_use.find(edge_key(a, b));
    return it != edge_use.end() && it->second > 0;
  };
  std::map<int, bool> visited;
  for (const auto& [start, outgoing] : boundary_next) {
    if (visited[start]) continue;
    // Follow the loop; give up on branching (non-manifold) or long loops.
    std::vector<int> loop{start};
    bool simple = true;
    int v = start;
    while (simple) {
      const auto it = boundary_next.find(v);
      if (it == boundary_next.end() || it->second.size() != 1) {
        simple = false;
        break;
      }
      v = it->second[0];
      if (v == start) break;
      if (static_cast<int>(loop.size()) >= max_planar_edges ||
          std::find(loop.begin(), loop.end(), v) != loop.end()) {
        simple = false;
        break;
      }
      loop.push_back(v);
    }
    for (int u : loop) visited[u] = true;
    if (!simple || loop.size() < 3) continue;
    if (static_cast<int>(loop.size()) > max_edges && !is_planar_loop(P, loop, 0.4)) continue;
    for (const auto& f : hole_triangulator.triangulate(loop, edge_exists)) {
      triangles.push_back(f);
      for (int j = 0; j < 3; ++j) ++edge_use[edge_key(f[j], f[(j + 1) % 3])];
    }
  }
}

// Where the triangles around a vertex form several fans (a non-manifold vertex), keeps the
// largest fan and removes the others; returns whether anything was removed.
bool remove_extra_fans(std::vector<std::array<int, 3>>& triangles) {
  std::map<int, std::vector<int>> star;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int c : triangles[t]) star[c].push_back(static_cast<int>(t));
  std::vector<bool> removed(triangles.size(), false);
  bool any = false;
  for (const auto& [v, around] : star) {
    // Union the triangles of the star that share an edge (v, x).
    std::vector<int> group(around.size());
    for (std::size_t a = 0; a < around.size(); ++a) group[a] = static_cast<int>(a);
    auto root = [&](int a) {
      while (group[a] != a) a = group[a] = group[group[a]];
      return a;
    };
    std::map<int, int> first_with;  // other corner x → a star triangle holding edge (v, x)
    for (std::size_t a = 0; a < around.size(); ++a)
      for (int x : triangles[around[a]]) {
        if (x == v) continue;
        const auto [it, inserted] = first_with.emplace(x, static_cast<int>(a));
        if (!inserted) group[root(static_cast<int>(a))] = root(it->second);
      }
    std::map<int, int> size;
    for (std::size_t a = 0; a < around.size(); ++a) ++size[root(static_cast<int>(a))];
    if (size.size() < 2) continue;
    int largest = size.begin()->first;
    for (const auto& [r, count] : size)
      if (count > size[largest]) largest = r;
    for (std::size_t a = 0; a < around.size(); ++a)
      if (root(static_cast<int>(a)) != largest && !removed[around[a]]) {
        removed[around[a]] = true;
        any = true;
      }
  }
  if (!any) return false;
  std::vector<std::array<int, 3>> kept;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (!removed[t]) kept.push_back(triangles[t]);
  triangles.swap(kept);
  return true;
}

// An oriented triangle set under local edits (split, flip, remove, add): each directed half-edge
// a→b is held by at most one triangle, recorded in `owner`. Removed triangles stay as {-1,-1,-1}
// until compact().
class SurfaceEditor {
 public:
  SurfaceEditor(const Eigen::Ref<const Eigen::MatrixXd>& P, std::vector<std::array<int, 3>>& triangles)
      : P_(P), triangles_(triangles) {
    owner_.reserve(triangles_.size() * 3);
    for (std::size_t t = 0; t < triangles_.size(); ++t) index(static_cast<int>(t));
  }

  /// The triangle holding the directed half-edge a→b, or -1.
  int owner(int a, int b) const {
    const auto it = owner_.find(half_edge_key(a, b));
    return it == owner_.end() ? -1 : it->second;
  }
  bool has_edge(int a, int b) const { return owner(a, b) >= 0 || owner(b, a) >= 0; }
  static bool is_removed(const std::array<int, 3>& f) { return f[0] < 0; }

  /// The corner of triangle t that is neither a nor b.
  int third(int t, int a, int b) const {
    for (int c : triangles_[t])
      if (c != a && c != b) return c;
    return -1;
  }

  void remove(int t) {
    unindex(t);
    triangles_[t] = {-1, -1, -1};
  }
  int add(const std::array<int, 3>& f) {
    triangles_.push_back(f);
    index(static_cast<int>(triangles_.size()) - 1);
    return static_cast<int>(triangles_.size()) - 1;
  }

  /// Splits triangle t = (a, b, c) at the new vertex v into (a, b, v), (b, c, v), (c, a, v).
  void split(int t, int v) {
    const std::array<int, 3> f = triangles_[t];
    remove(t);
    triangles_[t] = {f[0], f[1], v};
    index(t);
    add({f[1], f[2], v});
    add({f[2], f[0], v});
  }

  /// The two triangles (a, b, c) and (b, a, d) that a flip of edge ab would replace by
  /// (a, d, c) and (d, b, c); false when ab is not an edge of two triangles or cd is an edge
  /// already (the flip would make it non-manifold).
  struct Flip {
    int t0 = -1, t1 = -1, c = -1, d = -1;
    std::array<int, 3> new0{}, new1{};
  };
  bool flip_of(int a, int b, Flip& flip) const {
    flip.t0 = owner(a, b);
    flip.t1 = owner(b, a);
    if (flip.t0 < 0 || flip.t1 < 0) return false;
    flip.c = third(flip.t0, a, b);
    flip.d = third(flip.t1, a, b);
    if (flip.c == flip.d || has_edge(flip.c, flip.d)) return false;
    flip.new0 = {a, flip.d, flip.c};
    flip.new1 = {flip.d, b, flip.c};
    return true;
  }
  void apply(const Flip& flip) {
    unindex(flip.t0);
    unindex(flip.t1);
    triangles_[flip.t0] = flip.new0;
    triangles_[flip.t1] = flip.new1;
    index(flip.t0);
    index(flip.t1);
  }

  /// Rebuilds the half-edge index after the triangles were replaced wholesale.
  void reindex() {
    owner_.clear();
    for (std::size_t t = 0; t < triangles_.size(); ++t)
      if (!is_removed(triangles_[t])) index(static_cast<int>(t));
  }

  /// Drops the removed triangles.
  void compact() {
    triangles_.erase(std::remove_if(triangles_.begin(), triangles_.end(), is_removed), triangles_.end());
    owner_.clear();
    for (std::size_t t = 0; t < triangles_.size(); ++t) index(static_cast<int>(t));
  }

 private:
  static std::uint64_t half_edge_key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  }
  void index(int t) {
    const auto& f = triangles_[t];
    for (int j = 0; j < 3; ++j) owner_[half_edge_key(f[j], f[(j + 1) % 3])] = t;
  }
  void unindex(int t) {
    const auto& f = triangles_[t];
    for (int j = 0; j < 3; ++j) {
      const auto it = owner_.find(half_edge_key(f[j], f[(j + 1) % 3]));
      if (it != owner_.end() && it->second == t) owner_.erase(it);
    }
  }

  const Eigen::Ref<const Eigen::MatrixXd>& P_;
  std::vector<std::array<int, 3>>& triangles_;
  std::unordered_map<std::uint64_t, int> owner_;
};

// Angle at corner c of triangle (a, b, c).
double corner_angle(const Eigen::Ref<const Eigen::MatrixXd>& P, int a, int b, int c) {
  const Eigen::Vector3d u = row3(P, a) - row3(P, c), w = row3(P, b) - row3(P, c);
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

// Repairs of the extracted surface by local edits that keep it closed, manifold and
// consistently oriented: samples on no triangle are inserted, and inward triangles (folds,
// pleats) are cut out with their neighbours (or their corners' stars) and the hole
// re-triangulated. Orientation tests use the pole normals signed by the extracted surface.
class SurfaceRepair {
 public:
  SurfaceRepair(const Eigen::Ref<const Eigen::MatrixXd>& P, std::vector<std::array<int, 3>>& triangles,
                HoleTriangulator& hole_triangulator)
      : P_(P), triangles_(triangles), editor_(P, triangles), holes_(hole_triangulator) {}

  /// Inserts each sample on no triangle into the triangle around its Delaunay neighbours into
  /// which it projects (nearest to the plane; else the nearest centroid), then flips the edges
  /// around it (see flip_edges).
  void insert_missing(const std::vector<std::pair<int, int>>& delaunay_edges) {
    std::vector<Eigen::Vector3d>& normal = holes_.normals();
    const std::size_t n = normal.size();
    std::vector<bool> used(n, false);
    for (const auto& f : triangles_)
      if (!SurfaceEditor::is_removed(f))
        for (int c : f) used[c] = true;
    std::map<int, std::vector<int>> neighbours;  // missing sample → its Delaunay neighbours
    for (std::size_t v = 0; v < n; ++v)
      if (!used[v]) neighbours[static_cast<int>(v)];
    if (neighbours.empty()) return;
    for (const auto& [a, b] : delaunay_edges) {
      if (!used[a]) neighbours[a].push_back(b);
      if (!used[b]) neighbours[b].push_back(a);
    }
    std::vector<std::vector<int>> star(n);
    for (std::size_t t = 0; t < triangles_.size(); ++t)
      if (!SurfaceEditor::is_removed(triangles_[t]))
        for (int c : triangles_[t]) star[c].push_back(static_cast<int>(t));
    std::vector<std::pair<int, int>> to_flip;
    std::vector<int> pending;
    for (const auto& [v, around] : neighbours) pending.push_back(v);
    // Rounds: a sample whose neighbours are all missing waits for them.
    for (int round = 0; round < 8 && !pending.empty(); ++round) {
      std::vector<int> waiting;
      for (int v : pending) {
        const int t = host_triangle(v, neighbours[v], star);
        if (t < 0) {
          waiting.push_back(v);
          continue;
        }
        const std::array<int, 3> f = triangles_[t];
        const int first_new = static_cast<int>(triangles_.size());
        editor_.split(t, v);
        if (normal[v].dot(holes_.normal(f)) < 0.0) normal[v] = -normal[v];
        for (int k : {t, first_new, first_new + 1})
          for (int c : triangles_[k]) star[c].push_back(k);
        for (int j = 0; j < 3; ++j) to_flip.emplace_back(f[j], f[(j + 1) % 3]);
      }
      pending.swap(waiting);
    }
    flip_edges(to_flip);
  }

  /// Flips the queued edges (and then the edges around each flip) when the flip makes the two
  /// triangles agree better with the normals at their corners, or agree as well and satisfy the
  /// surface Delaunay criterion (the angles opposite the edge sum to at most π); never making an
  /// inward triangle or a fold sharper than a right angle.
  /// (Applied to all edges, or to those of the hole fills, this was measured to do worse: the
  /// restricted-Delaunay choices of the Cocone are better than this local rule elsewhere.)
  void flip_edges(std::vector<std::pair<int, int>>& to_flip) {
    std::size_t budget = 64 * to_flip.size();
    while (!to_flip.empty() && budget-- > 0) {
      const auto [a, b] = to_flip.back();
      to_flip.pop_back();
      SurfaceEditor::Flip flip;
      if (!editor_.flip_of(a, b, flip)) continue;
      if (holes_.is_inward(flip.new0) || holes_.is_inward(flip.new1)) continue;
      if (holes_.normal(flip.new0).dot(holes_.normal(flip.new1)) <= 0.0) continue;
      const double before = std::min(agreement(triangles_[flip.t0]), agreement(triangles_[flip.t1]));
      const double after = std::min(agreement(flip.new0), agreement(flip.new1));
      const bool delaunay = corner_angle(P_, a, b, flip.c) + corner_angle(P_, a, b, flip.d) > 3.14159265358979323846 + 1e-12;
      if (!(after > before + 0.02 || (delaunay && after > before - 0.02))) continue;
      editor_.apply(flip);
      for (auto [x, y] : {std::pair{a, flip.d}, std::pair{flip.d, b}, std::pair{b, flip.c}, std::pair{flip.c, a}})
        to_flip.emplace_back(x, y);
    }
  }

  /// Cuts out each inward triangle together with its three neighbours and re-triangulates the
  /// hole without inward triangles; when that fails (a pleat: the neighbours fold back over the
  /// triangle), cuts out the stars of its corners instead, re-triangulates that hole and inserts
  /// the corners again (replace_stars: undone unless the result faces outwards; at most 32
  /// such attempts, each O(#triangles)). Regions that are not disks bounded by a simple loop,
  /// or whose hole has no outward triangulation, are kept as they were; up to 4 rounds.
  void remove_folds(const std::vector<std::pair<int, int>>& delaunay_edges) {
    int star_attempts = 0;  // each costs O(#triangles)
    for (int round = 0; round < 4; ++round) {
      bool any = false;
      std::vector<std::vector<int>> star(holes_.normals().size());
      for (std::size_t t = 0; t < triangles_.size(); ++t)
        if (!SurfaceEditor::is_removed(triangles_[t]))
          for (int c : triangles_[t]) star[c].push_back(static_cast<int>(t));
      const std::size_t count = triangles_.size();
      for (std::size_t t = 0; t < count; ++t) {
        const std::array<int, 3> f = triangles_[t];
        if (SurfaceEditor::is_removed(f) || !holes_.is_inward(f)) continue;
        std::vector<int> region{static_cast<int>(t)};
        for (int j = 0; j < 3; ++j) {
          const int other = editor_.owner(f[(j + 1) % 3], f[j]);
          if (other >= 0 && std::find(region.begin(), region.end(), other) == region.end()) region.push_back(other);
        }
        if (refill(region, false)) {
          any = true;
          continue;
        }
        region.clear();
        bool current = true;  // the star lists still describe the triangles
        for (int c : f)
          for (int k : star[c]) {
            const auto& g = triangles_[k];
            current = current && std::find(g.begin(), g.end(), c) != g.end();
            if (std::find(region.begin(), region.end(), k) == region.end()) region.push_back(k);
          }
        if (current && star_attempts < 32) {
          ++star_attempts;
          any = replace_stars(f, region, delaunay_edges) || any;
        }
      }
      if (!any) break;
    }
  }

  void compact() { editor_.compact(); }

 private:
  // Smallest cosine between the triangle's normal and the normals at its corners.
  double agreement(const std::array<int, 3>& f) const {
    const Eigen::Vector3d n = holes_.normal(f).normalized();
    double smallest = 1.0;
    for (int c : f) smallest = std::min(smallest, n.dot(holes_.normals()[c]));
    return smallest;
  }

  // Replaces `region`, the stars of the corners of `f`, by a triangulation of its boundary loop
  // and inserts the corners again; kept only if every new triangle around the region's samples
  // faces outwards and no edge there is longer than the longest edge of the region, else undone.
  bool replace_stars(const std::array<int, 3>& f, const std::vector<int>& region,
                     const std::vector<std::pair<int, int>>& delaunay_edges) {
    const std::vector<std::array<int, 3>> snapshot = triangles_;
    std::set<int> samples;
    double longest = 0.0;
    for (int t : region)
      for (int j = 0; j < 3; ++j) {
        samples.insert(triangles_[t][j]);
        longest = std::max(longest, (P_.row(triangles_[t][j]) - P_.row(triangles_[t][(j + 1) % 3])).norm());
      }
    bool good = refill(region, true);
    if (good) insert_missing(delaunay_edges);
    std::set<int> on_surface;
    for (std::size_t t = 0; good && t < triangles_.size(); ++t) {
      const auto& g = triangles_[t];
      if (SurfaceEditor::is_removed(g)) continue;
      bool touches = false;
      for (int c : g) touches = touches || samples.count(c) > 0;
      if (!touches) continue;
      for (int c : g) on_surface.insert(c);
      good = !holes_.is_inward(g);
      for (int j = 0; j < 3 && good; ++j)
        good = (P_.row(g[j]) - P_.row(g[(j + 1) % 3])).norm() <= longest;
    }
    for (int c : f) good = good && on_surface.count(c) > 0;
    if (!good) {
      triangles_ = snapshot;
      editor_.reindex();
    }
    return good;
  }

  // Replaces the triangles of `region` by a triangulation of its boundary loop; false (and
  // nothing changed) when that is not possible. Samples inside the region are dropped when
  // `drop_interior` (for insert_missing to put back), else the region is refused.
  bool refill(const std::vector<int>& region, bool drop_interior) {
    auto in_region = [&](int t) { return std::find(region.begin(), region.end(), t) != region.end(); };
    std::map<int, int> next;  // hole loop: b → a for each boundary half-edge a→b of the region
    std::set<int> corners;
    for (int t : region)
      for (int j = 0; j < 3; ++j) {
        const int a = triangles_[t][j], b = triangles_[t][(j + 1) % 3];
        corners.insert(a);
        if (in_region(editor_.owner(b, a))) continue;
        if (!next.emplace(b, a).second) return false;  // the boundary touches itself
      }
    if ((!drop_interior && next.size() != corners.size()) || next.size() < 3) return false;  // an interior sample
    std::vector<int> loop{next.begin()->first};
    while (loop.size() <= next.size()) {
      const auto it = next.find(loop.back());
      if (it == next.end()) return false;
      if (it->second == loop.front()) break;
      loop.push_back(it->second);
    }
    if (loop.size() != next.size()) return false;  // several loops
    std::vector<std::array<int, 3>> removed;
    for (int t : region) {
      removed.push_back(triangles_[t]);
      editor_.remove(t);
    }
    const auto fill = holes_.triangulate(loop, [&](int a, int b) { return editor_.has_edge(a, b); });
    bool inward = fill.empty();
    for (const auto& g : fill) inward = inward || holes_.is_inward(g);
    if (inward) {
      for (std::size_t r = 0; r < region.size(); ++r) editor_.add(removed[r]);
      return false;
    }
    for (const auto& g : fill) editor_.add(g);
    return true;
  }

  // The triangle around v's Delaunay neighbours into which v projects (nearest to its plane), or
  // failing that the one whose centroid is nearest; -1 when no neighbour is on a triangle.
  int host_triangle(int v, const std::vector<int>& neighbours, const std::vector<std::vector<int>>& star) const {
    const Eigen::Vector3d p = row3(P_, v);
    int inside = -1, nearest = -1;
    double inside_distance = std::numeric_limits<double>::infinity();
    double nearest_distance = std::numeric_limits<double>::infinity();
    for (int u : neighbours)
      for (int t : star[u]) {
        const auto& f = triangles_[t];
        if (SurfaceEditor::is_removed(f)) continue;
        const Eigen::Vector3d a = row3(P_, f[0]), b = row3(P_, f[1]), c = row3(P_, f[2]);
        const Eigen::Vector3d n = (b - a).cross(c - a);
        const double area2 = n.squaredNorm();
        if (!(area2 > 0.0)) continue;
        // Barycentric coordinates of the projection of p.
        const double wa = (c - b).cross(p - b).dot(n) / area2, wb = (a - c).cross(p - c).dot(n) / area2;
        const double plane = std::abs((p - a).dot(n)) / std::sqrt(area2);
        if (wa >= 0.0 && wb >= 0.0 && 1.0 - wa - wb >= 0.0 && plane < inside_distance) {
          inside_distance = plane;
          inside = t;
        }
        const double centroid = (p - (a + b + c) / 3.0).norm();
        if (centroid < nearest_distance) {
          nearest_distance = centroid;
          nearest = t;
        }
      }
    return inside >= 0 ? inside : nearest;
  }

  const Eigen::Ref<const Eigen::MatrixXd>& P_;
  std::vector<std::array<int, 3>>& triangles_;
  SurfaceEditor editor_;
  HoleTriangulator& holes_;
};

}  // namespace

Mesh crust_3d(const Eigen::Ref<const Eigen::MatrixXd>& input_P, const CoconeOptions& options,
              const Progress& progress) {
  check_samples(input_P, 3, 4, "crust_3d");
  CoordinateFrame frame;
  const Eigen::MatrixXd normalized = normalized_samples(input_P, frame);
  // A Ref that lives as long as the helpers below that keep a reference to it.
  const Eigen::Ref<const Eigen::MatrixXd> P(normalized);
  if (!(options.cocone_angle > 0.0 && options.cocone_angle < 1.5707963267948966))
    throw InputError("crust_3d: cocone_angle must lie in (0, pi/2)");
  if (options.max_hole_edges < 0) throw InputError("crust_3d: max_hole_edges must be >= 0");
  const Eigen::Index n = P.rows();
  const detail::Triangulation t = full_delaunay(P, "crust_3d", progress.subrange(0.0, 0.35));
  const auto& tets = t.simplices;
  std::vector<Eigen::Vector3d> centre(static_cast<std::size_t>(tets.rows()));
  for (Eigen::Index k = 0; k < tets.rows(); ++k)
    centre[k] = circumcentre(row3(P, tets(k, 0)), row3(P, tets(k, 1)), row3(P, tets(k, 2)), row3(P, tets(k, 3)));
  const std::vector<DelaunayFace> faces = delaunay_faces(tets);
  const double diagonal = (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm();

  // Outward unit normal of a hull face (away from its tetrahedron's opposite corner).
  auto hull_normal = [&](const DelaunayFace& f) {
    const Eigen::Vector3d a = row3(P, f.corners[0]), b = row3(P, f.corners[1]), c = row3(P, f.corners[2]);
    Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    if (normal.dot(row3(P, f.opposite) - a) > 0.0) normal = -normal;
    return normal;
  };

  // Pole vectors: farthest Voronoi vertex, or the mean outward hull normal on the hull.
  std::vector<Eigen::Vector3d> hull_direction(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  for (const auto& f : faces)
    if (f.other_tet < 0) {
      const Eigen::Vector3d normal = hull_normal(f);
      for (int c : f.corners) hull_direction[c] += normal;
    }
  std::vector<double> farthest(static_cast<std::size_t>(n), -1.0);
  std::vector<Eigen::Vector3d> pole(static_cast<std::size_t>(n), Eigen::Vector3d::Zero());
  for (Eigen::Index k = 0; k < tets.rows(); ++k) {
    if (k % 65536 == 0) progress.report(0.35 + 0.05 * static_cast<double>(k) / static_cast<double>(tets.rows()), "crust_3d: poles");
    for (int j = 0; j < 4; ++j) {
      const int v = tets(k, j);
      const Eigen::Vector3d d = centre[k] - row3(P, v);
      if (d.norm() > farthest[v]) {
        farthest[v] = d.norm();
        pole[v] = d;
      }
    }
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d& direction = hull_direction[v].squaredNorm() > 0.0 ? hull_direction[v] : pole[v];
    pole[v] = direction.normalized();
  }

  // Cocone candidates.
  const double sin_theta = std::sin(options.cocone_angle);
  std::vector<std::array<int, 3>> candidates;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (i % 65536 == 0) progress.report(0.4 + 0.1 * static_cast<double>(i) / static_cast<double>(faces.size()), "crust_3d: cocone");
    const DelaunayFace& f = faces[i];
    const Eigen::Vector3d e0 = centre[f.tet];
    const Eigen::Vector3d e1 = f.other_tet >= 0 ? centre[f.other_tet]
                                                : Eigen::Vector3d(e0 + 10.0 * diagonal * hull_normal(f));
    bool keep = true;
    for (int c : f.corners) keep = keep && meets_cocone(row3(P, c), pole[c], e0, e1, sin_theta);
    if (keep) candidates.push_back(f.corners);
  }

  progress.report(0.5, "crust_3d: pruning");
  // Edge → candidate triangles; remove dangling triangles until none is left.
  const std::size_t m = candidates.size();
  std::map<std::uint64_t, std::vector<int>> edge_triangles;
  for (std::size_t k = 0; k < m; ++k)
    for (int j = 0; j < 3; ++j)
      edge_triangles[edge_key(candidates[k][j], candidates[k][(j + 1) % 3])].push_back(static_cast<int>(k));
  std::vector<bool> alive(m, true);
  std::vector<int> stack;
  auto live_count = [&](std::uint64_t key) {
    int count = 0;
    for (int k : edge_triangles[key]) count += alive[k];
    return count;
  };
  // Sharp-edge pruning: an edge whose live candidates all lie within a wedge of less than π/2
  // (two consecutive ones around it leave a gap of more than 3π/2) cannot be a smooth surface
  // there; its candidates go (typically a triangle folded back across a flat tetrahedron).
  // Edges with a single live candidate are left to the dangling-triangle removal below.
  auto remove_sharp_edge_triangles = [&]() {
    bool any = false;
    for (auto& [key, around] : edge_triangles) {
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const Eigen::Vector3d pa = row3(P, a), axis = (row3(P, b) - pa).normalized();
      std::vector<std::pair<double, int>> angles;
      Eigen::Vector3d x_axis, y_axis;
      for (int k : around) {
        if (!alive[k]) continue;
        const auto& g = candidates[k];
        const int d = g[0] != a && g[0] != b ? g[0] : (g[1] != a && g[1] != b ? g[1] : g[2]);
        Eigen::Vector3d u = row3(P, d) - pa;
        u -= u.dot(axis) * axis;
        if (angles.empty()) {
          x_axis = u.normalized();
          y_axis = axis.cross(x_axis);
        }
        angles.emplace_back(std::atan2(u.dot(y_axis), u.dot(x_axis)), k);
      }
      if (angles.size() < 2) continue;
      std::sort(angles.begin(), angles.end());
      double largest_gap = angles.front().first + 2.0 * 3.14159265358979323846 - angles.back().first;
      for (std::size_t i = 0; i + 1 < angles.size(); ++i)
        largest_gap = std::max(largest_gap, angles[i + 1].first - angles[i].first);
      if (largest_gap <= 1.5 * 3.14159265358979323846) continue;
      for (const auto& [angle, k] : angles) alive[k] = false;
      any = true;
    }
    return any;
  };
  for (int round = 0; round < 3; ++round)
    if (!remove_sharp_edge_triangles()) break;
  for (std::size_t k = 0; k < m; ++k) stack.push_back(static_cast<int>(k));
  while (!stack.empty()) {
    const int k = stack.back();
    stack.pop_back();
    if (!alive[k]) continue;
    // A dangling triangle: a free edge, and another edge where the surface goes on without it.
    // (Triangles around a hole of the candidate set have a free edge but are kept.)
    bool free_edge = false, crowded_edge = false;
    for (int j = 0; j < 3; ++j) {
      const int count = live_count(edge_key(candidates[k][j], candidates[k][(j + 1) % 3]));
      free_edge = free_edge || count < 2;
      crowded_edge = crowded_edge || count > 2;
    }
    if (!(free_edge && crowded_edge)) continue;
    alive[k] = false;
    for (int j = 0; j < 3; ++j)
      for (int other : edge_triangles[edge_key(candidates[k][j], candidates[k][(j + 1) % 3])])
        if (alive[other]) stack.push_back(other);
  }

  // Outer-surface walk. oriented[k]: the corners of candidate k in the chosen orientation.
  std::vector<std::array<int, 3>> oriented(m);
  std::vector<bool> taken(m, false), vertex_used(static_cast<std::size_t>(n), false);
  std::vector<int> chosen;
  // Directed half-edges a→b of the chosen triangles: each at most once, so an edge carries at
  // most two chosen triangles, and two of them always in opposite directions (consistent
  // orientation).
  std::set<std::uint64_t> half_edges;
  auto half_edge = [](int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  };
  auto fits = [&](const std::array<int, 3>& f) {
    for (int j = 0; j < 3; ++j)
      if (half_edges.count(half_edge(f[j], f[(j + 1) % 3]))) return false;
    return true;
  };
  auto take = [&](int k) {
    taken[k] = true;
    for (int j = 0; j < 3; ++j) half_edges.insert(half_edge(oriented[k][j], oriented[k][(j + 1) % 3]));
  };
  auto normal_of = [&](const std::array<int, 3>& f) {
    return Eigen::Vector3d((row3(P, f[1]) - row3(P, f[0])).cross(row3(P, f[2]) - row3(P, f[0])));
  };
  progress.report(0.6, "crust_3d: extraction");
  while (true) {
    // Seed: among live triangles on unused vertices, the one at the point of largest x with the
    // largest |normal_x|, oriented with normal_x > 0.
    int seed = -1;
    double best_x = -std::numeric_limits<double>::infinity(), best_nx = -1.0;
    for (std::size_t k = 0; k < m; ++k) {
      if (!alive[k] || taken[k]) continue;
      const auto& f = candidates[k];
      if (vertex_used[f[0]] || vertex_used[f[1]] || vertex_used[f[2]]) continue;
      double x = -std::numeric_limits<double>::infinity();
      for (int c : f) x = std::max(x, P(c, 0));
      const double nx = std::abs(normal_of(f).normalized().x());
      if (x > best_x || (x == best_x && nx > best_nx)) {
        best_x = x;
        best_nx = nx;
        seed = static_cast<int>(k);
      }
    }
    if (seed < 0) break;
    oriented[seed] = candidates[seed];
    if (normal_of(oriented[seed]).x() < 0.0) std::swap(oriented[seed][1], oriented[seed][2]);
    if (!fits(oriented[seed])) {
      taken[seed] = true;  // never seed here again
      continue;
    }
    take(seed);
    std::vector<int> queue{seed};
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int k = queue[head];
      chosen.push_back(k);
      if (chosen.size() % 16384 == 0)
        progress.report(0.6 + 0.35 * std::min(1.0, static_cast<double>(chosen.size()) / (2.0 * static_cast<double>(n))),
                        "crust_3d: extraction");
      const auto& f = oriented[k];
      const Eigen::Vector3d normal = normal_of(f).normalized();
      for (int j = 0; j < 3; ++j) {
        const int a = f[j], b = f[(j + 1) % 3], c = f[(j + 2) % 3];
        const Eigen::Vector3d pa = row3(P, a), axis = (row3(P, b) - pa).normalized();
        auto perpendicular = [&](int v) {
          const Eigen::Vector3d d = row3(P, v) - pa;
          return Eigen::Vector3d(d - d.dot(axis) * axis);
        };
        const Eigen::Vector3d x_axis = perpendicular(c).normalized();
        int next = -1;
        double smallest = std::numeric_limits<double>::infinity();
        for (int other : edge_triangles[edge_key(a, b)]) {
          if (other == k || !alive[other]) continue;
          const auto& g = candidates[other];
          const int d = g[0] != a && g[0] != b ? g[0] : (g[1] != a && g[1] != b ? g[1] : g[2]);
          const Eigen::Vector3d u = perpendicular(d);
          double angle = std::atan2(u.dot(normal), u.dot(x_axis));
          if (angle <= 0.0) angle += 2.0 * 3.14159265358979323846;
          if (angle < smallest) {
            smallest = angle;
            next = other;
          }
        }
        if (next < 0 || taken[next]) continue;
        const auto& g = candidates[next];
        const int d = g[0] != a && g[0] != b ? g[0] : (g[1] != a && g[1] != b ? g[1] : g[2]);
        oriented[next] = {b, a, d};
        if (!fits(oriented[next])) continue;
        take(next);
        queue.push_back(next);
      }
    }
    for (int k : queue)
      for (int c : oriented[k]) vertex_used[c] = true;
  }

  std::vector<std::array<int, 3>> triangles;
  for (int k : chosen) triangles.push_back(oriented[k]);
  progress.report(0.95, "crust_3d: repair");
  HoleTriangulator hole_triangulator(P, oriented_normals(P, triangles, pole));
  progress.report(0.955, "crust_3d: repair (holes)");
  fill_small_holes(P, triangles, options.max_hole_edges, hole_triangulator);
  for (int round = 0; round < 3 && remove_extra_fans(triangles); ++round) {
    progress.report(0.96 + 0.005 * round, "crust_3d: repair (fans)");
    fill_small_holes(P, triangles, options.max_hole_edges, hole_triangulator);
  }
  progress.report(0.975, "crust_3d: repair (missing edges)");
  SurfaceRepair repair(P, triangles, hole_triangulator);
  repair.insert_missing(t.edges);
  progress.report(0.985, "crust_3d: repair (folds)");
  repair.remove_folds(t.edges);
  progress.report(0.995, "crust_3d: repair (compact)");
  repair.compact();
  progress.report(1.0, "crust_3d");

  Mesh mesh;
  mesh.V = input_P;
  mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t r = 0; r < triangles.size(); ++r)
    for (int j = 0; j < 3; ++j) mesh.F(static_cast<Eigen::Index>(r), j) = triangles[r][j];
  return mesh;
}

}  // namespace meshsmith::tessellation
