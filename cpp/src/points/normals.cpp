#include <meshsmith/points/normals.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <meshsmith/core/parallel.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <sstream>
#include <string>
#include <vector>

namespace meshsmith::points {

namespace {

/// Unit normal and surface variation of the points `neighbors` (count >= 1) of `points`.
/// `degenerate_trace`: covariance traces at or below it mean "all points coincide".
void fit_plane(const VertexMatrix& points, const std::uint32_t* neighbors, int count,
               double degenerate_trace, double* normal, double* variation) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int j = 0; j < count; ++j) centroid += points.row(neighbors[j]).transpose();
  centroid /= static_cast<double>(count);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int j = 0; j < count; ++j) {
    const Eigen::Vector3d d = points.row(neighbors[j]).transpose() - centroid;
    covariance.noalias() += d * d.transpose();
  }
  if (!(covariance.trace() > degenerate_trace)) {
    normal[0] = 0.0, normal[1] = 0.0, normal[2] = 1.0;
    *variation = 1.0 / 3.0;
    return;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  Eigen::Vector3d eigenvalues = solver.eigenvalues();
  Eigen::Vector3d smallest = solver.eigenvectors().col(0);
  // The closed form loses accuracy when the two smallest eigenvalues are close relative to the
  // largest (thin or nearly isotropic neighbourhoods). The angle between the computed and the
  // true eigenvector is at most residual / (λ1 − λ0); where that bound exceeds 1e-10 rad, solve
  // again with the iterative (tridiagonal QR) solver, which is accurate to round-off.
  const double residual = (covariance * smallest - eigenvalues(0) * smallest).norm();
  const double gap = eigenvalues(1) - eigenvalues(0);
  if (!smallest.allFinite() || !(residual <= 1e-10 * gap) ||
      !(std::abs(smallest.norm() - 1.0) <= 1e-12)) {
    solver.compute(covariance);
    eigenvalues = solver.eigenvalues();
    smallest = solver.eigenvectors().col(0);
  }
  smallest.normalize();
  normal[0] = smallest(0), normal[1] = smallest(1), normal[2] = smallest(2);
  const Eigen::Vector3d clamped = eigenvalues.cwiseMax(0.0);
  *variation = clamped(0) / clamped.sum();
}

/// Length scale below which a neighbourhood counts as a single point: the bounding-box
/// diagonal, or (for a cloud of identical points) the size of the coordinates, whose rounding
/// in the centroid leaves a covariance of order (1e-16 |p|)^2.
double degeneracy_scale(const VertexMatrix& points) {
  const double diagonal = (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
  return std::max(diagonal, 1e-2 * points.cwiseAbs().maxCoeff());
}

}  // namespace

NormalEstimate estimate_normals(const KdTree& tree, const NormalEstimationOptions& options,
                                const Progress& progress) {
  // Plane fits are scale-invariant: everything runs on the tree's normalized points.
  const VertexMatrix& points = tree.normalized_points();
  const Eigen::Index n = points.rows();
  const bool use_radius = options.radius != 0.0;
  if (use_radius) {
    if (!(options.radius > 0.0) || !std::isfinite(options.radius)) {
      throw InputError("radius = " + std::to_string(options.radius) +
                       " must be positive and finite (or 0 to use k nearest neighbours)");
    }
    if (n < 3) {
      throw InputError("P has " + std::to_string(n) + " points: a normal needs at least 3");
    }
  } else {
    if (options.k < 3) {
      throw InputError("k = " + std::to_string(options.k) +
                       ": normal estimation needs k >= 3 neighbours");
    }
    if (n <= options.k) {
      throw InputError("P has " + std::to_string(n) + " points: k = " + std::to_string(options.k) +
                       " neighbours need at least k + 1 = " + std::to_string(options.k + 1));
    }
  }
  const double scale = degeneracy_scale(points);
  const double degenerate_trace = (1e-12 * scale) * (1e-12 * scale);
  NormalEstimate result{VertexMatrix(n, 3), Eigen::VectorXd(n)};
  const auto& order = tree.leaf_order();
  const int wanted = options.k + 1;
  const double normalized_radius = std::min(tree.frame().to_normalized(options.radius, 1), 4.0);  // 4 > the diameter
  const double squared_radius = normalized_radius * normalized_radius;
  parallel_for_with_progress(n, progress, "estimate normals", [&](Eigen::Index t) {
    const std::uint32_t i = order[static_cast<std::size_t>(t)];
    const double* point = points.row(i).data();
    std::uint32_t buffer[65];
    double squared[65];
    thread_local std::vector<std::uint32_t> heap_indices;
    thread_local std::vector<double> heap_squared;
    thread_local std::vector<std::pair<std::uint32_t, double>> matches;
    std::uint32_t* indices = buffer;
    double* distances = squared;
    int count = 0;
    if (use_radius) {
      tree.within_radius(point, squared_radius, matches);
      count = static_cast<int>(matches.size());
      if (count < 3) {
        count = tree.nearest(point, 3, indices, distances);
      } else {
        heap_indices.resize(matches.size());
        for (std::size_t j = 0; j < matches.size(); ++j) heap_indices[j] = matches[j].first;
        indices = heap_indices.data();
      }
    } else {
      if (wanted > 65) {
        heap_indices.resize(wanted);
        heap_squared.resize(wanted);
        indices = heap_indices.data();
        distances = heap_squared.data();
      }
      count = tree.nearest(point, wanted, indices, distances);
    }
    fit_plane(points, indices, count, degenerate_trace, result.normals.row(i).data(),
              &result.surface_variation(i));
  });
  return result;
}

