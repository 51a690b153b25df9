#pragma once
/// \file kd_tree.h
/// k-nearest-neighbour and radius queries on 3D point sets (the neighbourhoods of §2.2 step 1,
/// normal estimation). A kd-tree (nanoflann) is built once and queried many times; queries run
/// in parallel (TBB) and their results do not depend on the thread count.
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace meshsmith::points {

/// #Q by k neighbour indices (rows of the tree's points), nearest first.
using NeighborIndexMatrix =
    Eigen::Matrix<std::int64_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// #Q by k Euclidean distances matching a NeighborIndexMatrix.
using NeighborDistanceMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Result of a k-nearest-neighbour query.
struct KnnResult {
  NeighborIndexMatrix indices;       ///< #Q×k, row i: the k nearest points to query i, nearest first
  NeighborDistanceMatrix distances;  ///< #Q×k Euclidean distances, non-decreasing along each row
};

/// Result of a radius query in compressed-row form: the neighbours of query i are
/// indices[offsets[i] .. offsets[i+1]), nearest first, with their distances.
struct RadiusResult {
  std::vector<std::int64_t> offsets;  ///< #Q+1 entries, offsets[0] = 0
  std::vector<std::int64_t> indices;  ///< offsets[#Q] point indices
  std::vector<double> distances;      ///< offsets[#Q] Euclidean distances
};

/// A kd-tree over a copy of n points in 3D: build once (O(n log n)), query many times.
///
/// The index is built on the points in normalized coordinates (core/normalization.h), so
/// coordinates anywhere in the double range (1e-300 to 1e308) give the same neighbours as at
/// scale 1, and distances are mapped back exactly. Coincident or nearly coincident points cost
/// O(n log n) to build and O(log n + k) per query, like any others (a subtree is searched only
/// if it may hold a point strictly closer than the current k-th).
///
/// Ties: points at exactly the same distance from a query come in an unspecified (but
/// deterministic) order, so with ties the k-th neighbour may differ from another library's
/// while the distances agree.
class KdTree {
 public:
  /// P: n×3 point positions (copied). leaf_size: points per leaf (nanoflann's leaf_max_size).
  /// \throw InputError if P is empty, holds a NaN/Inf, or leaf_size < 1.
  explicit KdTree(const VertexRef& P, int leaf_size = 10);
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;

  /// Number of points in the tree.
  Eigen::Index size() const;
  /// The points the tree was built on (n×3).
  const VertexMatrix& points() const;

  /// For each row of Q (m×3), its k nearest tree points.
  /// \throw InputError if Q holds a NaN/Inf, k < 1 or k > size(), or a distance exceeds the
  /// double range (a query near +1.8e308 and a point near −1.8e308).
  KnnResult query(const VertexRef& Q, int k, const Progress& progress = {}) const;

  /// For each tree point i, its k nearest *other* tree points: i itself is never listed (a
  /// duplicate of i at distance 0 is listed, it is another point).
  /// \throw InputError if k < 1 or k >= size().
  KnnResult query_self(int k, const Progress& progress = {}) const;

  /// For each row of Q (m×3), all tree points at distance < radius (strictly), nearest first.
  /// \throw InputError if Q holds a NaN/Inf or radius is not positive and finite.
  RadiusResult query_radius(const VertexRef& Q, double radius, const Progress& progress = {}) const;

  /// The points in the tree's normalized frame (n×3, in (−1, 1)), and that frame.
  const VertexMatrix& normalized_points() const;
  const CoordinateFrame& frame() const;

  /// Single-query primitives for callers that run their own (parallel) loops; thread-safe.
  /// They work in the tree's normalized frame: `query` is a normalized point (frame().
  /// normalize_point), squared distances and radii are in normalized units.
  /// nearest: the min(k, size()) nearest points to `query` (3 doubles) into `indices` and
  /// `squared_distances` (room for k each), nearest first; returns how many were written.
  /// squared_bound: only points at squared distance < squared_bound count (fewer than k may then
  /// be written; every other point is at least that far); a caller that knows k points within
  /// some distance passes it, and the search prunes from the first node on.
  int nearest(const double* query, int k, std::uint32_t* indices, double* squared_distances,
              double squared_bound = std::numeric_limits<double>::infinity()) const;
  /// nearest_within: the single nearest point to `query` among those at squared distance <
  /// squared_bound (+inf: no bound), into `index` and `squared_distance`; returns false (and
  /// leaves them unchanged) when no point is that close. A specialised 1-NN search (no result
  /// buffer, no sort) whose bound prunes the tree from the start, like a ball search that stops
  /// at the first ring: callers that know a nearby point (ICP's previous partner) pass its
  /// distance. Among points at the same distance the result is the same as nearest(query, 1).
  bool nearest_within(const double* query, double squared_bound, std::uint32_t& index,
                      double& squared_distance) const;
  /// within_radius: the points at squared distance < squared_radius, nearest first (`matches`
  /// is cleared first; pairs of index and squared distance).
  void within_radius(const double* query, double squared_radius,
                     std::vector<std::pair<std::uint32_t, double>>& matches) const;
  /// The tree's point indices in leaf order: processing queries at the tree's own points in this
  /// order keeps consecutive searches in the same nodes (cache-friendly).
  const std::vector<std::uint32_t>& leaf_order() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// kNN of P in itself, excluding each point's own index (see KdTree::query_self).
/// \throw InputError as KdTree and KdTree::query_self.
KnnResult knn(const VertexRef& P, int k, const Progress& progress = {});

/// kNN in P of each row of Q (see KdTree::query).
/// \throw InputError as KdTree and KdTree::query.
KnnResult knn(const VertexRef& P, const VertexRef& Q, int k, const Progress& progress = {});

}  // namespace meshsmith::points
