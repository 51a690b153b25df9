// Voronoi filtering (§2.1.3): the 2D crust, the approximate medial axis and LFS (§2.1.2), and
// the 3D Cocone reconstruction with its manifold extraction.
#include <meshsmith/core/errors.h>
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
detail::Triangulation full_delaunay(const Eigen::Ref<const Eigen::MatrixXd>& P, const char* function) {
  detail::Triangulation t = detail::delaunay_triangulation(P);
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

EdgeMatrix keys_to_edges(const std::vector<std::uint64_t>& keys) {
  EdgeMatrix E(static_cast<Eigen::Index>(keys.size()), 2);
  for (std::size_t e = 0; e < keys.size(); ++e) {
    E(static_cast<Eigen::Index>(e), 0) = static_cast<int>(keys[e] >> 32);
    E(static_cast<Eigen::Index>(e), 1) = static_cast<int>(keys[e] & 0xffffffffu);
  }
  return E;
}

}  // namespace

EdgeMatrix crust(const Eigen::Ref<const Eigen::MatrixXd>& samples) {
  return keys_to_edges(crust_data(samples, "crust").crust_edges);
}

MedialAxis medial_axis(const Eigen::Ref<const Eigen::MatrixXd>& samples) {
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

Eigen::VectorXd local_feature_size(const Eigen::Ref<const Eigen::MatrixXd>& samples) {
  const MedialAxis axis = medial_axis(samples);
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
    const double query[3] = {samples(i, 0), samples(i, 1), 0.0};
    std::uint32_t nearest = 0;
    double squared = 0.0;
    tree.nearest(query, 1, &nearest, &squared);
    lfs(i) = std::sqrt(squared);
  }
  return lfs;
}

double sampling_ratio(const Eigen::Ref<const Eigen::MatrixXd>& samples) {
  const EdgeMatrix E = crust(samples);
  const Eigen::VectorXd lfs = local_feature_size(samples);
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

// Closes the holes of an oriented triangle set bounded by simple loops of at most `max_edges`
// boundary edges, and of at most 4·max_edges edges when the loop is nearly planar (least
// principal spread at most 0.4 of the largest), by cutting ears (shortest new edge first) that
// create no edge used twice.
void fill_small_holes(const Eigen::Ref<const Eigen::MatrixXd>& P,
                      std::vector<std::array<int, 3>>& triangles, int max_edges) {
  const int max_planar_edges = 4 * max_edges;
  std::map<std::uint64_t, int> edge_use;
  std::map<int, std::vector<int>> boundary_next;  // a -> b for boundary half-edges a→b
  for (const auto& f : triangles)
    for (int j = 0; j < 3; ++j) ++edge_use[edge_key(f[j], f[(j + 1) % 3])];
  for (const auto& f : triangles)
    for (int j = 0; j < 3; ++j)
      if (edge_use[edge_key(f[j], f[(j + 1) % 3])] == 1) boundary_next[f[j]].push_back(f[(j + 1) % 3]);
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
    // Ear cutting. The fill triangles run against the loop's direction.
    while (loop.size() > 3) {
      int best = -1;
      double shortest = std::numeric_limits<double>::infinity();
      const int k = static_cast<int>(loop.size());
      for (int i = 0; i < k; ++i) {
        const int previous = loop[(i + k - 1) % k], following = loop[(i + 1) % k];
        if (edge_use[edge_key(previous, following)] > 0) continue;
        const double length = (P.row(previous) - P.row(following)).norm();
        if (length < shortest) {
          shortest = length;
          best = i;
        }
      }
      if (best < 0) break;
      const int previous = loop[(best + k - 1) % k], following = loop[(best + 1) % k];
      triangles.push_back({following, loop[best], previous});
      for (int j = 0; j < 3; ++j)
        ++edge_use[edge_key(triangles.back()[j], triangles.back()[(j + 1) % 3])];
      loop.erase(loop.begin() + best);
    }
    if (loop.size() == 3) {
      triangles.push_back({loop[2], loop[1], loop[0]});
      for (int j = 0; j < 3; ++j)
        ++edge_use[edge_key(triangles.back()[j], triangles.back()[(j + 1) % 3])];
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

}  // namespace

Mesh crust_3d(const Eigen::Ref<const Eigen::MatrixXd>& P, const CoconeOptions& options) {
  check_samples(P, 3, 4, "crust_3d");
  if (!(options.cocone_angle > 0.0 && options.cocone_angle < 1.5707963267948966))
    throw InputError("crust_3d: cocone_angle must lie in (0, pi/2)");
  if (options.max_hole_edges < 0) throw InputError("crust_3d: max_hole_edges must be >= 0");
  const Eigen::Index n = P.rows();
  const detail::Triangulation t = full_delaunay(P, "crust_3d");
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
  for (Eigen::Index k = 0; k < tets.rows(); ++k)
    for (int j = 0; j < 4; ++j) {
      const int v = tets(k, j);
      const Eigen::Vector3d d = centre[k] - row3(P, v);
      if (d.norm() > farthest[v]) {
        farthest[v] = d.norm();
        pole[v] = d;
      }
    }
  for (Eigen::Index v = 0; v < n; ++v) {
    const Eigen::Vector3d& direction = hull_direction[v].squaredNorm() > 0.0 ? hull_direction[v] : pole[v];
    pole[v] = direction.normalized();
  }

  // Cocone candidates.
  const double sin_theta = std::sin(options.cocone_angle);
  std::vector<std::array<int, 3>> candidates;
  for (const auto& f : faces) {
    const Eigen::Vector3d e0 = centre[f.tet];
    const Eigen::Vector3d e1 = f.other_tet >= 0 ? centre[f.other_tet]
                                                : Eigen::Vector3d(e0 + 10.0 * diagonal * hull_normal(f));
    bool keep = true;
    for (int c : f.corners) keep = keep && meets_cocone(row3(P, c), pole[c], e0, e1, sin_theta);
    if (keep) candidates.push_back(f.corners);
  }

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
  fill_small_holes(P, triangles, options.max_hole_edges);
  for (int round = 0; round < 3 && remove_extra_fans(triangles); ++round)
    fill_small_holes(P, triangles, options.max_hole_edges);

  Mesh mesh;
  mesh.V = P;
  mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t r = 0; r < triangles.size(); ++r)
    for (int j = 0; j < 3; ++j) mesh.F(static_cast<Eigen::Index>(r), j) = triangles[r][j];
  return mesh;
}

}  // namespace meshsmith::tessellation
