#pragma once
/// \file boundary_map.h
/// Fixed boundary maps for harmonic parametrizations (§5: a polygon parametrized by its
/// arc length, t_i proportional to the length walked from p_0; §5.1.1 step 1 "map the boundary
/// polygon in 3D to a convex polygon in 2D").
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>

#include <vector>

namespace meshsmith::parametrization {

/// The convex 2D polygon a boundary loop is mapped onto.
enum class BoundaryShape {
  circle,  ///< the unit circle centred at the origin, starting at (1, 0), counter-clockwise
  square,  ///< the unit square [0, 1]², starting at (0, 0), counter-clockwise; the four loop
           ///< vertices nearest a quarter, half and three quarters of the arc length (and the
           ///< first one) go to the corners, the others are spaced by arc length along the sides
};

/// Boundary vertices and where they go in the plane.
struct BoundaryMap {
  std::vector<int> indices;          ///< #b vertex indices, in loop order
  geometry::ParameterMatrix uv;      ///< #b×2 their parameter positions
};

/// Maps an ordered loop of vertices onto `shape` with arc-length spacing: loop[0] at the start
/// of the shape, consecutive vertices separated in proportion to the 3D length of the edge
/// between them (for the circle, exactly libigl's map_vertices_to_circle).
/// V: #V×3; loop: #b ≥ 3 distinct vertex indices (≥ 4 for the square) in boundary order.
/// \throw InputError if the loop is too short, repeats a vertex, indexes outside V, or has two
/// consecutive vertices at the same position.
BoundaryMap map_boundary_loop(const VertexRef& V, const std::vector<int>& loop,
                              BoundaryShape shape = BoundaryShape::circle);

/// Maps the longest boundary loop of (V, F) (topology::boundary_loops: walked along the faces'
/// orientation, so a counter-clockwise shape keeps the triangles counter-clockwise) onto `shape`.
/// V: #V×3, F: #F×3.
/// \pre (V, F) is a clean, connected, oriented 2-manifold with at least one boundary loop.
/// \throw InputError naming the problem otherwise (closed meshes: cut them with cut_to_disk).
BoundaryMap map_boundary(const VertexRef& V, const FaceRef& F, BoundaryShape shape = BoundaryShape::circle);

}  // namespace meshsmith::parametrization
