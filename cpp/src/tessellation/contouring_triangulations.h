#pragma once
// Private to the contouring part of the tessellation chapter: the CGAL triangulations that the
// power diagram and Voronoi filtering build on, behind plain Eigen types (CGAL types never leave
// contouring_triangulations_cgal.cpp). Indices refer to the rows of the input point matrix.
#include <meshsmith/core/progress.h>

#include <Eigen/Core>

#include <utility>
#include <vector>

namespace meshsmith::tessellation::detail {

using SimplexMatrix = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Simplices of a triangulation of n points in d = 2 or 3 dimensions.
struct Triangulation {
  SimplexMatrix simplices;        ///< #S×(d+1) finite triangles (CCW in 2D) or tetrahedra (positive)
  int dimension = -1;             ///< dimension of the triangulation (< d for degenerate input)
  std::vector<bool> is_vertex;    ///< n flags: point i is a vertex of the triangulation
  /// Finite edges, in every dimension >= 1 (on a line / in a plane for degenerate input).
  std::vector<std::pair<int, int>> edges;
};

/// Regular (weighted Delaunay) triangulation of the rows of P (n×2 or n×3), weights = squared
/// radii: CGAL Regular_triangulation_2 / Regular_triangulation_3 with exact predicates. Points
/// hidden by their neighbours' weights are not vertices (is_vertex false).
Triangulation regular_triangulation(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                    const Eigen::Ref<const Eigen::VectorXd>& weights);

/// Delaunay triangulation of the rows of P (n×2 or n×3): CGAL Delaunay_triangulation_2 / _3.
/// Of coincident points only one is a vertex (is_vertex false for the others). In 3D the points
/// are spatially sorted, then inserted one by one (each located from the previous one), reporting
/// the inserted fraction to `progress` as stage "delaunay". \throw Cancelled from progress.
Triangulation delaunay_triangulation(const Eigen::Ref<const Eigen::MatrixXd>& P,
                                     const Progress& progress = {});

}  // namespace meshsmith::tessellation::detail
