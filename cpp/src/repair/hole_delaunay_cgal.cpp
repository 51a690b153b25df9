// The Delaunay search space of hole filling (hole_delaunay.h) with CGAL's Delaunay_triangulation_3.
#include "hole_delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <utility>

namespace meshsmith::repair::detail {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<int, Kernel>;
using CellBase = CGAL::Delaunay_triangulation_cell_base_3<Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;
}  // namespace

std::vector<std::array<int, 2>> delaunay_loop_edges(const std::vector<Eigen::Vector3d>& points) {
  std::vector<std::array<int, 2>> edges;
  if (points.size() < 3) return edges;
  std::vector<std::pair<Kernel::Point_3, int>> sites;
  sites.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    sites.emplace_back(Kernel::Point_3(points[i].x(), points[i].y(), points[i].z()), static_cast<int>(i));
  const Delaunay delaunay(sites.begin(), sites.end());
  if (delaunay.number_of_vertices() != points.size() || delaunay.dimension() < 2) return edges;
  edges.reserve(8 * points.size());
  for (auto edge = delaunay.finite_edges_begin(); edge != delaunay.finite_edges_end(); ++edge) {
    const int a = edge->first->vertex(edge->second)->info(), b = edge->first->vertex(edge->third)->info();
    edges.push_back({std::min(a, b), std::max(a, b)});
  }
  return edges;
}

}  // namespace meshsmith::repair::detail
