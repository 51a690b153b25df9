// Power diagrams (§2.1.4): cells by clipping the box with the power half-spaces of the
// neighbours in the regular triangulation (contouring_triangulations_cgal.cpp).
#include <meshsmith/core/errors.h>
#include <meshsmith/tessellation/power_diagram.h>

#include "contouring_triangulations.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace meshsmith::tessellation {

namespace {

// Half-space { q : normal . q <= offset } with the tolerance below which a point counts as on
// its plane.
struct HalfSpace {
  Eigen::VectorXd normal;
  double offset = 0.0;
  double tolerance = 0.0;
  double side(const Eigen::VectorXd& q) const { return normal.dot(q) - offset; }
};

constexpr double kRelativeTolerance = 1e-12;

// The power half-space of site i against site j:
// |q-p_i|^2 - w_i <= |q-p_j|^2 - w_j  <=>  2 (p_j - p_i) . q <= |p_j|^2 - |p_i|^2 - w_j + w_i.
HalfSpace power_half_space(const Eigen::Ref<const Eigen::MatrixXd>& P, const Eigen::VectorXd& w,
                           Eigen::Index i, Eigen::Index j, double box_scale) {
  HalfSpace h;
  h.normal = 2.0 * (P.row(j) - P.row(i)).transpose();
  h.offset = P.row(j).squaredNorm() - P.row(i).squaredNorm() - w(j) + w(i);
  h.tolerance = kRelativeTolerance * (h.normal.norm() * box_scale + std::abs(h.offset) +
                                      std::abs(w(i)) + std::abs(w(j)));
  return h;
}

using Polygon = std::vector<Eigen::VectorXd>;

// Sutherland–Hodgman: the part of a convex polygon (2D or planar in 3D) in the half-space.
// Corners on the plane are kept and also appended to `on_plane` (if given) with the crossings.
Polygon clip_polygon(const Polygon& polygon, const HalfSpace& h, Polygon* on_plane) {
  Polygon out;
  const std::size_t k = polygon.size();
  std::vector<double> side(k);
  for (std::size_t a = 0; a < k; ++a) side[a] = h.side(polygon[a]);
  auto state = [&](std::size_t a) { return side[a] > h.tolerance ? 1 : (side[a] < -h.tolerance ? -1 : 0); };
  for (std::size_t a = 0; a < k; ++a) {
    const std::size_t b = (a + 1) % k;
    const int sa = state(a), sb = state(b);
    if (sa <= 0) out.push_back(polygon[a]);
    if (sa == 0 && on_plane) on_plane->push_back(polygon[a]);
    if (sa * sb < 0) {
      const double t = side[a] / (side[a] - side[b]);
      Eigen::VectorXd crossing = polygon[a] + t * (polygon[b] - polygon[a]);
      out.push_back(crossing);
      if (on_plane) on_plane->push_back(crossing);
    }
  }
  if (out.size() < 3) out.clear();
  return out;
}

Polygon box_polygon_2d(const Eigen::VectorXd& b) {
  Polygon box(4, Eigen::VectorXd(2));
  box[0] << b(0), b(1);
  box[1] << b(2), b(1);
  box[2] << b(2), b(3);
  box[3] << b(0), b(3);
  return box;
}

// A convex polyhedron as its faces, each a convex polygon counter-clockwise seen from outside.
using Polyhedron = std::vector<Polygon>;

Polyhedron box_polyhedron(const Eigen::VectorXd& b) {
  auto corner = [&](int x, int y, int z) {
    Eigen::VectorXd q(3);
    q << b(x ? 2 : 0), b(y ? 3 : 1), b(z ? 5 : 4);
    return q;
  };
  const int faces[6][4][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},   // z = zmin
                              {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},   // z = zmax
                              {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},   // y = ymin
                              {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},   // y = ymax
                              {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},   // x = xmin
                              {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};  // x = xmax
  Polyhedron box;
  for (const auto& face : faces) {
    Polygon polygon;
    for (const auto& c : face) polygon.push_back(corner(c[0], c[1], c[2]));
    box.push_back(polygon);
  }
  return box;
}

// Points of `points` closer than `tolerance` to an earlier one are dropped.
Polygon unique_points(const Polygon& points, double tolerance) {
  Polygon unique;
  for (const auto& p : points) {
    const bool seen = std::any_of(unique.begin(), unique.end(), [&](const Eigen::VectorXd& q) {
      return (p - q).norm() <= tolerance;
    });
    if (!seen) unique.push_back(p);
  }
  return unique;
}

Polyhedron clip_polyhedron(const Polyhedron& polyhedron, const HalfSpace& h, double point_tolerance) {
  Polyhedron out;
  Polygon on_plane;
  for (const auto& face : polyhedron) {
    Polygon clipped = clip_polygon(face, h, &on_plane);
    if (!clipped.empty()) out.push_back(std::move(clipped));
  }
  if (out.empty()) return out;
  Polygon cap = unique_points(on_plane, point_tolerance);
  if (cap.size() < 3) return out;
  // Order the cap counter-clockwise around its outward normal h.normal.
  const Eigen::Vector3d normal = h.normal.normalized();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : cap) centre += p;
  centre /= static_cast<double>(cap.size());
  const Eigen::Vector3d u = (Eigen::Vector3d(cap[0]) - centre).normalized();
  const Eigen::Vector3d v = normal.cross(u);
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t a = 0; a < cap.size(); ++a) {
    const Eigen::Vector3d d = Eigen::Vector3d(cap[a]) - centre;
    order.emplace_back(std::atan2(d.dot(v), d.dot(u)), a);
  }
  std::sort(order.begin(), order.end());
  Polygon ordered;
  for (const auto& entry : order) ordered.push_back(cap[entry.second]);
  out.push_back(std::move(ordered));
  return out;
}

