// CGAL translation unit of the 2D tessellations: Delaunay, constrained Delaunay, Delaunay
// refinement and the exact predicates used by the chapter's own code (flips, Voronoi).
#include "planar_detail.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/tessellation/delaunay.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace meshsmith::tessellation {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;

// --- Delaunay triangulation: vertices carry their input index ---------------------------------
using DelaunayVertex = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using DelaunayTds =
    CGAL::Triangulation_data_structure_2<DelaunayVertex, CGAL::Triangulation_face_base_2<Kernel>>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, DelaunayTds>;

// --- Constrained Delaunay triangulation usable by the mesher ----------------------------------
/// Input index of a vertex; -1 for vertices CGAL creates (intersections, Steiner points).
struct InputIndex {
  int value = -1;
};
using CdtVertex = CGAL::Triangulation_vertex_base_with_info_2<InputIndex, Kernel,
                                                              CGAL::Delaunay_mesh_vertex_base_2<Kernel>>;
using CdtFace = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using CdtTds = CGAL::Triangulation_data_structure_2<CdtVertex, CdtFace>;
// Exact_predicates_tag: crossing constraints are split at intersection points constructed in
// double precision, while every predicate stays exact.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, CdtTds, CGAL::Exact_predicates_tag>;

/// A corner of the domain where two input segments meet at less than 60°: its apex and the
/// unit directions of the two segments (points scaled as in the CDT).
struct SmallAngleApex {
  double x, y;
  double u[2][2];
};

/// Mesh quality: a triangle is bad when the squared sine of its smallest angle is below B, and
/// imperatively bad (split first) when its area exceeds max_area (> 0). Same Quality ordering as
/// CGAL's Delaunay_mesh_size_criteria_2 (big triangles first, then the worst angles).
///
/// Small input angles (Shewchuk 2002, "Delaunay refinement algorithms for triangular mesh
/// generation", §5; Triangle's rule): a skinny triangle whose shortest edge joins two points on
/// the two segments of one small-angle apex, equally far from it, is left alone whatever its angle. Its small angle is
/// forced by the input (the segments are that close there); splitting it only makes a smaller
/// copy nearer the apex, and with a bound above ~20° that can go on until the Steiner cap.
class AngleAreaCriteria {
 public:
  using Quality = CGAL::Delaunay_mesh_size_criteria_2<Cdt>::Quality;

  AngleAreaCriteria(double squared_sine_bound, double max_area, const std::vector<SmallAngleApex>* apexes)
      : squared_sine_bound_(squared_sine_bound), max_area_(max_area), apexes_(apexes) {}

  class Is_bad {
   public:
    Is_bad(double squared_sine_bound, double max_area, const std::vector<SmallAngleApex>* apexes)
        : squared_sine_bound_(squared_sine_bound), max_area_(max_area), apexes_(apexes) {}

    CGAL::Mesh_2::Face_badness operator()(const Quality& q) const {
      if (q.size() > 1) return CGAL::Mesh_2::IMPERATIVELY_BAD;
      return q.sine() < squared_sine_bound_ ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }

    CGAL::Mesh_2::Face_badness operator()(const Cdt::Face_handle& face, Quality& q) const {
      const Point& a = face->vertex(0)->point();
      const Point& b = face->vertex(1)->point();
      const Point& c = face->vertex(2)->point();
      const double area = CGAL::area(a, b, c);
      const double ab = CGAL::squared_distance(a, b);
      const double bc = CGAL::squared_distance(b, c);
      const double ca = CGAL::squared_distance(c, a);
      // The smallest angle is opposite the shortest edge: sin² = (2·area)² / (product of the
      // two longer squared edge lengths).
      const double shortest = std::min({ab, bc, ca});
      const double longer_product = ab * bc * ca / shortest;
      q.second = max_area_ > 0 ? area / max_area_ : 0;
      q.first = 4 * area * area / longer_product;
      const CGAL::Mesh_2::Face_badness badness = (*this)(q);
      if (badness != CGAL::Mesh_2::BAD || apexes_->empty()) return badness;
      const Point& p = shortest == ab ? a : shortest == bc ? b : c;
      const Point& r = shortest == ab ? b : shortest == bc ? c : a;
      for (const SmallAngleApex& apex : *apexes_)
        if (((on_ray(p, apex, 0) && on_ray(r, apex, 1)) || (on_ray(p, apex, 1) && on_ray(r, apex, 0))) &&
            on_one_shell(p, r, apex)) {
          q.first = squared_sine_bound_;  // ranks as acceptable
          return CGAL::Mesh_2::NOT_BAD;
        }
      return badness;
    }

   private:
    /// Whether `point` lies on segment `side` of `apex` (the apex itself counts), up to the
    /// rounding of constructed points (relative 1e-12 of the distance to the apex).
    static bool on_ray(const Point& point, const SmallAngleApex& apex, int side) {
      const double dx = point.x() - apex.x, dy = point.y() - apex.y;
      if (dx == 0 && dy == 0) return true;
      const double along = dx * apex.u[side][0] + dy * apex.u[side][1];
      const double across = dx * apex.u[side][1] - dy * apex.u[side][0];
      return along > 0 && std::abs(across) <= 1e-12 * along;
    }

    /// Whether p and r are equally far from the apex (within 0.1%, Triangle's tolerance): the
    /// points concentric-shell splitting puts on the two segments. Elsewhere along the segments
    /// the triangles are split as usual.
    static bool on_one_shell(const Point& p, const Point& r, const SmallAngleApex& apex) {
      const double dp = std::hypot(p.x() - apex.x, p.y() - apex.y), dr = std::hypot(r.x() - apex.x, r.y() - apex.y);
      return dp < 1.001 * dr && dr < 1.001 * dp;
    }

