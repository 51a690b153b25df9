#pragma once
// Internal to the geometry chapter (not installed API): per-triangle corner quantities and the
// vertex → corner incidence shared by normals, Laplacians, mass matrices and curvatures.
//
// Every per-vertex quantity is computed as a gather over the corners around the vertex, in
// face order, so results are parallel (TBB over faces, then over vertices) and yet bitwise
// deterministic whatever the thread count: no vertex is ever written by two threads and every
// sum is taken in the same order.
#include <meshsmith/core/types.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <vector>

namespace meshsmith::geometry::detail {

/// Per-face values for the three corners, row f = (corner 0, corner 1, corner 2).
using CornerMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// Per-face directed edge weights: column 2c is the weight of corner c's vertex towards the
/// next vertex of the face (c+1 mod 3), column 2c+1 towards the previous one (c+2 mod 3).
using DirectedWeights = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

/// Runs body(i) for i in [0, n), in parallel chunks of `grain`.
template <typename Body>
void parallel_for(Eigen::Index n, Body&& body, Eigen::Index grain = 2048) {
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, grain),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index i = range.begin(); i != range.end(); ++i) body(i);
                    });
}

/// The corners (3·face + corner) around every vertex, in increasing face order:
/// corners[offsets[v] .. offsets[v+1]) are the corners c with F(c / 3, c % 3) == v.
struct VertexCorners {
  std::vector<std::int64_t> offsets;  // #V + 1
  std::vector<int> corners;           // 3·#F
  std::int64_t begin(Eigen::Index v) const { return offsets[v]; }
  std::int64_t end(Eigen::Index v) const { return offsets[v + 1]; }
};
/// \pre every index of F is in [0, n).
VertexCorners vertex_corners(const FaceRef& F, Eigen::Index n);

/// The geometry of one triangle that every quantity here derives from.
struct Triangle {
  Eigen::Vector3d p[3];     // corner positions
  Eigen::Vector3d cross;    // (p1 − p0) × (p2 − p0) = 2·area·unit normal
  double double_area;       // |cross|
  double dot[3];            // (p_next − p_c) · (p_prev − p_c) at corner c
  double squared_edge[3];   // |p_prev − p_next|², the edge opposite corner c
  bool degenerate;          // double_area ≤ 8·ε·(longest edge)²: cotangents would blow up
};
Triangle triangle(const VertexRef& V, const FaceRef& F, Eigen::Index f);

/// Interior angle at corner c, atan2(|cross|, dot): accurate for small and large angles alike.
inline double corner_angle(const Triangle& t, int c) { return std::atan2(t.double_area, t.dot[c]); }

/// ½ cot of every corner angle (zero on degenerate triangles). #F×3.
CornerMatrix half_cotangents(const VertexRef& V, const FaceRef& F);
/// Interior angle of every corner (finite for degenerate triangles too). #F×3.
CornerMatrix corner_angles(const VertexRef& V, const FaceRef& F);
/// The part of each triangle's area that goes to each corner: a third (barycentric) or the
/// mixed Voronoi area (Meyer et al. 2003, libigl's rule for obtuse triangles). #F×3.
enum class CornerAreaRule { barycentric, mixed_voronoi };
CornerMatrix corner_areas(const VertexRef& V, const FaceRef& F, CornerAreaRule rule);

/// Σ over the corners around each vertex of values(face, corner), in face order. #V.
Eigen::VectorXd sum_at_vertices(const VertexCorners& corners, const CornerMatrix& values);

/// Laplacian-shaped #V×#V CSC matrix from directed per-face weights: L(i, j) is the sum over
/// the faces with edge ij of the weight of i towards j, L(i, i) = −Σ_j L(i, j). With `weights`
/// null every edge gets weight 1 (whatever the number of faces sharing it): the graph Laplacian.
/// Every column holds its diagonal entry (0 for vertices used by no face); rows are sorted.
Eigen::SparseMatrix<double> assemble_laplacian(const FaceRef& F, const VertexCorners& corners,
                                               const DirectedWeights* weights);

/// \throw InputError unless (V, F) passes validate_mesh and 6·#F + #V fits the matrix indices.
void validate_surface(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::geometry::detail