NormalEstimate estimate_normals(const VertexRef& P, const NormalEstimationOptions& options,
                                const Progress& progress) {
  const KdTree tree(P);  // validates P
  return estimate_normals(tree, options, progress);
}

namespace {

/// Symmetrised kNN graph in compressed-row form (no self loops, no repeated edges).
struct NeighborGraph {
  std::vector<std::int64_t> offsets;
  std::vector<std::uint32_t> targets;
};

NeighborGraph symmetric_knn_graph(const NeighborIndexMatrix& neighbors) {
  const Eigen::Index n = neighbors.rows();
  const Eigen::Index k = neighbors.cols();
  std::vector<std::int64_t> degree(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < k; ++j) {
      ++degree[static_cast<std::size_t>(i) + 1];
      ++degree[static_cast<std::size_t>(neighbors(i, j)) + 1];
    }
  }
  for (std::size_t i = 1; i < degree.size(); ++i) degree[i] += degree[i - 1];
  std::vector<std::uint32_t> all(static_cast<std::size_t>(degree.back()));
  std::vector<std::int64_t> fill(degree.begin(), degree.end() - 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < k; ++j) {
      const auto other = static_cast<std::uint32_t>(neighbors(i, j));
      all[static_cast<std::size_t>(fill[static_cast<std::size_t>(i)]++)] = other;
      all[static_cast<std::size_t>(fill[other]++)] = static_cast<std::uint32_t>(i);
    }
  }
  NeighborGraph graph;
  graph.offsets.assign(static_cast<std::size_t>(n) + 1, 0);
  graph.targets.reserve(all.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    auto begin = all.begin() + degree[static_cast<std::size_t>(i)];
    auto end = all.begin() + degree[static_cast<std::size_t>(i) + 1];
    std::sort(begin, end);
    end = std::unique(begin, end);
    for (auto it = begin; it != end; ++it)
      if (*it != static_cast<std::uint32_t>(i)) graph.targets.push_back(*it);
    graph.offsets[static_cast<std::size_t>(i) + 1] = static_cast<std::int64_t>(graph.targets.size());
  }
  return graph;
}

}  // namespace