PowerCell polygon_cell(const Polygon& polygon) {
  PowerCell cell;
  cell.vertices.resize(static_cast<Eigen::Index>(polygon.size()), 2);
  for (std::size_t a = 0; a < polygon.size(); ++a)
    cell.vertices.row(static_cast<Eigen::Index>(a)) = polygon[a].transpose();
  return cell;
}

// Shared corners merged (within tolerance), each face fanned into triangles.
PowerCell polyhedron_cell(const Polyhedron& polyhedron, double point_tolerance) {
  PowerCell cell;
  Polygon corners;
  std::vector<std::vector<int>> faces;
  for (const auto& face : polyhedron) {
    std::vector<int> indices;
    for (const auto& p : face) {
      int found = -1;
      for (std::size_t c = 0; c < corners.size() && found < 0; ++c)
        if ((corners[c] - p).norm() <= point_tolerance) found = static_cast<int>(c);
      if (found < 0) {
        found = static_cast<int>(corners.size());
        corners.push_back(p);
      }
      if (indices.empty() || indices.back() != found) indices.push_back(found);
    }
    while (indices.size() > 1 && indices.front() == indices.back()) indices.pop_back();
    if (indices.size() >= 3) faces.push_back(std::move(indices));
  }
  cell.vertices.resize(static_cast<Eigen::Index>(corners.size()), 3);
  for (std::size_t c = 0; c < corners.size(); ++c)
    cell.vertices.row(static_cast<Eigen::Index>(c)) = corners[c].transpose();
  std::vector<Eigen::Vector3i> triangles;
  for (const auto& f : faces)
    for (std::size_t a = 1; a + 1 < f.size(); ++a) triangles.emplace_back(f[0], f[a], f[a + 1]);
  cell.faces.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    cell.faces.row(static_cast<Eigen::Index>(t)) = triangles[t].transpose();
  return cell;
}

