// CGAL translation unit (compiled with CGAL's flags): the regular and Delaunay triangulations
// behind power_diagram.cpp and voronoi_filtering.cpp, returned as plain index matrices.
#include "contouring_triangulations.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Regular_triangulation_2.h>
#include <CGAL/Regular_triangulation_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

namespace meshsmith::tessellation::detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Vertex bases carry the input row index as `info`.
using RegularVertex2 = CGAL::Triangulation_vertex_base_with_info_2<
    int, Kernel, CGAL::Regular_triangulation_vertex_base_2<Kernel>>;
using RegularFace2 = CGAL::Regular_triangulation_face_base_2<Kernel>;
using Regular2 = CGAL::Regular_triangulation_2<
    Kernel, CGAL::Triangulation_data_structure_2<RegularVertex2, RegularFace2>>;

using RegularVertex3 = CGAL::Triangulation_vertex_base_with_info_3<
    int, Kernel, CGAL::Regular_triangulation_vertex_base_3<Kernel>>;
using RegularCell3 = CGAL::Regular_triangulation_cell_base_3<Kernel>;
using Regular3 = CGAL::Regular_triangulation_3<
    Kernel, CGAL::Triangulation_data_structure_3<RegularVertex3, RegularCell3>>;

using Delaunay2 = CGAL::Delaunay_triangulation_2<
    Kernel, CGAL::Triangulation_data_structure_2<
                CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>>>;
using Delaunay3 = CGAL::Delaunay_triangulation_3<
    Kernel, CGAL::Triangulation_data_structure_3<
                CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>>>;

// Which of the n input points are vertices of t (duplicates and hidden weighted points are not).
template <typename AnyTriangulation>
std::vector<bool> vertex_flags(const AnyTriangulation& t, Eigen::Index n) {
  std::vector<bool> flags(static_cast<std::size_t>(n), false);
  for (auto v = t.finite_vertices_begin(); v != t.finite_vertices_end(); ++v)
    flags[static_cast<std::size_t>(v->info())] = true;
  return flags;
}

// CGAL's range constructors insert in a spatial order drawn from its global random state, so
// the iteration order of edges and simplices differs between two calls on the same input. Sorted
// here (edges as (low, high); each simplex turned by an even permutation so its smallest index
// comes first, orientation kept; rows in lexicographic order), results do not depend on it.
void canonical_order(Triangulation& result) {
  for (auto& [a, b] : result.edges)
    if (b < a) std::swap(a, b);
  std::sort(result.edges.begin(), result.edges.end());
  SimplexMatrix& S = result.simplices;
  const Eigen::Index corners = S.cols();
  for (Eigen::Index r = 0; r < S.rows(); ++r) {
    Eigen::Index first = 0;
    S.row(r).minCoeff(&first);
    if (corners == 3) {
      const int a = S(r, first), b = S(r, (first + 1) % 3), c = S(r, (first + 2) % 3);  // a rotation
      S(r, 0) = a, S(r, 1) = b, S(r, 2) = c;
    } else if (first != 0) {
      // Swap the smallest into place, then swap the two corners other than 0 and `first`.
      std::swap(S(r, 0), S(r, first));
      const Eigen::Index u = first == 1 ? 2 : 1, v = first == 3 ? 2 : 3;
      std::swap(S(r, u), S(r, v));
    }
  }
  std::vector<Eigen::Index> order(static_cast<std::size_t>(S.rows()));
  std::iota(order.begin(), order.end(), Eigen::Index(0));
  std::sort(order.begin(), order.end(), [&](Eigen::Index x, Eigen::Index y) {
    for (Eigen::Index k = 0; k < corners; ++k)
      if (S(x, k) != S(y, k)) return S(x, k) < S(y, k);
    return false;
  });
  SimplexMatrix sorted(S.rows(), corners);
  for (std::size_t r = 0; r < order.size(); ++r) sorted.row(static_cast<Eigen::Index>(r)) = S.row(order[r]);
  S = std::move(sorted);
}

