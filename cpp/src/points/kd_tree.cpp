#include <meshsmith/points/kd_tree.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>

#include <meshsmith/core/parallel.h>

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
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

/// nanoflann's k-nearest result set with one change: once full, a subtree is pruned unless it
/// may hold a point *strictly* closer than the current k-th (nanoflann's own set also descends
/// into subtrees at exactly that distance). With many coincident points every subtree is at
/// distance 0 and nanoflann's test visits them all: O(n) per query, O(n²) for a self query of a
/// million equal points. A leaf point is taken when it is strictly closer than the worst kept
/// one as before; the only points given up are ties with the current k-th and those closer by
/// one unit in the last place of the squared distance (below its rounding error).
class StrictKnnResultSet {
 public:
  using DistanceType = double;
  StrictKnnResultSet(std::size_t capacity, std::uint32_t* indices, double* distances,
                     double bound = std::numeric_limits<double>::max())
      : indices_(indices), distances_(distances), capacity_(capacity), bound_(bound) {
    distances_[capacity_ - 1] = std::numeric_limits<double>::max();
  }
  std::size_t size() const { return count_; }
  bool full() const { return count_ == capacity_; }
  bool addPoint(double distance, std::uint32_t index) {
    std::size_t i = count_;
    for (; i > 0 && distances_[i - 1] > distance; --i) {
      if (i < capacity_) {
        distances_[i] = distances_[i - 1];
        indices_[i] = indices_[i - 1];
      }
    }
    if (i < capacity_) {
      distances_[i] = distance;
      indices_[i] = index;
    }
    if (count_ < capacity_) ++count_;
    // The bound changes only here (nanoflann asks for it at every node it visits).
    if (count_ == capacity_) bound_ = just_below(distances_[capacity_ - 1]);
    return true;
  }
  double worstDist() const { return bound_; }

  /// The largest double below d >= 0 (d's bits minus one; any negative number below 0): what
  /// std::nextafter(d, -inf) gives, without the library call on every insertion.
  static double just_below(double d) {
    if (!(d > 0.0)) return -1.0;
    std::uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    --bits;
    std::memcpy(&d, &bits, sizeof bits);
    return d;
  }

 private:
  std::uint32_t* indices_;
  double* distances_;
  std::size_t capacity_;
  std::size_t count_ = 0;
  double bound_;
};

/// The single nearest point below a squared-distance bound (KdTree::nearest_within): the bound
/// shrinks to just below each point taken, so subtrees at exactly the best distance are pruned
/// (as in StrictKnnResultSet) and the first point in the search's order among equals is kept.
class NearestBelowResultSet {
 public:
  using DistanceType = double;
  explicit NearestBelowResultSet(double bound) : bound_(bound) {}
  std::size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return found_; }
  bool addPoint(double distance, std::uint32_t index) {
    if (distance < bound_ && !(found_ && distance >= best_)) {
      best_ = distance, index_ = index, found_ = true;
      bound_ = StrictKnnResultSet::just_below(distance);
    }
    return true;
  }
  double worstDist() const { return bound_; }
  double best() const { return best_; }
  std::uint32_t index() const { return index_; }

 private:
  double bound_;
  double best_ = std::numeric_limits<double>::infinity();
  std::uint32_t index_ = 0;
  bool found_ = false;
};

/// Normalized coordinates of a query point, its distance from the origin capped at about 2^27
/// (same direction) so squared distances to the tree's points, which lie in (−1, 1), cannot
/// overflow. The cap also keeps the ranking: from a query at distance R the squared distances
/// R² − 2R·x + |p|² resolve differences of x down to R·2^-52 only, so beyond 2^27 the points
/// furthest along the query's direction are found more reliably from the capped point than
/// from the true one. Returns false when the cap applied (the distances must then be measured
/// in input coordinates, see input_distance).
bool normalized_query(const CoordinateFrame& frame, const double* input, double* query) {
  frame.normalize_point(input, query);
  const double largest = std::max({std::abs(query[0]), std::abs(query[1]), std::abs(query[2])});
  if (largest <= 0x1p27) return true;
  // The same direction from the origin (inside the points' box), at distance about 2^27.
  int e = 0;
  std::frexp(std::max({std::abs(input[0]), std::abs(input[1]), std::abs(input[2])}), &e);
  for (int j = 0; j < 3; ++j) query[j] = std::ldexp(input[j], 27 - e);
  return false;
}

/// |a − b| for two input points without intermediate overflow (halved, then std::hypot).
double input_distance(const double* a, const double* b) {
  return 2.0 * std::hypot(0.5 * a[0] - 0.5 * b[0], 0.5 * a[1] - 0.5 * b[1], 0.5 * a[2] - 0.5 * b[2]);
}

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
  VertexMatrix points;      // as given
  CoordinateFrame frame;    // points -> normalized
  VertexMatrix normalized;  // what the index is built on
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
  impl_->frame = normalizing_frame(P);
  impl_->normalized = impl_->frame.normalize_vertices(P);
  impl_->adaptor.points = &impl_->normalized;
  impl_->tree = std::make_unique<NanoflannTree>(
      3, impl_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(static_cast<std::size_t>(leaf_size)));
}

KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

int KdTree::nearest(const double* query, int k, std::uint32_t* indices,
                    double* squared_distances, double squared_bound) const {
  const std::size_t wanted = std::min(static_cast<std::size_t>(k), static_cast<std::size_t>(size()));
  if (wanted == 0 || !(squared_bound > 0.0)) return 0;
  StrictKnnResultSet found(wanted, indices, squared_distances, std::min(squared_bound, std::numeric_limits<double>::max()));
  impl_->tree->findNeighbors(found, query, nanoflann::SearchParams());
  return static_cast<int>(found.size());
}

