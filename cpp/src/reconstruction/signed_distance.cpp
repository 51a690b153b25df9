// Signed distance fields (reconstruction/signed_distance.h).
//
// tangent_plane_sdf queries the points chapter's kd-tree once for all queries and blends the k
// nearest tangent planes. The winding number's hierarchy is a binary tree of triangles split at
// the median centroid along the box's longest axis (leaves of at most 8); each node keeps the
// first-order (dipole) moment of its triangles, which is what the far field of a solid angle
// needs (Barill et al. 2018, order 1). Queries walk it with an explicit stack; each query's
// result depends only on the query, so results do not depend on the thread count.
#include <meshsmith/reconstruction/signed_distance.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/parallel.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/distance.h>
#include <meshsmith/points/kd_tree.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace meshsmith::reconstruction {
namespace {

constexpr double pi = 3.14159265358979323846;

void validate_queries(const VertexRef& Q) {
  if (Q.rows() > 0) validate_vertices(Q, "Q");
}

/// Solid angle of triangle (a, b, c) seen from the origin (a, b, c relative to the query).
double solid_angle(const double* a, const double* b, const double* c) {
  const double la = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  const double lb = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
  const double lc = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  const double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
  const double ca = c[0] * a[0] + c[1] * a[1] + c[2] * a[2];
  return 2.0 * std::atan2(det, la * lb * lc + ab * lc + bc * la + ca * lb);
}

}  // namespace

Eigen::VectorXd tangent_plane_sdf(const VertexRef& P, const VertexRef& N, const VertexRef& Q, int k,
                                  const Progress& progress) {
  validate_vertices(P, "P");
  if (N.rows() != P.rows())
    throw InputError("N has " + std::to_string(N.rows()) + " rows and P " + std::to_string(P.rows()) +
                     ": expected one normal per sample");
  validate_vertices(N, "N");
  validate_queries(Q);
  if (k < 1 || k > P.rows())
    throw InputError("k = " + std::to_string(k) + ": expected an integer in [1, " + std::to_string(P.rows()) + "]");
  VertexMatrix unit(P.rows(), 3);
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const double length = N.row(i).norm();
    if (!(length > 0.0) || !std::isfinite(length))
      throw InputError("N[" + std::to_string(i) + "] has length " + std::to_string(length) +
                       ": expected a non-zero normal per sample");
    unit.row(i) = N.row(i) / length;
  }
  Eigen::VectorXd out(Q.rows());
  if (Q.rows() == 0) return out;
  const points::KdTree tree(P);
  const points::KnnResult nearest = tree.query(Q, k, progress.subrange(0.0, 0.8));
  parallel_for_with_progress(Q.rows(), progress.subrange(0.8, 1.0), "tangent-plane distance", [&](Eigen::Index q) {
    const double scale = nearest.distances(q, k - 1);
    double sum = 0.0, weights = 0.0;
    for (int j = 0; j < k; ++j) {
      const auto p = static_cast<Eigen::Index>(nearest.indices(q, j));
      const double r = scale > 0.0 ? nearest.distances(q, j) / scale : 0.0;
      const double w = k == 1 ? 1.0 : std::exp(-r * r);
      sum += w * (Q.row(q) - P.row(p)).dot(unit.row(p));
      weights += w;
    }
    out[q] = sum / weights;
  });
  return out;
}

WindingNumber::WindingNumber(const VertexRef& V, const FaceRef& F, double accuracy) : accuracy_(accuracy) {
  validate_mesh(V, F);
  if (!(accuracy >= 1.0) || !std::isfinite(accuracy))
    throw InputError("accuracy = " + std::to_string(accuracy) + ": expected a finite number >= 1");
  const int m = static_cast<int>(F.rows());
  corners_.resize(static_cast<std::size_t>(m) * 9);
  std::vector<double> centroids(static_cast<std::size_t>(m) * 3);
  for (int f = 0; f < m; ++f)
    for (int c = 0; c < 3; ++c)
      for (int a = 0; a < 3; ++a) {
        corners_[9 * f + 3 * c + a] = V(F(f, c), a);
        centroids[3 * f + a] += V(F(f, c), a) / 3.0;
      }
  order_.resize(static_cast<std::size_t>(m));
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(static_cast<std::size_t>(2 * (m / 4 + 1)));
  build(0, m, centroids);
  std::vector<double> sorted(corners_.size());
  for (int s = 0; s < m; ++s) std::copy_n(&corners_[9 * static_cast<std::size_t>(order_[s])], 9, &sorted[9 * static_cast<std::size_t>(s)]);
  corners_ = std::move(sorted);
}

