#pragma once
/// \file distance.h
/// Exact distances from points to a triangle mesh, accelerated by an axis-aligned bounding box
/// (AABB) tree built once and queried many times, and the distances between two surfaces built
/// on it: the (vertex- or face-sampled) Hausdorff distance and the mean surface distance (used by
/// the curriculum to measure approximation error, e.g. of decimation and remeshing).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace meshsmith::geometry {

/// Result of SurfaceDistance::closest_points for #Q query points.
struct ClosestPoints {
  Eigen::VectorXd distances;  ///< #Q Euclidean distances to the surface
  Eigen::VectorXi faces;      ///< #Q indices of a nearest face (the first found on ties, where
                              ///< the closest point may also differ from another library's)
  VertexMatrix points;        ///< #Q×3 closest points on the surface
};

/// Point-to-surface distance queries on a copy of a triangle mesh (V, F).
///
/// Built once in O(#F log #F): a binary AABB tree over the triangles, split at the median of the
/// centroids along the longest axis. Each query is exact (closest point on each candidate
/// triangle, region by region, Ericson "Real-Time Collision Detection" §5.1.5; degenerate
/// triangles are treated as their edges) and prunes subtrees whose box is farther than the best
/// distance so far. Queries run in parallel (TBB); each result depends only on its query, so
/// results do not depend on the thread count.
class SurfaceDistance {
 public:
  /// V: #V×3 positions, F: #F×3 triangles (both copied). leaf_size: triangles per leaf.
  /// \pre validate_mesh(V, F) passes; leaf_size >= 1; #F / leaf_size < 2^29.
  /// \throw InputError if a precondition fails.
  SurfaceDistance(const VertexRef& V, const FaceRef& F, int leaf_size = 4);

  /// Number of triangles in the tree.
  Eigen::Index face_count() const { return static_cast<Eigen::Index>(face_of_slot_.size()); }

  /// The face indices in the order of the tree's leaves: spatially coherent, so queries made in
  /// this order (e.g. samples of these faces) visit the same nodes one after another.
  const std::vector<int>& faces_in_leaf_order() const { return face_of_slot_; }

  /// Distance, nearest face and closest point for each row of Q (#Q×3, may be empty).
  /// \throw InputError if Q holds a NaN/Inf. \throw Cancelled if progress asks to stop.
  ClosestPoints closest_points(const VertexRef& Q, const Progress& progress = {}) const;

  /// Distances only (#Q), same rules as closest_points.
  Eigen::VectorXd distances(const VertexRef& Q, const Progress& progress = {}) const;

  /// One query, thread-safe: returns the squared distance from `query` to the surface and
  /// writes the nearest face and the closest point (3 doubles).
  double closest_point(const double* query, int& face, double* point) const;

  /// One query that may stop early, thread-safe: returns the exact squared distance from `query`
  /// to the surface when it is greater than `squared_threshold`, otherwise some value
  /// <= squared_threshold (the search stops at the first triangle that close). The maximum of
  /// distances over many queries (Hausdorff) needs only this, and most queries stop early.
  /// `hint`: a slot to try first (-1: none); on return, the slot of the best triangle found (the
  /// next query of a coherent sequence, e.g. samples of one face, starts there and often stops
  /// at once).
  double squared_distance_unless_below(const double* query, double squared_threshold, int& hint) const;

 private:
  struct Node {
    double lower[3], upper[3];
    int first;  ///< internal: index of the right child (the left one is the next node); leaf: first slot
    int count;  ///< 0 for an internal node; number of triangles for a leaf
  };
  /// A triangle's centroid, moved with it while the build partitions (no indirection).
  struct Centroid {
    double position[3];
    int face;
  };
  /// Splits the slots [begin, end) of `items` under node `index`; the subtree occupies the nodes
  /// [index, index + subtree_size(end − begin)) in preorder, so halves are built in parallel.
  void build(int index, int begin, int end, std::vector<Centroid>& items, int leaf_size);
  /// The tree search shared by the queries above: starts from the triangle in slot best_slot when
  /// it is >= 0, stops once the best squared distance is <= stop_below (-1: never), writes the
  /// best slot and closest point.
  double search(const double* query, double stop_below, int& best_slot, double* point) const;
  std::vector<Node> nodes_;
  std::vector<double> corners_;    ///< 9 doubles per slot: the triangle's corners in leaf order
  std::vector<int> face_of_slot_;  ///< face index of each slot
  std::vector<std::uint8_t> flat_; ///< 1 where the slot's triangle has zero area (searched by edges)
};

/// How surfaces are sampled for the distances below.
struct SurfaceSampling {
  /// 0: the vertices only (what libigl's `hausdorff` computes). k > 0: also k points per face,
  /// uniform in the triangle, from a deterministic hash of (seed, face, sample).
  int samples_per_face = 0;
  std::uint64_t seed = 0;
};

/// Distance between surfaces A and B, both one-sided ways and the symmetric value.
struct SurfaceDistances {
  double symmetric = 0.0;  ///< Hausdorff: max(a_to_b, b_to_a); mean: area-weighted combination
  double a_to_b = 0.0;     ///< over samples of A, distance to B
  double b_to_a = 0.0;     ///< over samples of B, distance to A
};

/// Hausdorff distance between the surfaces (VA, FA) and (VB, FB), evaluated at samples:
/// a_to_b = max over the vertices of A (and, with samples_per_face > 0, points on its faces) of
/// the exact distance to the surface B; symmetric = max(a_to_b, b_to_a). With the vertices only
/// this is what libigl's `hausdorff` computes; samples on the faces give a tighter lower bound
/// of the true (continuous) Hausdorff distance. Deterministic.
/// \pre validate_mesh passes for both meshes; samples_per_face >= 0 and #F · samples_per_face
///      is at most 2^27 (a bound on memory) for each mesh.
/// \throw InputError if a precondition fails. \throw Cancelled if progress asks to stop.
SurfaceDistances hausdorff_distance(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB,
                                    const FaceRef& FB, const SurfaceSampling& sampling = {},
                                    const Progress& progress = {});

/// Mean distance between the surfaces, an approximation of (1/|A|) ∫_A d(x, B) dA:
/// with samples_per_face = 0, the vertices of A weighted by their lumped (barycentric) area
/// Σ_{f∋i} A_f / 3; with k > 0, the k samples of each face of A weighted by A_f / k (the
/// vertices are then not used). symmetric = (|A| a_to_b + |B| b_to_a) / (|A| + |B|), the mean
/// over both surfaces together.
/// \pre as hausdorff_distance, and each mesh has positive total area.
/// \throw InputError if a precondition fails. \throw Cancelled if progress asks to stop.
SurfaceDistances mean_surface_distance(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB,
                                       const FaceRef& FB, const SurfaceSampling& sampling = {},
                                       const Progress& progress = {});

/// The sample points of a surface as hausdorff_distance uses them (samples_per_face = 0: V;
/// otherwise V followed by the face samples, face by face in `face_order`, a permutation of
/// 0..#F−1, by default the identity), with their weights for the mean (lumped vertex areas, or
/// 0 for the vertices and A_f / k for face samples when k > 0). The samples of face f do not
/// depend on the order, only where they are placed.
/// \throw InputError as hausdorff_distance, or if face_order is not empty and not of size #F.
std::pair<VertexMatrix, Eigen::VectorXd> surface_samples(const VertexRef& V, const FaceRef& F,
                                                         const SurfaceSampling& sampling,
                                                         const std::vector<int>& face_order = {});

}  // namespace meshsmith::geometry
