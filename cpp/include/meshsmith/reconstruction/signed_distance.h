#pragma once
/// \file signed_distance.h
/// Signed distance fields for reconstruction (§2.2, §3.1): to the tangent planes of oriented
/// samples (Hoppe et al. 1992, "Surface reconstruction from unorganized points") and to a
/// triangle mesh, signed by the generalized winding number (Jacobson et al. 2013; evaluated
/// hierarchically as Barill et al. 2018) so that meshes with holes still get a sign.
/// Sign convention (libigl's): negative inside, positive outside.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::reconstruction {

/// Signed distances of the query points Q (#Q×3) to the tangent planes of the samples P (#P×3)
/// with normals N (#P×3, any non-zero length; outward): with k = 1, (q − p)·n̂ for the nearest
/// sample p (Hoppe 1992); with k > 1, the blend Σ w_i (q − p_i)·n̂_i / Σ w_i over the k nearest
/// samples, w_i = exp(−(d_i / d_k)²) (d_i: distance to the i-th neighbour). Returns #Q values.
/// \pre P non-empty and finite, N of P's shape, finite and without a zero row, Q finite,
///      1 <= k <= #P.
/// \throw InputError if a precondition fails (naming the row). \throw Cancelled.
/// O((#P + #Q k) log #P), parallel, thread-count independent.
Eigen::VectorXd tangent_plane_sdf(const VertexRef& P, const VertexRef& N, const VertexRef& Q, int k = 1,
                                  const Progress& progress = {});

/// Generalized winding number of a triangle soup (V, F) at query points, evaluated through a
/// bounding-volume hierarchy: a node far from the query (distance > accuracy · its radius)
/// contributes its first two Taylor terms (the dipole Σ area vectors at the area-weighted
/// centroid, and the first moment), near triangles their
/// exact solid angle (Van Oosterom & Strackee 1983). 1 inside a closed outward mesh, 0 outside,
/// fractional near holes. Built once in O(#F log #F); queries are thread-safe.
class WindingNumber {
 public:
  /// \pre validate_mesh(V, F) passes; accuracy >= 1 (the far-field distance in node radii).
  /// \throw InputError if a precondition fails.
  WindingNumber(const VertexRef& V, const FaceRef& F, double accuracy = 4.0);
  /// Winding number at one point (3 doubles).
  double at(const double* query) const;
  /// Winding numbers at the rows of Q (#Q×3). \throw InputError for a NaN/Inf row. \throw Cancelled.
  Eigen::VectorXd at(const VertexRef& Q, const Progress& progress = {}) const;

 private:
  struct Node {
    double lower[3], upper[3];
    double area[3];    ///< Σ of the triangles' area vectors ½ (b − a) × (c − a)
    double centre[3];  ///< area-weighted centroid
    double moment[9];  ///< Σ_t a_t (c_t − centre)ᵀ, row-major (the second-order term, Barill et al. §3.2)
    double radius;     ///< of the ball around centre holding the node's triangles
    int first, count;  ///< leaf: triangles [first, first + count) in order_; internal: count 0, first = right child
  };
  int build(int begin, int end, std::vector<double>& centroids);
  std::vector<Node> nodes_;
  std::vector<int> order_;
  std::vector<double> corners_;  ///< 9 doubles per triangle, in the order of order_
  double accuracy_;
};

/// Signed distance from query points to a mesh.
struct MeshSignedDistance {
  Eigen::VectorXd distance;  ///< #Q signed distances, negative where winding >= 0.5
  Eigen::VectorXi face;      ///< #Q nearest faces
  VertexMatrix point;        ///< #Q×3 closest points on the surface
  Eigen::VectorXd winding;   ///< #Q generalized winding numbers
};

/// Signed distance of Q (#Q×3) to the triangle mesh (V, F): the exact distance to the surface
/// (geometry::SurfaceDistance, an AABB tree), negative where the generalized winding number is
/// at least 1/2, as libigl's signed_distance with SIGNED_DISTANCE_TYPE_WINDING_NUMBER.
/// \pre validate_mesh(V, F) passes; Q finite (may be empty).
/// \throw InputError if a precondition fails. \throw Cancelled.
/// O(#F log #F + #Q log #F), parallel, thread-count independent.
MeshSignedDistance mesh_sdf(const VertexRef& V, const FaceRef& F, const VertexRef& Q, const Progress& progress = {});

}  // namespace meshsmith::reconstruction