int WindingNumber::build(int begin, int end, std::vector<double>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node{};
  for (int a = 0; a < 3; ++a) node.lower[a] = std::numeric_limits<double>::infinity(), node.upper[a] = -node.lower[a];
  double total = 0.0, weighted[3] = {0, 0, 0};
  for (int s = begin; s < end; ++s) {
    const double* t = &corners_[9 * static_cast<std::size_t>(order_[s])];
    const double u[3] = {t[3] - t[0], t[4] - t[1], t[5] - t[2]}, w[3] = {t[6] - t[0], t[7] - t[1], t[8] - t[2]};
    const double n[3] = {0.5 * (u[1] * w[2] - u[2] * w[1]), 0.5 * (u[2] * w[0] - u[0] * w[2]), 0.5 * (u[0] * w[1] - u[1] * w[0])};
    const double area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int a = 0; a < 3; ++a) {
      node.area[a] += n[a];
      weighted[a] += area * (t[a] + t[3 + a] + t[6 + a]) / 3.0;
      for (int c = 0; c < 3; ++c) node.lower[a] = std::min(node.lower[a], t[3 * c + a]), node.upper[a] = std::max(node.upper[a], t[3 * c + a]);
    }
    total += area;
  }
  for (int a = 0; a < 3; ++a)
    node.centre[a] = total > 0.0 ? weighted[a] / total : 0.5 * (node.lower[a] + node.upper[a]);
  node.radius = 0.0;
  for (int s = begin; s < end; ++s) {
    const double* t = &corners_[9 * static_cast<std::size_t>(order_[s])];
    const double u[3] = {t[3] - t[0], t[4] - t[1], t[5] - t[2]}, w[3] = {t[6] - t[0], t[7] - t[1], t[8] - t[2]};
    const double n[3] = {0.5 * (u[1] * w[2] - u[2] * w[1]), 0.5 * (u[2] * w[0] - u[0] * w[2]), 0.5 * (u[0] * w[1] - u[1] * w[0])};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) node.moment[3 * i + j] += n[i] * ((t[j] + t[3 + j] + t[6 + j]) / 3.0 - node.centre[j]);
    for (int c = 0; c < 3; ++c) {
      double d2 = 0.0;
      for (int a = 0; a < 3; ++a) d2 += (t[3 * c + a] - node.centre[a]) * (t[3 * c + a] - node.centre[a]);
      node.radius = std::max(node.radius, std::sqrt(d2));
    }
  }
  if (end - begin <= 8) {
    node.first = begin, node.count = end - begin;
    nodes_[static_cast<std::size_t>(index)] = node;
    return index;
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (node.upper[a] - node.lower[a] > node.upper[axis] - node.lower[axis]) axis = a;
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end, [&](int x, int y) {
    const double cx = centroids[3 * static_cast<std::size_t>(x) + axis], cy = centroids[3 * static_cast<std::size_t>(y) + axis];
    return cx < cy || (cx == cy && x < y);
  });
  build(begin, middle, centroids);
  node.first = build(middle, end, centroids);
  node.count = 0;
  nodes_[static_cast<std::size_t>(index)] = node;
  return index;
}

double WindingNumber::at(const double* q) const {
  double omega = 0.0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[static_cast<std::size_t>(stack[--top])];
    const double d[3] = {node.centre[0] - q[0], node.centre[1] - q[1], node.centre[2] - q[2]};
    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (r2 > accuracy_ * accuracy_ * node.radius * node.radius) {
      // g(x) = (x − q)/|x − q|³ expanded at the centre: Σ a·g(c) + Σ a_tᵀ ∇g(c) (c_t − c), with
      // ∇g = I/r³ − 3 d dᵀ/r⁵ (d = c − q).
      const double r = std::sqrt(r2), r3 = r2 * r;
      const double* M = node.moment;
      double dMd = 0.0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) dMd += d[i] * M[3 * i + j] * d[j];
      omega += (node.area[0] * d[0] + node.area[1] * d[1] + node.area[2] * d[2]) / r3 +
               (M[0] + M[4] + M[8]) / r3 - 3.0 * dMd / (r3 * r2);
      continue;
    }
    if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s) {
        const double* t = &corners_[9 * static_cast<std::size_t>(s)];
        const double a[3] = {t[0] - q[0], t[1] - q[1], t[2] - q[2]};
        const double b[3] = {t[3] - q[0], t[4] - q[1], t[5] - q[2]};
        const double c[3] = {t[6] - q[0], t[7] - q[1], t[8] - q[2]};
        omega += solid_angle(a, b, c);
      }
      continue;
    }
    const int self = static_cast<int>(&node - nodes_.data());
    stack[top++] = node.first;  // right child
    stack[top++] = self + 1;    // left child
  }
  return omega / (4.0 * pi);
}

Eigen::VectorXd WindingNumber::at(const VertexRef& Q, const Progress& progress) const {
  validate_queries(Q);
  Eigen::VectorXd out(Q.rows());
  parallel_for_with_progress(Q.rows(), progress, "winding number", [&](Eigen::Index r) {
    const double q[3] = {Q(r, 0), Q(r, 1), Q(r, 2)};
    out[r] = at(q);
  }, 64);
  return out;
}

MeshSignedDistance mesh_sdf(const VertexRef& V, const FaceRef& F, const VertexRef& Q, const Progress& progress) {
  validate_mesh(V, F);
  validate_queries(Q);
  const geometry::SurfaceDistance surface(V, F);
  geometry::ClosestPoints closest = surface.closest_points(Q, progress.subrange(0.0, 0.5));
  const WindingNumber winding(V, F);
  MeshSignedDistance out;
  out.winding = winding.at(Q, progress.subrange(0.5, 1.0));
  out.distance = std::move(closest.distances);
  for (Eigen::Index r = 0; r < Q.rows(); ++r)
    if (out.winding[r] >= 0.5) out.distance[r] = -out.distance[r];
  out.face = std::move(closest.faces);
  out.point = std::move(closest.points);
  return out;
}

}  // namespace meshsmith::reconstruction
