#include <meshsmith/points/kd_tree.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <meshsmith/core/parallel.h>

#include <nanoflann.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace meshsmith::points {

namespace {

/// nanoflann's dataset interface over the row-major n×3 matrix the tree owns.
struct PointCloudAdaptor {
  const VertexMatrix* points;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(points->rows()); }
  double kdtree_get_pt(std::uint32_t index, std::size_t dim) const {
    return points->data()[3 * static_cast<std::size_t>(index) + dim];
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox&) const { return false; }
};

using NanoflannTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloudAdaptor>,
                                        PointCloudAdaptor, 3, std::uint32_t>;

void check_k(int k, Eigen::Index available, const char* what) {
  if (k < 1 || k > available) {
    throw InputError("k = " + std::to_string(k) + " is outside [1, " + std::to_string(available) +
                     "]: " + what);
  }
}

/// Room for one query's `count` neighbour indices and squared distances: on the stack for the
/// usual small k, on the heap beyond. Not copyable (the pointers address its own arrays).
class NeighborBuffers {
 public:
  explicit NeighborBuffers(int count) {
    if (count > kOnStack) {
      indices_heap_.resize(count);
      distances_heap_.resize(count);
      indices = indices_heap_.data();
      distances = distances_heap_.data();
    }
  }
  NeighborBuffers(const NeighborBuffers&) = delete;
  NeighborBuffers& operator=(const NeighborBuffers&) = delete;

 private:
  static constexpr int kOnStack = 65;
  std::uint32_t indices_stack_[kOnStack];
  double distances_stack_[kOnStack];
  std::vector<std::uint32_t> indices_heap_;
  std::vector<double> distances_heap_;

 public:
  std::uint32_t* indices = indices_stack_;
  double* distances = distances_stack_;
};

}  // namespace

struct KdTree::Impl {
  VertexMatrix points;
  PointCloudAdaptor adaptor;
  std::unique_ptr<NanoflannTree> tree;
};

KdTree::KdTree(const VertexRef& P, int leaf_size) : impl_(std::make_unique<Impl>()) {
  validate_vertices(P, "P");
  if (leaf_size < 1) throw InputError("leaf_size = " + std::to_string(leaf_size) + " must be >= 1");
  if (P.rows() >= static_cast<Eigen::Index>(std::numeric_limits<std::uint32_t>::max())) {
    throw InputError("P has " + std::to_string(P.rows()) + " points: at most 2^32 - 2 supported");
  }
  impl_->points = P;
  impl_->adaptor.points = &impl_->points;
  impl_->tree = std::make_unique<NanoflannTree>(
      3, impl_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(static_cast<std::size_t>(leaf_size)));
}

KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

int KdTree::nearest(const double* query, int k, std::uint32_t* indices,
                    double* squared_distances) const {
  return static_cast<int>(impl_->tree->knnSearch(query, static_cast<std::size_t>(k), indices,
                                                 squared_distances));
}

void KdTree::within_radius(const double* query, double squared_radius,
                           std::vector<std::pair<std::uint32_t, double>>& matches) const {
  impl_->tree->radiusSearch(query, squared_radius, matches, nanoflann::SearchParams(32, 0.0f, true));
}

const std::vector<std::uint32_t>& KdTree::leaf_order() const { return impl_->tree->vAcc; }

Eigen::Index KdTree::size() const { return impl_->points.rows(); }
const VertexMatrix& KdTree::points() const { return impl_->points; }

KnnResult KdTree::query(const VertexRef& Q, int k, const Progress& progress) const {
  validate_vertices(Q, "Q");
  check_k(k, size(), "k must be at least 1 and at most the number of points P");
  const Eigen::Index m = Q.rows();
  KnnResult result{NeighborIndexMatrix(m, k), NeighborDistanceMatrix(m, k)};
  parallel_for_with_progress(m, progress, "knn", [&](Eigen::Index q) {
    NeighborBuffers found(k);
    const double point[3] = {Q(q, 0), Q(q, 1), Q(q, 2)};
    nearest(point, k, found.indices, found.distances);
    for (int j = 0; j < k; ++j) {
      result.indices(q, j) = found.indices[j];
      result.distances(q, j) = std::sqrt(found.distances[j]);
    }
  });
  return result;
}