void check_input(const Eigen::Ref<const Eigen::MatrixXd>& P, const Eigen::VectorXd& weights,
                 const Eigen::VectorXd& bounds) {
  const Eigen::Index d = P.cols();
  if (d != 2 && d != 3)
    throw InputError("power_diagram: P must have 2 or 3 columns, got " + std::to_string(d));
  if (P.rows() == 0) throw InputError("power_diagram: P is empty");
  if (weights.size() != P.rows())
    throw InputError("power_diagram: expected " + std::to_string(P.rows()) + " weights, got " +
                     std::to_string(weights.size()));
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (!P.row(i).allFinite())
      throw InputError("power_diagram: site " + std::to_string(i) + " is not finite");
  for (Eigen::Index i = 0; i < weights.size(); ++i)
    if (!std::isfinite(weights(i)))
      throw InputError("power_diagram: weight " + std::to_string(i) + " is not finite");
  if (bounds.size() != 2 * d)
    throw InputError("power_diagram: bounds must hold " + std::to_string(2 * d) + " numbers, got " +
                     std::to_string(bounds.size()));
  if (!bounds.allFinite()) throw InputError("power_diagram: bounds are not finite");
  const Eigen::Index lower[3] = {0, 1, 4}, upper[3] = {2, 3, 5};
  for (Eigen::Index k = 0; k < d; ++k)
    if (!(bounds(lower[k]) < bounds(upper[k])))
      throw InputError("power_diagram: bounds are empty along axis " + std::to_string(k));
}

}  // namespace

PowerDiagram power_diagram(const Eigen::Ref<const Eigen::MatrixXd>& P,
                           const Eigen::Ref<const Eigen::VectorXd>& weights_in,
                           const Eigen::Ref<const Eigen::VectorXd>& bounds_in) {
  const Eigen::VectorXd weights = weights_in, bounds = bounds_in;
  check_input(P, weights, bounds);
  const Eigen::Index n = P.rows(), d = P.cols();
  const detail::Triangulation t = detail::regular_triangulation(P, weights);

  PowerDiagram result;
  result.triangulation = t.simplices;
  // Power neighbours = edges of the regular triangulation. For degenerate sites (on a line in 2D,
  // in a plane in 3D) the lower-dimensional triangulation's edges still are: the bisecting
  // hyperplanes are orthogonal to that line/plane.
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(n));
  for (const auto& [a, b] : t.edges) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  }

  double box_scale = bounds.cwiseAbs().maxCoeff();
  double box_diagonal = 0.0;
  for (Eigen::Index k = 0; k < d; ++k) {
    const double extent = bounds(k < 2 ? k + 2 : 5) - bounds(k < 2 ? k : 4);
    box_diagonal += extent * extent;
  }
  box_diagonal = std::sqrt(box_diagonal);
  box_scale = std::max(box_scale, box_diagonal);
  const double point_tolerance = 1e-10 * box_diagonal;

  result.cells.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    PowerCell& cell = result.cells[static_cast<std::size_t>(i)];
    if (!t.is_vertex[i]) {
      result.hidden.push_back(static_cast<int>(i));
      cell.vertices.resize(0, d);
      continue;
    }
    if (d == 2) {
      Polygon polygon = box_polygon_2d(bounds);
      for (int j : neighbours[i]) {
        polygon = clip_polygon(polygon, power_half_space(P, weights, i, j, box_scale), nullptr);
        if (polygon.empty()) break;
      }
      polygon = unique_points(polygon, point_tolerance);
      if (polygon.size() < 3) polygon.clear();
      cell = polygon_cell(polygon);
    } else {
      Polyhedron polyhedron = box_polyhedron(bounds);
      for (int j : neighbours[i]) {
        polyhedron = clip_polyhedron(polyhedron, power_half_space(P, weights, i, j, box_scale),
                                     point_tolerance);
        if (polyhedron.empty()) break;
      }
      cell = polyhedron_cell(polyhedron, point_tolerance);
    }
  }
  return result;
}

}  // namespace meshsmith::tessellation
