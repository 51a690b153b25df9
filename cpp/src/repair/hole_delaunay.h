#pragma once
// The Delaunay search space of hole filling (fill_holes.h; Zou et al. 2013): the faces of the 3D
// Delaunay triangulation of a hole's loop vertices. Internal to the repair chapter; implemented
// apart (hole_delaunay_cgal.cpp) because CGAL compiles with its own floating-point flags.
#include <Eigen/Core>

#include <array>
#include <vector>

namespace meshsmith::repair::detail {

/// The edges (a, b), a < b indices into `points`, of the Delaunay triangulation of the points (in
/// dimension 3, or 2 when they are coplanar). Empty when there is no such triangulation to
/// restrict to: fewer than three points, all collinear, or two that coincide (the triangulation
/// would merge them).
std::vector<std::array<int, 2>> delaunay_loop_edges(const std::vector<Eigen::Vector3d>& points);

}  // namespace meshsmith::repair::detail
