#include <meshsmith/parametrization/bijectivity.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/topology/edge_incidence.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <cmath>
#include <string>

namespace meshsmith::parametrization {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;
using Segment = Kernel::Segment_2;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, int>;

void check_input(const geometry::ParameterRef& UV, const FaceRef& F) {
  if (F.rows() == 0) throw InputError("is_bijective: F is empty");
  for (Eigen::Index i = 0; i < UV.rows(); ++i) {
    if (!std::isfinite(UV(i, 0)) || !std::isfinite(UV(i, 1))) {
      throw InputError("is_bijective: UV row " + std::to_string(i) + " is not finite");
    }
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (F(f, k) < 0 || F(f, k) >= UV.rows()) {
        throw InputError("is_bijective: face " + std::to_string(f) + " indexes vertex " + std::to_string(F(f, k)) +
                         ", outside [0, " + std::to_string(UV.rows()) + ")");
      }
    }
  }
}

}  // namespace

BijectivityReport check_bijectivity(const geometry::ParameterRef& UV, const FaceRef& F) {
  check_input(UV, F);
  const auto point = [&](int v) { return Point(UV(v, 0), UV(v, 1)); };
  BijectivityReport report;
  std::vector<int> positive, negative;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    switch (CGAL::orientation(point(F(f, 0)), point(F(f, 1)), point(F(f, 2)))) {
      case CGAL::LEFT_TURN: positive.push_back(static_cast<int>(f)); break;
      case CGAL::RIGHT_TURN: negative.push_back(static_cast<int>(f)); break;
      default: report.degenerate_faces.push_back(static_cast<int>(f));
    }
  }
  report.minority_faces = positive.size() >= negative.size() ? negative : positive;
  if (report.degenerate_faces.empty() && report.minority_faces.empty()) report.orientation = negative.empty() ? 1 : -1;

  // Boundary sides: the sides of F that no other face shares.
  const auto incidence = topology::edge_incidence(F, UV.rows());
  std::vector<int> sides;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) == 1) sides.push_back(incidence.edge_sides[incidence.edge_offsets[e]]);
  }
  const auto side_vertex = [&](int side, int end) { return F(side / 3, (side % 3 + end) % 3); };
  std::vector<Box> boxes;
  boxes.reserve(sides.size());
  for (const int side : sides) {
    const int a = side_vertex(side, 0), b = side_vertex(side, 1);
    double lo[2] = {std::min(UV(a, 0), UV(b, 0)), std::min(UV(a, 1), UV(b, 1))};
    double hi[2] = {std::max(UV(a, 0), UV(b, 0)), std::max(UV(a, 1), UV(b, 1))};
    boxes.emplace_back(lo, hi, side);
  }
  constexpr std::size_t max_listed = 100;
  auto test_pair = [&](const Box& first, const Box& second) {
    if (report.crossing_boundary_edges.size() >= max_listed) return;
    const int s = first.info(), t = second.info();
    const int a = side_vertex(s, 0), b = side_vertex(s, 1), c = side_vertex(t, 0), d = side_vertex(t, 1);
    bool crossing;
    if (a == c || a == d || b == c || b == d) {
      // Consecutive edges meet at their shared vertex; they cross only if they fold back onto
      // each other (collinear, the far ends on the same side of the shared vertex) — or if the
      // two edges share both ends (a boundary that doubles back).
      const bool both = (a == c && b == d) || (a == d && b == c);
      const int shared = (a == c || a == d) ? a : b;
      const int p = (shared == a) ? b : a, q = (shared == c) ? d : c;
      crossing = both || (CGAL::collinear(point(p), point(shared), point(q)) &&
                          !CGAL::collinear_are_ordered_along_line(point(p), point(shared), point(q)));
    } else {
      crossing = CGAL::do_intersect(Segment(point(a), point(b)), Segment(point(c), point(d)));
    }
    if (crossing) report.crossing_boundary_edges.emplace_back(std::min(s, t), std::max(s, t));
  };
  // Closed boxes: segments that only touch at an end are paired too (and tested exactly).
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), test_pair, std::ptrdiff_t(10),
                                CGAL::Box_intersection_d::CLOSED);
  std::sort(report.crossing_boundary_edges.begin(), report.crossing_boundary_edges.end());
  report.bijective = report.orientation != 0 && report.boundary_simple();
  return report;
}

bool is_bijective(const geometry::ParameterRef& UV, const FaceRef& F) { return check_bijectivity(UV, F).bijective; }

}  // namespace meshsmith::parametrization