KnnResult KdTree::query_self(int k, const Progress& progress) const {
  check_k(k, size() - 1, "k must be at least 1 and less than the number of points (each "
                         "point's own index is excluded)");
  const Eigen::Index n = size();
  KnnResult result{NeighborIndexMatrix(n, k), NeighborDistanceMatrix(n, k)};
  const VertexMatrix& points = impl_->points;
  const int wanted = k + 1;
  // Queries in the tree's leaf order: consecutive queries touch the same nodes (cache).
  const auto& order = leaf_order();
  parallel_for_with_progress(n, progress, "knn", [&](Eigen::Index t) {
    const std::uint32_t i = order[static_cast<std::size_t>(t)];
    NeighborBuffers found(wanted);
    nearest(points.row(i).data(), wanted, found.indices, found.distances);
    // Drop i itself; if more than k duplicates of i hide it, drop the farthest instead.
    int out = 0;
    for (int j = 0; j < wanted && out < k; ++j) {
      if (found.indices[j] == i) continue;
      result.indices(i, out) = found.indices[j];
      result.distances(i, out) = std::sqrt(found.distances[j]);
      ++out;
    }
  });
  return result;
}

RadiusResult KdTree::query_radius(const VertexRef& Q, double radius, const Progress& progress) const {
  validate_vertices(Q, "Q");
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw InputError("radius = " + std::to_string(radius) + " must be positive and finite");
  }
  const Eigen::Index m = Q.rows();
  std::vector<std::vector<std::pair<std::uint32_t, double>>> per_query(static_cast<std::size_t>(m));
  const double squared_radius = radius * radius;
  parallel_for_with_progress(m, progress, "radius search", [&](Eigen::Index q) {
    const double point[3] = {Q(q, 0), Q(q, 1), Q(q, 2)};
    within_radius(point, squared_radius, per_query[static_cast<std::size_t>(q)]);
  });
  RadiusResult result;
  result.offsets.resize(static_cast<std::size_t>(m) + 1, 0);
  for (std::size_t q = 0; q < per_query.size(); ++q)
    result.offsets[q + 1] = result.offsets[q] + static_cast<std::int64_t>(per_query[q].size());
  result.indices.reserve(static_cast<std::size_t>(result.offsets.back()));
  result.distances.reserve(static_cast<std::size_t>(result.offsets.back()));
  for (auto& matches : per_query) {
    for (const auto& [index, squared] : matches) {
      result.indices.push_back(index);
      result.distances.push_back(std::sqrt(squared));
    }
    std::vector<std::pair<std::uint32_t, double>>().swap(matches);
  }
  return result;
}

KnnResult knn(const VertexRef& P, int k, const Progress& progress) {
  validate_vertices(P, "P");
  if (k < 1 || k >= P.rows()) {
    throw InputError("k = " + std::to_string(k) + " needs at least k + 1 = " + std::to_string(k + 1) +
                     " points (each point's own index is excluded), P has " +
                     std::to_string(P.rows()));
  }
  return KdTree(P).query_self(k, progress);
}

KnnResult knn(const VertexRef& P, const VertexRef& Q, int k, const Progress& progress) {
  validate_vertices(P, "P");
  validate_vertices(Q, "Q");
  if (k < 1 || k > P.rows()) {
    throw InputError("k = " + std::to_string(k) + " is outside [1, " + std::to_string(P.rows()) +
                     "]: k cannot exceed the number of points in P");
  }
  return KdTree(P).query(Q, k, progress);
}

}  // namespace meshsmith::points