VertexMatrix orient_normals(const VertexRef& P, const VertexRef& N,
                            const NormalOrientationOptions& options, const Progress& progress) {
  validate_vertices(P, "P");
  validate_vertices(N, "N");
  const Eigen::Index n = P.rows();
  if (N.rows() != n) {
    throw InputError("N has " + std::to_string(N.rows()) + " rows but P has " + std::to_string(n) +
                     ": one normal per point expected");
  }
  if (options.axis < 0 || options.axis > 2) {
    throw InputError("axis = " + std::to_string(options.axis) + " must be 0, 1 or 2 (x, y, z)");
  }
  if (!(options.alpha >= 0.0) || !(options.beta >= 0.0) || !(options.alpha + options.beta > 0.0) ||
      !std::isfinite(options.alpha + options.beta)) {
    std::ostringstream message;
    message << "alpha = " << options.alpha << ", beta = " << options.beta
            << ": both must be finite and >= 0, not both 0";
    throw InputError(message.str());
  }
  if (options.k < 1 || n <= options.k) {
    throw InputError("k = " + std::to_string(options.k) + " with " + std::to_string(n) +
                     " points: need 1 <= k < number of points");
  }
  VertexMatrix unit(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double length = N.row(i).norm();
    if (!(length > 0.0)) {
      throw InputError("N[" + std::to_string(i) + "] is the zero vector: normals must be nonzero");
    }
    unit.row(i) = N.row(i) / length;
  }

  const KdTree tree(P);
  const KnnResult neighbors = tree.query_self(options.k, progress.subrange(0.0, 0.4));
  const NeighborGraph graph = symmetric_knn_graph(neighbors.indices);
  const Progress propagation = progress.subrange(0.4, 1.0);
  propagation.report(0.0, "orient normals: components");
  double scale = neighbors.distances.mean();
  if (!(scale > 0.0)) scale = 1.0;  // every point duplicated k+1 times: distance term is 0 anyway
  const double alpha = options.alpha / scale;
  const double beta = options.beta;
  auto cost = [&](std::uint32_t i, std::uint32_t j) {
    const double distance = (P.row(i) - P.row(j)).norm();
    return alpha * distance + beta * (1.0 - std::abs(unit.row(i).dot(unit.row(j))));
  };

  // Seeds: the point with the largest coordinate along `axis` in each connected component,
  // visited in order of their lowest index (components found by a traversal of the graph).
  std::vector<std::int64_t> component(static_cast<std::size_t>(n), -1);
  std::vector<std::uint32_t> seeds;
  std::vector<std::uint32_t> stack;
  for (Eigen::Index start = 0; start < n; ++start) {
    if (component[static_cast<std::size_t>(start)] >= 0) continue;
    propagation.report(0.0, "orient normals: components");
    const auto label = static_cast<std::int64_t>(seeds.size());
    std::uint32_t best = static_cast<std::uint32_t>(start);
    stack.assign(1, static_cast<std::uint32_t>(start));
    component[static_cast<std::size_t>(start)] = label;
    while (!stack.empty()) {
      const std::uint32_t v = stack.back();
      stack.pop_back();
      if (P(v, options.axis) > P(best, options.axis) ||
          (P(v, options.axis) == P(best, options.axis) && v < best))
        best = v;
      for (auto e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e) {
        const std::uint32_t w = graph.targets[static_cast<std::size_t>(e)];
        if (component[w] < 0) {
          component[w] = label;
          stack.push_back(w);
        }
      }
    }
    seeds.push_back(best);
  }

  // Prim's algorithm from each seed; a vertex joins the tree through its cheapest edge to the
  // tree and takes the orientation that agrees with the vertex it joined through.
  VertexMatrix oriented = N;
  std::vector<char> in_tree(static_cast<std::size_t>(n), 0);
  // Cheapest known edge to the tree per vertex: only improvements are queued, which keeps the
  // lazy-deletion heap small.
  std::vector<double> best_cost(static_cast<std::size_t>(n), std::numeric_limits<double>::infinity());
  struct Candidate {
    double cost;
    std::uint32_t vertex, parent;
    bool operator>(const Candidate& other) const {
      if (cost != other.cost) return cost > other.cost;
      return vertex > other.vertex;
    }
  };
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
  Eigen::Index joined = 0;
  for (const std::uint32_t seed : seeds) {
    if (oriented(seed, options.axis) < 0.0) oriented.row(seed) *= -1.0;
    in_tree[seed] = 1;
    ++joined;
    auto push_neighbors = [&](std::uint32_t v) {
      for (auto e = graph.offsets[v]; e < graph.offsets[v + 1]; ++e) {
        const std::uint32_t w = graph.targets[static_cast<std::size_t>(e)];
        if (in_tree[w]) continue;
        const double c = cost(v, w);
        if (c < best_cost[w]) {
          best_cost[w] = c;
          queue.push({c, w, v});
        }
      }
    };
    push_neighbors(seed);
    while (!queue.empty()) {
      const Candidate next = queue.top();
      queue.pop();
      if (in_tree[next.vertex]) continue;
      in_tree[next.vertex] = 1;
      if (oriented.row(next.vertex).dot(oriented.row(next.parent)) < 0.0)
        oriented.row(next.vertex) *= -1.0;
      push_neighbors(next.vertex);
      if ((++joined & 0xFFFF) == 0)
        propagation.report(static_cast<double>(joined) / static_cast<double>(n), "orient normals");
    }
  }
  propagation.report(1.0, "orient normals");
  return oriented;
}

}  // namespace meshsmith::points