    double squared_sine_bound_;
    double max_area_;
    const std::vector<SmallAngleApex>* apexes_;
  };

  Is_bad is_bad_object() const { return Is_bad(squared_sine_bound_, max_area_, apexes_); }

 private:
  double squared_sine_bound_;
  double max_area_;
  const std::vector<SmallAngleApex>* apexes_;
};

using Mesher = CGAL::Delaunay_mesher_2<Cdt, AngleAreaCriteria>;

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

/// Checks the PSLG arguments, merges duplicate points and builds the CDT with its constraints.
/// handle_of[i] is the vertex of input point i (duplicates share their representative's).
/// The CDT holds the points multiplied by `scale` (detail::normalizing_scale).
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
  std::vector<std::pair<Point, InputIndex>> kept;
  for (int i = 0; i < n; ++i)
    if (representative[i] == i)
      kept.push_back({Point(P(i, 0) * scale, P(i, 1) * scale), InputIndex{i}});
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

/// The corners where two constrained edges of the CDT (input segments, or their pieces) meet at
/// an input vertex at less than 60°.
std::vector<SmallAngleApex> small_angle_apexes(const Cdt& cdt) {
  std::vector<SmallAngleApex> apexes;
  const double cos60 = 0.5;
  std::vector<std::pair<double, std::array<double, 2>>> directions;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    directions.clear();
    auto edge = cdt.incident_edges(v), done = edge;
    if (edge == nullptr) continue;
    do {
      if (cdt.is_infinite(*edge) || !cdt.is_constrained(*edge)) continue;
      const auto other = edge->first->vertex(Cdt::cw(edge->second)) == Cdt::Vertex_handle(v)
                             ? edge->first->vertex(Cdt::ccw(edge->second))
                             : edge->first->vertex(Cdt::cw(edge->second));
      const double dx = other->point().x() - v->point().x(), dy = other->point().y() - v->point().y();
      const double length = std::hypot(dx, dy);
      if (length > 0) directions.push_back({std::atan2(dy, dx), {dx / length, dy / length}});
    } while (++edge != done);
    if (directions.size() < 2) continue;
    std::sort(directions.begin(), directions.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const auto& d0 = directions[i].second;
      const auto& d1 = directions[(i + 1) % directions.size()].second;
      if (d0[0] * d1[0] + d0[1] * d1[1] > cos60)
        apexes.push_back({v->point().x(), v->point().y(), {{d0[0], d0[1]}, {d1[0], d1[1]}}});
    }
  }
  return apexes;
}

/// Input points first (unchanged), then every vertex CGAL created; triangles in the domain.
PlanarMesh extract_domain(const PointRef2& P, const Cdt& cdt, double scale) {
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

}  // namespace

namespace detail {

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
  std::vector<Cdt::Vertex_handle> handle_of;
  std::vector<Point> seeds;
  double scale = 1;
  build_constrained(P, segments, holes, cdt, handle_of, seeds, scale);
  // Flood fill across non-constrained edges: from the unbounded face and from every hole seed
  // (marked outside), everything else inside.
  Mesher::mark_facets(cdt, seeds.begin(), seeds.end(), false);
  return extract_domain(P, cdt, scale);
}

PlanarMesh refine(const PointRef2& P, const SegmentRef& segments, const PointRef2& holes,
                  const RefineOptions& options, const Progress& progress) {
  if (!(options.min_angle_degrees > 0 && options.min_angle_degrees < 35))
    throw InputError("min_angle: must be in (0, 35) degrees, got " +
                     std::to_string(options.min_angle_degrees));
  if (!(options.max_area >= 0) || !std::isfinite(options.max_area))
    throw InputError("max_area: must be a finite number >= 0, got " +
                     std::to_string(options.max_area));
  if (options.max_steiner_points < 0)
    throw InputError("max_steiner_points: must be >= 0");
  Cdt cdt;
  std::vector<Cdt::Vertex_handle> handle_of;
  std::vector<Point> seeds;
  double scale = 1;
  build_constrained(P, segments, holes, cdt, handle_of, seeds, scale);
  const double sine = std::sin(options.min_angle_degrees * M_PI / 180.0);
  const std::vector<SmallAngleApex> apexes = small_angle_apexes(cdt);
  Mesher mesher(cdt, AngleAreaCriteria(sine * sine, options.max_area * scale * scale, &apexes));
  mesher.set_seeds(seeds.begin(), seeds.end(), false);
  mesher.init();
  const std::size_t limit = cdt.number_of_vertices() + static_cast<std::size_t>(options.max_steiner_points);
  // Termination whatever the input: at most max_steiner_points insertions, and a step that
  // inserts nothing (a circumcentre rounded onto an existing vertex next to a tiny feature)
  // may repeat only so often before the refinement counts as stuck.
  constexpr std::size_t kMaxIdleSteps = 100000;
  std::size_t steps = 0, idle = 0, vertices = cdt.number_of_vertices();
  while (!mesher.is_refinement_done()) {
    mesher.step_by_step_refine_mesh();
    if (cdt.number_of_vertices() > limit)
      throw SolverError("refine: more than max_steiner_points = " +
                        std::to_string(options.max_steiner_points) +
                        " Steiner points needed; raise the limit, lower min_angle or raise max_area");
    idle = cdt.number_of_vertices() > vertices ? 0 : idle + 1;
    vertices = cdt.number_of_vertices();
    if (idle > kMaxIdleSteps)
      throw SolverError("refine: no progress in " + std::to_string(kMaxIdleSteps) +
                        " refinement steps (a feature too small for double precision); lower min_angle");
    if (++steps % 4096 == 0) progress.report(0.0, "refine");
  }
  progress.report(1.0, "refine");
  return extract_domain(P, cdt, scale);
}

}  // namespace meshsmith::tessellation