bool KdTree::nearest_within(const double* query, double squared_bound, std::uint32_t& index,
                            double& squared_distance) const {
  if (size() == 0 || !(squared_bound > 0.0)) return false;
  NearestBelowResultSet found(std::min(squared_bound, std::numeric_limits<double>::max()));
  impl_->tree->findNeighbors(found, query, nanoflann::SearchParams());
  if (!found.full()) return false;
  index = found.index(), squared_distance = found.best();
  return true;
}

void KdTree::within_radius(const double* query, double squared_radius,
                           std::vector<std::pair<std::uint32_t, double>>& matches) const {
  impl_->tree->radiusSearch(query, squared_radius, matches, nanoflann::SearchParams(32, 0.0f, true));
}

const std::vector<std::uint32_t>& KdTree::leaf_order() const { return impl_->tree->vAcc; }

Eigen::Index KdTree::size() const { return impl_->points.rows(); }
const VertexMatrix& KdTree::points() const { return impl_->points; }
const VertexMatrix& KdTree::normalized_points() const { return impl_->normalized; }
const CoordinateFrame& KdTree::frame() const { return impl_->frame; }

KnnResult KdTree::query(const VertexRef& Q, int k, const Progress& progress) const {
  validate_vertices(Q, "Q");
  check_k(k, size(), "k must be at least 1 and at most the number of points P");
  const Eigen::Index m = Q.rows();
  KnnResult result{NeighborIndexMatrix(m, k), NeighborDistanceMatrix(m, k)};
  const CoordinateFrame& frame = impl_->frame;
  parallel_for_with_progress(m, progress, "knn", [&](Eigen::Index q) {
    NeighborBuffers found(k);
    const double input[3] = {Q(q, 0), Q(q, 1), Q(q, 2)};
    double point[3];
    const bool exact = normalized_query(frame, input, point);
    const int count = nearest(point, k, found.indices, found.distances);
    if (count != k) throw SolverError("knn: the kd-tree search found " + std::to_string(count) + " of k = " +
                                      std::to_string(k) + " neighbours of query " + std::to_string(q));
    for (int j = 0; j < k; ++j) {
      result.indices(q, j) = found.indices[j];
      result.distances(q, j) =
          exact ? frame.to_input(std::sqrt(found.distances[j]), 1, "knn: a distance")
                : input_distance(input, impl_->points.row(found.indices[j]).data());
      if (!std::isfinite(result.distances(q, j)))
        throw InputError("knn: the distance from query " + std::to_string(q) + " to point " +
                         std::to_string(found.indices[j]) + " exceeds the double range");
    }
  });
  return result;
}

KnnResult KdTree::query_self(int k, const Progress& progress) const {
  check_k(k, size() - 1, "k must be at least 1 and less than the number of points (each "
                         "point's own index is excluded)");
  const Eigen::Index n = size();
  KnnResult result{NeighborIndexMatrix(n, k), NeighborDistanceMatrix(n, k)};
  const VertexMatrix& points = impl_->normalized;
  const CoordinateFrame& frame = impl_->frame;
  const int wanted = k + 1;
  // Queries in the tree's leaf order: consecutive queries touch the same nodes (cache).
  const auto& order = leaf_order();
  parallel_for_with_progress(n, progress, "knn", [&](Eigen::Index t) {
    const std::uint32_t i = order[static_cast<std::size_t>(t)];
    NeighborBuffers found(wanted);
    const int count = nearest(points.row(i).data(), wanted, found.indices, found.distances);
    // Drop i itself; if more than k duplicates of i hide it, drop the farthest instead.
    int out = 0;
    for (int j = 0; j < count && out < k; ++j) {
      if (found.indices[j] == i) continue;
      result.indices(i, out) = found.indices[j];
      result.distances(i, out) = frame.to_input(std::sqrt(found.distances[j]), 1, "knn: a distance");
      ++out;
    }
    if (out != k) throw SolverError("knn: the kd-tree search found " + std::to_string(out) + " of k = " +
                                    std::to_string(k) + " neighbours of point " + std::to_string(i));
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
  const CoordinateFrame& frame = impl_->frame;
  const double normalized_radius = frame.to_normalized(radius, 1);
  // A radius beyond 2^29 normalized units holds every point of a query that is not capped.
  const double squared_radius = std::min(normalized_radius, 0x1p29) * std::min(normalized_radius, 0x1p29);
  parallel_for_with_progress(m, progress, "radius search", [&](Eigen::Index q) {
    const double input[3] = {Q(q, 0), Q(q, 1), Q(q, 2)};
    double point[3];
    auto& matches = per_query[static_cast<std::size_t>(q)];
    if (normalized_query(frame, input, point)) {
      within_radius(point, squared_radius, matches);
      for (auto& match : matches) match.second = frame.to_input(std::sqrt(match.second), 1, "radius search: a distance");
    } else {  // a query 2^27 times farther than the points' extent: measure in input units
      matches.clear();
      for (Eigen::Index i = 0; i < size(); ++i) {
        const double distance = input_distance(input, impl_->points.row(i).data());
        if (distance < radius) matches.emplace_back(static_cast<std::uint32_t>(i), distance);
      }
      std::stable_sort(matches.begin(), matches.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    }
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
      result.distances.push_back(squared);  // already a distance in input units
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
