// Voronoi diagram as the dual of the Delaunay triangulation (curriculum §2.1.1), with each cell
// clipped to a box by the bisectors of the site's Delaunay neighbours.
#include "edge_faces.h"
#include "planar_detail.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/tessellation/delaunay.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace meshsmith::tessellation {

namespace {

using Point2 = Eigen::Vector2d;

Point2 circumcentre(const Point2& a, const Point2& b, const Point2& c) {
  const Point2 ab = b - a, ac = c - a;
  const double d = 2 * (ab.x() * ac.y() - ab.y() * ac.x());
  const double ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm();
  return a + Point2(ac.y() * ab2 - ab.y() * ac2, ab.x() * ac2 - ac.x() * ab2) / d;
}

/// Sutherland-Hodgman step: the part of the convex polygon where (x - m)·normal <= 0.
std::vector<Point2> clip(const std::vector<Point2>& polygon, const Point2& m, const Point2& normal) {
  std::vector<Point2> out;
  const std::size_t k = polygon.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Point2& s = polygon[i];
    const Point2& e = polygon[(i + 1) % k];
    const double ds = (s - m).dot(normal), de = (e - m).dot(normal);
    if (ds <= 0) out.push_back(s);
    if ((ds < 0 && de > 0) || (ds > 0 && de < 0)) out.push_back(s + (e - s) * (ds / (ds - de)));
  }
  return out;
}

}  // namespace

VoronoiDiagram voronoi(const PointRef2& P, const Eigen::Vector4d& bounds) {
  if (!bounds.allFinite() || !(bounds[0] < bounds[2]) || !(bounds[1] < bounds[3]))
    throw InputError("bounds: need finite xmin < xmax and ymin < ymax");
  VoronoiDiagram diagram;
  diagram.delaunay = delaunay(P);
  const FaceMatrix& F = diagram.delaunay.F;
  const Eigen::VectorXi& representative = diagram.delaunay.merged;
  const int n = static_cast<int>(P.rows());
  // Constructions run on exactly rescaled sites (no overflow / underflow of squared lengths).
  const double scale = detail::normalizing_scale(P);
  auto site = [&](int i) { return Point2(P(i, 0) * scale, P(i, 1) * scale); };

  diagram.vertices.resize(F.rows(), 2);
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    diagram.vertices.row(t) =
        circumcentre(site(F(t, 0)), site(F(t, 1)), site(F(t, 2))).transpose() / scale;
    if (!diagram.vertices.row(t).allFinite())
      throw InputError("voronoi: the Voronoi vertex of Delaunay triangle " + std::to_string(t) + " (sites " +
                       std::to_string(F(t, 0)) + ", " + std::to_string(F(t, 1)) + ", " + std::to_string(F(t, 2)) +
                       ") lies beyond the double range: its sites are nearly collinear at the scale of the "
                       "whole set (one site far from the rest?)");
  }

  // One Voronoi edge per Delaunay edge: a segment between the circumcentres of its two
  // triangles, or (convex-hull edge) a ray from its triangle's circumcentre, pointing outwards.
  const detail::EdgeFaces edges = detail::build_edge_faces(F);
  std::vector<std::vector<int>> neighbours(n);
  diagram.edges.resize(static_cast<Eigen::Index>(edges.size()), 2);
  diagram.directions.setZero(static_cast<Eigen::Index>(edges.size()), 2);
  diagram.edge_sites.resize(static_cast<Eigen::Index>(edges.size()), 2);
  Eigen::Index e = 0;
  for (const auto& [key, sides] : edges) {
    const int p = static_cast<int>(key >> 32), q = static_cast<int>(key & 0xffffffffu);
    neighbours[p].push_back(q);
    neighbours[q].push_back(p);
    diagram.edge_sites.row(e) << p, q;
    diagram.edges.row(e) << sides[0], sides[1];
    if (sides[1] < 0) {
      // Orient p → q as in the CCW triangle; the outside is then on the right.
      const int f = sides[0];
      int from = p, to = q;
      for (int c = 0; c < 3; ++c)
        if (F(f, c) == q && F(f, (c + 1) % 3) == p) std::swap(from, to);
      const Point2 along = site(to) - site(from);
      diagram.directions.row(e) = Point2(along.y(), -along.x()).normalized().transpose();
    }
    ++e;
  }

  const Eigen::Vector4d box_bounds = bounds * scale;
  if (!box_bounds.allFinite())
    throw InputError("bounds: too large relative to the points' coordinates");
  const std::vector<Point2> box = {{box_bounds[0], box_bounds[1]}, {box_bounds[2], box_bounds[1]},
                                   {box_bounds[2], box_bounds[3]}, {box_bounds[0], box_bounds[3]}};
  diagram.cells.resize(n);
  for (int i = 0; i < n; ++i) {
    if (representative[i] != i) continue;
    std::vector<Point2> cell = box;
    for (int j : neighbours[i]) {
      if (cell.empty()) break;
      cell = clip(cell, (site(i) + site(j)) / 2, site(j) - site(i));
    }
    diagram.cells[i].resize(static_cast<Eigen::Index>(cell.size()), 2);
    for (std::size_t k = 0; k < cell.size(); ++k)
      diagram.cells[i].row(k) = cell[k].transpose() / scale;
  }
  for (int i = 0; i < n; ++i)
    if (representative[i] != i) diagram.cells[i] = diagram.cells[representative[i]];
  return diagram;
}

}  // namespace meshsmith::tessellation
