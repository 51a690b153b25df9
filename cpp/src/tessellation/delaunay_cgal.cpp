// CGAL translation unit of the 2D tessellations: Delaunay, constrained Delaunay and the exact
// predicates used by the chapter's own code (flips, Voronoi, refinement_cgal.cpp).
#include "cdt.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/tessellation/delaunay.h>

#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_triangulation_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace meshsmith::tessellation {

namespace {

using detail::Cdt;
using detail::Point;

// --- Delaunay triangulation: vertices carry their input index ---------------------------------
using DelaunayVertex = CGAL::Triangulation_vertex_base_with_info_2<int, detail::Kernel>;
using DelaunayTds =
    CGAL::Triangulation_data_structure_2<DelaunayVertex, CGAL::Triangulation_face_base_2<detail::Kernel>>;
using Delaunay = CGAL::Delaunay_triangulation_2<detail::Kernel, DelaunayTds>;

/// Where two segments cross, CGAL (Exact_predicates_tag) inserts their intersection rounded to
/// double precision, or, when that rounded point is unusable (closer to an endpoint than the
/// rounding can tell), routes the constraint through the nearest endpoint: the segment then
/// bends through a vertex that is not on it, and the mesher walks off the triangulation on such
/// input (a segfault). Every constrained edge between two input vertices must therefore lie on
/// an input segment (exactly, by the orientation predicate); edges at constructed vertices are
/// the usual rounded crossings. O(#E) plus O(#segments) per edge not on a segment at its ends.
/// \throw InputError naming the vertex a segment was bent through.
void check_constraints_follow_segments(const Cdt& cdt, const PointRef2& P, const SegmentRef& segments,
                                       const std::vector<int>& representative) {
  const Eigen::Index n_segments = segments.rows();
  std::vector<std::vector<int>> at_vertex(static_cast<std::size_t>(P.rows()));
  for (Eigen::Index s = 0; s < n_segments; ++s)
    for (int k = 0; k < 2; ++k) at_vertex[representative[segments(s, k)]].push_back(static_cast<int>(s));
  const auto point = [&](int i) { return Point(P(i, 0), P(i, 1)); };
  const auto on_segment = [&](int w, Eigen::Index s) {
    const int a = representative[segments(s, 0)], b = representative[segments(s, 1)];
    if (w == a || w == b) return true;
    return CGAL::orientation(point(a), point(b), point(w)) == CGAL::COLLINEAR &&
           CGAL::collinear_are_ordered_along_line(point(a), point(w), point(b));
  };
  for (auto edge = cdt.finite_edges_begin(); edge != cdt.finite_edges_end(); ++edge) {
    if (!cdt.is_constrained(*edge)) continue;
    const int u = edge->first->vertex(Cdt::cw(edge->second))->info().value;
    const int v = edge->first->vertex(Cdt::ccw(edge->second))->info().value;
    if (u < 0 || v < 0) continue;  // a constructed crossing point
    bool follows = false;
    for (const int w : {u, v})
      for (const int s : at_vertex[w]) follows = follows || (on_segment(u, s) && on_segment(v, s));
    for (Eigen::Index s = 0; s < n_segments && !follows; ++s) follows = on_segment(u, s) && on_segment(v, s);
    if (!follows) {
      throw InputError("segments: two segments cross so close to vertex " + std::to_string(u) + " or " +
                       std::to_string(v) + " that double precision cannot place their intersection (the "
                       "constraint would bend through a vertex that is not on it); move the points apart "
                       "or split the segments there");
    }
  }
}

/// Checks the PSLG, merges duplicate points and builds the CDT. handle_of[i] is the vertex of input point i (duplicates
/// share their representative's); the CDT holds the points multiplied by `scale`, `seeds` the
/// hole seeds multiplied by it.
void build_constrained(const PointRef2& P, const SegmentRef& segments, const PointRef2& holes,
                       Cdt& cdt, std::vector<Cdt::Vertex_handle>& handle_of,
                       std::vector<Point>& seeds, double& scale) {
  detail::require_finite(P, "P");
  detail::require_finite(holes, "holes");
  const int n = static_cast<int>(P.rows());
  for (Eigen::Index s = 0; s < segments.rows(); ++s)
    for (int k = 0; k < 2; ++k)
      if (segments(s, k) < 0 || segments(s, k) >= n)
        throw InputError("segments: row " + std::to_string(s) + " holds index " +
                         std::to_string(segments(s, k)) + ", outside [0, " + std::to_string(n) +
                         ")");
  const std::vector<int> representative = detail::merge_duplicates(P);
  detail::require_three_distinct(representative);
  for (Eigen::Index s = 0; s < segments.rows(); ++s)
    if (representative[segments(s, 0)] == representative[segments(s, 1)])
      throw InputError("segments: row " + std::to_string(s) + " has zero length");

  scale = detail::normalizing_scale(P);
  std::vector<std::pair<Point, detail::VertexInfo>> kept;
  for (int i = 0; i < n; ++i)
    if (representative[i] == i)
      kept.push_back({Point(P(i, 0) * scale, P(i, 1) * scale), detail::VertexInfo{i, -1}});
  cdt.insert(kept.begin(), kept.end());
  if (cdt.dimension() < 2) throw InputError("P: all points are collinear");

  handle_of.assign(n, Cdt::Vertex_handle());
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    handle_of[v->info().value] = v;
  for (int i = 0; i < n; ++i) handle_of[i] = handle_of[representative[i]];
  for (Eigen::Index s = 0; s < segments.rows(); ++s)
    cdt.insert_constraint(handle_of[segments(s, 0)], handle_of[segments(s, 1)]);
  check_constraints_follow_segments(cdt, P, segments, representative);
  if (segments.rows() == 0) {
    // A plain point set: its domain is the convex hull, so the hull edges become the segments.
    std::vector<std::pair<Cdt::Vertex_handle, Cdt::Vertex_handle>> hull;
    auto face = cdt.incident_faces(cdt.infinite_vertex()), done = face;
    do {
      const int i = face->index(cdt.infinite_vertex());
      hull.emplace_back(face->vertex(Cdt::ccw(i)), face->vertex(Cdt::cw(i)));
    } while (++face != done);
    for (const auto& [a, b] : hull) cdt.insert_constraint(a, b);
  }

  seeds.clear();
  for (Eigen::Index h = 0; h < holes.rows(); ++h) seeds.emplace_back(holes(h, 0) * scale, holes(h, 1) * scale);
}

}  // namespace