// Collects the finite simplices and the vertex flags of a 2D triangulation.
template <typename Triangulation2>
Triangulation collect_2d(const Triangulation2& t, Eigen::Index n) {
  Triangulation result;
  result.dimension = t.dimension();
  result.is_vertex = vertex_flags(t, n);
  for (auto e = t.finite_edges_begin(); e != t.finite_edges_end(); ++e)
    result.edges.emplace_back(e->first->vertex(t.cw(e->second))->info(),
                              e->first->vertex(t.ccw(e->second))->info());
  if (t.dimension() < 2) {
    canonical_order(result);
    return result;
  }
  result.simplices.resize(static_cast<Eigen::Index>(t.number_of_faces()), 3);
  Eigen::Index row = 0;
  for (auto f = t.finite_faces_begin(); f != t.finite_faces_end(); ++f, ++row)
    for (int k = 0; k < 3; ++k) result.simplices(row, k) = f->vertex(k)->info();
  result.simplices.conservativeResize(row, 3);
  canonical_order(result);
  return result;
}

template <typename Triangulation3>
Triangulation collect_3d(const Triangulation3& t, Eigen::Index n) {
  Triangulation result;
  result.dimension = t.dimension();
  result.is_vertex = vertex_flags(t, n);
  for (auto e = t.finite_edges_begin(); e != t.finite_edges_end(); ++e)
    result.edges.emplace_back(e->first->vertex(e->second)->info(), e->first->vertex(e->third)->info());
  if (t.dimension() < 3) {
    canonical_order(result);
    return result;
  }
  result.simplices.resize(static_cast<Eigen::Index>(t.number_of_finite_cells()), 4);
  Eigen::Index row = 0;
  for (auto c = t.finite_cells_begin(); c != t.finite_cells_end(); ++c, ++row)
    for (int k = 0; k < 4; ++k) result.simplices(row, k) = c->vertex(k)->info();
  result.simplices.conservativeResize(row, 4);
  canonical_order(result);
  return result;
}

}  // namespace

Triangulation regular_triangulation(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                    const Eigen::Ref<const Eigen::VectorXd>& weights) {
  const Eigen::Index n = P.rows();
  if (P.cols() == 2) {
    std::vector<std::pair<Regular2::Weighted_point, int>> points;
    points.reserve(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i)
      points.emplace_back(Regular2::Weighted_point(Kernel::Point_2(P(i, 0), P(i, 1)), weights(i)),
                          static_cast<int>(i));
    Regular2 t(points.begin(), points.end());
    return collect_2d(t, n);
  }
  std::vector<std::pair<Regular3::Weighted_point, int>> points;
  points.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    points.emplace_back(
        Regular3::Weighted_point(Kernel::Point_3(P(i, 0), P(i, 1), P(i, 2)), weights(i)),
        static_cast<int>(i));
  Regular3 t(points.begin(), points.end());
  return collect_3d(t, n);
}

Triangulation delaunay_triangulation(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                     const Progress& progress) {
  const Eigen::Index n = P.rows();
  if (P.cols() == 2) {
    std::vector<std::pair<Kernel::Point_2, int>> points;
    points.reserve(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i)
      points.emplace_back(Kernel::Point_2(P(i, 0), P(i, 1)), static_cast<int>(i));
    Delaunay2 t(points.begin(), points.end());
    return collect_2d(t, n);
  }
  std::vector<std::pair<Kernel::Point_3, int>> points;
  points.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i)
    points.emplace_back(Kernel::Point_3(P(i, 0), P(i, 1), P(i, 2)), static_cast<int>(i));
  // What the range constructor does (spatial sort, then insertion located from the last vertex),
  // spelled out so that progress can be reported between insertions.
  using PointFirst = CGAL::First_of_pair_property_map<std::pair<Kernel::Point_3, int>>;
  CGAL::spatial_sort(points.begin(), points.end(),
                     CGAL::Spatial_sort_traits_adapter_3<Kernel, PointFirst>(PointFirst()));
  Delaunay3 t;
  Delaunay3::Cell_handle hint;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::size_t before = t.number_of_vertices();
    const Delaunay3::Vertex_handle v = t.insert(points[i].first, hint);
    if (t.number_of_vertices() > before) v->info() = points[i].second;  // else a duplicate
    hint = v->cell();
    if (i % 4096 == 0) progress.report(static_cast<double>(i) / static_cast<double>(points.size()), "delaunay");
  }
  return collect_3d(t, n);
}

}  // namespace meshsmith::tessellation::detail
