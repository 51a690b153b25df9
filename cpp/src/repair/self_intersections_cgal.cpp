// Self-intersecting face pairs (self_intersections.h): candidate pairs from CGAL's box
// intersection (the faces' axis-aligned bounding boxes, closed, so touching boxes pair too), each
// decided in parallel by how many vertices the two faces share. Boxes rather than the triangles
// themselves select the candidates: the faces around a vertex touch exactly there, and deciding
// that contact with a triangle–triangle predicate falls through every floating-point filter to
// exact arithmetic, which made an AABB tree of triangles 30 times slower on 70k faces.
#include <meshsmith/core/parallel.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/repair/self_intersections.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

namespace meshsmith::repair {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Segment = Kernel::Segment_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;

/// Whether faces a and b (corner indices ia, ib; their triangles ta, tb) meet other than along
/// what they share.
bool meet_improperly(const std::array<int, 3>& ia, const std::array<int, 3>& ib, const Triangle& ta,
                     const Triangle& tb) {
  int shared = 0, a_at[3], b_at[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (ia[i] == ib[j]) {
        a_at[shared] = i;
        b_at[shared] = j;
        ++shared;
      }
  if (shared == 3) return true;                  // a duplicate face
  if (shared == 0) return CGAL::do_intersect(ta, tb);
  if (shared == 2) {
    // Common edge (p, q): they overlap only folded flat onto each other, the third corners on the
    // same side of the edge in the common plane.
    const int r = 3 - a_at[0] - a_at[1], s = 3 - b_at[0] - b_at[1];
    const Point& p = ta[a_at[0]];
    const Point& q = ta[a_at[1]];
    return CGAL::coplanar(p, q, ta[r], tb[s]) && CGAL::coplanar_orientation(p, q, ta[r], tb[s]) == CGAL::POSITIVE;
  }
  // One common vertex: they meet elsewhere iff the opposite edge of one meets the other triangle.
  const Segment opposite_a(ta[(a_at[0] + 1) % 3], ta[(a_at[0] + 2) % 3]);
  const Segment opposite_b(tb[(b_at[0] + 1) % 3], tb[(b_at[0] + 2) % 3]);
  return CGAL::do_intersect(opposite_b, ta) || CGAL::do_intersect(opposite_a, tb);
}

}  // namespace

EdgeMatrix self_intersections(const VertexRef& V, const FaceRef& F, const Progress& progress) {
  validate_mesh(V, F);
  std::vector<Triangle> triangles;
  std::vector<int> face_of;
  triangles.reserve(F.rows());
  face_of.reserve(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Point a(V(F(f, 0), 0), V(F(f, 0), 1), V(F(f, 0), 2));
    const Point b(V(F(f, 1), 0), V(F(f, 1), 1), V(F(f, 1), 2));
    const Point c(V(F(f, 2), 0), V(F(f, 2), 1), V(F(f, 2), 2));
    if (CGAL::collinear(a, b, c)) continue;
    triangles.emplace_back(a, b, c);
    face_of.push_back(static_cast<int>(f));
  }
  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto box = triangles[t].bbox();
    double lo[3] = {box.xmin(), box.ymin(), box.zmin()}, hi[3] = {box.xmax(), box.ymax(), box.zmax()};
    boxes.emplace_back(lo, hi, static_cast<int>(t));
  }
  std::vector<std::pair<int, int>> candidates;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    candidates.emplace_back(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
  }, std::ptrdiff_t(10), CGAL::Box_intersection_d::CLOSED);
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> meets(candidates.size(), 0);
  parallel_for_with_progress(static_cast<Eigen::Index>(candidates.size()), progress, "self-intersections",
                             [&](Eigen::Index k) {
    const auto [t, u] = candidates[k];
    const int f = face_of[t], g = face_of[u];
    meets[k] = meet_improperly({F(f, 0), F(f, 1), F(f, 2)}, {F(g, 0), F(g, 1), F(g, 2)}, triangles[t], triangles[u]);
  });
  std::size_t count = 0;
  for (const char m : meets) count += m;
  EdgeMatrix pairs(static_cast<Eigen::Index>(count), 2);
  Eigen::Index row = 0;
  for (std::size_t k = 0; k < candidates.size(); ++k)
    if (meets[k]) pairs.row(row++) << face_of[candidates[k].first], face_of[candidates[k].second];
  return pairs;
}

}  // namespace meshsmith::repair