namespace detail {

double build_domain(const PointRef2& P, const SegmentRef& segments, const PointRef2& holes, Cdt& cdt) {
  std::vector<Cdt::Vertex_handle> handle_of;
  std::vector<Point> seeds;
  double scale = 1;
  build_constrained(P, segments, holes, cdt, handle_of, seeds, scale);
  // Flood fill across non-constrained edges: from the unbounded face and from every hole seed
  // (marked outside), everything else inside.
  CGAL::Delaunay_mesher_2<Cdt, CGAL::Delaunay_mesh_size_criteria_2<Cdt>>::mark_facets(cdt, seeds.begin(), seeds.end(),
                                                                                     false);
  return scale;
}

PlanarMesh extract_domain(const PointRef2& P, Cdt& cdt, double scale) {
  const int n = static_cast<int>(P.rows());
  std::vector<Cdt::Vertex_handle> created;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    if (v->info().value < 0) created.push_back(v);
  PlanarMesh mesh;
  mesh.steiner_count = static_cast<int>(created.size());
  mesh.V.resize(n + mesh.steiner_count, 2);
  mesh.V.topRows(n) = P;
  for (int k = 0; k < mesh.steiner_count; ++k) {
    created[k]->info().value = n + k;  // the mesh is ours: number the new vertices in place
    mesh.V.row(n + k) << created[k]->point().x() / scale, created[k]->point().y() / scale;
  }
  std::vector<Eigen::Vector3i> triangles;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain())
      triangles.emplace_back(f->vertex(0)->info().value, f->vertex(1)->info().value,
                             f->vertex(2)->info().value);
  mesh.F.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t) mesh.F.row(t) = triangles[t].transpose();
  return mesh;
}

int orientation(const double* a, const double* b, const double* c) {
  return static_cast<int>(CGAL::orientation(Point(a[0], a[1]), Point(b[0], b[1]), Point(c[0], c[1])));
}

int side_of_circle(const double* a, const double* b, const double* c, const double* d) {
  return static_cast<int>(CGAL::side_of_oriented_circle(Point(a[0], a[1]), Point(b[0], b[1]),
                                                        Point(c[0], c[1]), Point(d[0], d[1])));
}

}  // namespace detail

DelaunayResult delaunay(const PointRef2& P) {
  detail::require_finite(P, "P");
  const int n = static_cast<int>(P.rows());
  DelaunayResult result;
  const std::vector<int> representative = detail::merge_duplicates(P);
  detail::require_three_distinct(representative);
  result.merged = Eigen::Map<const Eigen::VectorXi>(representative.data(), n);

  std::vector<std::pair<Point, int>> kept;
  kept.reserve(n);
  for (int i = 0; i < n; ++i)
    if (representative[i] == i) kept.emplace_back(Point(P(i, 0), P(i, 1)), i);
  Delaunay triangulation;
  triangulation.insert(kept.begin(), kept.end());  // spatial sort, then hinted insertion
  if (triangulation.dimension() < 2) throw InputError("P: all points are collinear");

  result.F.resize(static_cast<Eigen::Index>(triangulation.number_of_faces()), 3);
  Eigen::Index t = 0;
  for (auto f = triangulation.finite_faces_begin(); f != triangulation.finite_faces_end(); ++f, ++t)
    result.F.row(t) << f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info();
  return result;
}

PlanarMesh constrained_delaunay(const PointRef2& P, const SegmentRef& segments,
                                const PointRef2& holes) {
  Cdt cdt;
  const double scale = detail::build_domain(P, segments, holes, cdt);
  return detail::extract_domain(P, cdt, scale);
}

}  // namespace meshsmith::tessellation
