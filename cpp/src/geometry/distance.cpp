#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/distance.h>
#include <meshsmith/geometry/measures.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <meshsmith/core/parallel.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace meshsmith::geometry {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

inline double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Closest point to p on the segment [a, b] (a itself when the segment is a point).
inline void closest_on_segment(const double* p, const double* a, const double* b, double* out) {
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double length2 = dot3(ab, ab);
  const double t = length2 > 0.0 ? std::clamp(dot3(ap, ab) / length2, 0.0, 1.0) : 0.0;
  for (int k = 0; k < 3; ++k) out[k] = a[k] + t * ab[k];
}

inline double squared_distance(const double* p, const double* q) {
  const double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
  return dot3(d, d);
}

/// Closest point to p on a triangle of zero area: the nearest of the closest points on its edges.
void closest_on_flat_triangle(const double* p, const double* a, const double* b, const double* c, double* out) {
  double candidate[3], best = infinity;
  const double* ends[3][2] = {{a, b}, {b, c}, {c, a}};
  for (auto& edge : ends) {
    closest_on_segment(p, edge[0], edge[1], candidate);
    const double d = squared_distance(p, candidate);
    if (d < best) {
      best = d;
      std::copy(candidate, candidate + 3, out);
    }
  }
}

/// Closest point to p on the triangle (a, b, c), by the Voronoi regions of its corners, edges
/// and face (Ericson, Real-Time Collision Detection, §5.1.5). `flat`: the triangle has zero area.
void closest_on_triangle(const double* p, const double* a, const double* b, const double* c, bool flat,
                         double* out) {
  if (flat) return closest_on_flat_triangle(p, a, b, c, out);
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return void(std::copy(a, a + 3, out));
  const double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
  const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return void(std::copy(b, b + 3, out));
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);  // d1 − d3 = |ab|² > 0
    for (int k = 0; k < 3; ++k) out[k] = a[k] + v * ab[k];
    return;
  }
  const double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
  const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return void(std::copy(c, c + 3, out));
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);  // d2 − d6 = |ac|² > 0
    for (int k = 0; k < 3; ++k) out[k] = a[k] + w * ac[k];
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));  // = |bc|² > 0
    for (int k = 0; k < 3; ++k) out[k] = b[k] + w * (c[k] - b[k]);
    return;
  }
  const double sum = va + vb + vc;  // = |ab × ac|² up to rounding
  if (!(sum > 0.0)) return closest_on_flat_triangle(p, a, b, c, out);
  const double v = vb / sum, w = vc / sum;
  for (int k = 0; k < 3; ++k) out[k] = a[k] + v * ab[k] + w * ac[k];
}

void validate_queries(const VertexRef& Q) {
  for (Eigen::Index i = 0; i < Q.rows(); ++i)
    for (Eigen::Index c = 0; c < 3; ++c)
      if (!std::isfinite(Q(i, c)))
        throw InputError("Q[" + std::to_string(i) + ", " + std::to_string(c) + "] is not finite");
}

/// Number of nodes of the tree over `count` triangles: leaves hold <= leaf_size, internal nodes
/// split at count / 2. Known before building, so each subtree's place in the array is too.
int subtree_size(int count, int leaf_size) {
  if (count <= leaf_size) return 1;
  return 1 + subtree_size(count / 2, leaf_size) + subtree_size(count - count / 2, leaf_size);
}

/// splitmix64: a well-mixed 64-bit hash, for reproducible samples independent of thread count.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double unit_uniform(std::uint64_t bits) { return static_cast<double>(bits >> 11) * 0x1.0p-53; }

/// validate_mesh with the mesh's name ("A" or "B") in front of the message.
void validate_named_mesh(const VertexRef& V, const FaceRef& F, const char* name) {
  try {
    validate_mesh(V, F);
  } catch (const InputError& error) {
    throw InputError(std::string("mesh ") + name + ": " + error.what());
  }
}

void validate_sampling(const FaceRef& F, const SurfaceSampling& sampling) {
  if (sampling.samples_per_face < 0)
    throw InputError("samples_per_face must be >= 0, got " + std::to_string(sampling.samples_per_face));
  // A bound on memory (24 bytes per sample): 2^27 samples are 3 GB.
  if (static_cast<double>(F.rows()) * sampling.samples_per_face > 134217728.0)
    throw InputError("samples_per_face = " + std::to_string(sampling.samples_per_face) + " on " +
                     std::to_string(F.rows()) + " faces gives more than 2^27 samples");
}

}  // namespace

SurfaceDistance::SurfaceDistance(const VertexRef& V, const FaceRef& F, int leaf_size) {
  validate_mesh(V, F);
  if (leaf_size < 1) throw InputError("leaf_size must be >= 1, got " + std::to_string(leaf_size));
  if (F.rows() / leaf_size >= (Eigen::Index(1) << 29))
    throw InputError("too many faces (" + std::to_string(F.rows()) + ") for leaf_size " + std::to_string(leaf_size) +
                     ": the tree would have more than 2^30 nodes");
  const int m = static_cast<int>(F.rows());
  std::vector<Centroid> items(m);
  tbb::parallel_for(tbb::blocked_range<int>(0, m, 8192), [&](const tbb::blocked_range<int>& range) {
    for (int f = range.begin(); f < range.end(); ++f) {
      for (int k = 0; k < 3; ++k)
        items[f].position[k] = (V(F(f, 0), k) + V(F(f, 1), k) + V(F(f, 2), k)) / 3.0;
      items[f].face = f;
    }
  });
  nodes_.resize(subtree_size(m, leaf_size));
  build(0, 0, m, items, leaf_size);
  face_of_slot_.resize(m);
  for (int s = 0; s < m; ++s) face_of_slot_[s] = items[s].face;
  corners_.resize(9 * static_cast<std::size_t>(m));
  flat_.resize(m);
  tbb::parallel_for(tbb::blocked_range<int>(0, m, 8192), [&](const tbb::blocked_range<int>& range) {
    for (int s = range.begin(); s < range.end(); ++s) {
      double* corner = &corners_[9 * static_cast<std::size_t>(s)];
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) corner[3 * j + k] = V(F(face_of_slot_[s], j), k);
      const Eigen::Vector3d a(corner), b(corner + 3), c(corner + 6);
      flat_[s] = (b - a).cross(c - a).squaredNorm() == 0.0;
    }
  });
  // Boxes, bottom-up: children always come after their parent in nodes_.
  for (int n = static_cast<int>(nodes_.size()) - 1; n >= 0; --n) {
    Node& node = nodes_[n];
    std::fill(node.lower, node.lower + 3, infinity);
    std::fill(node.upper, node.upper + 3, -infinity);
    auto grow = [&](const double* lower, const double* upper) {
      for (int k = 0; k < 3; ++k) {
        node.lower[k] = std::min(node.lower[k], lower[k]);
        node.upper[k] = std::max(node.upper[k], upper[k]);
      }
    };
    if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s)
        for (int j = 0; j < 3; ++j) grow(&corners_[9 * s + 3 * j], &corners_[9 * s + 3 * j]);
    } else {
      grow(nodes_[n + 1].lower, nodes_[n + 1].upper);
      grow(nodes_[node.first].lower, nodes_[node.first].upper);
    }
  }
}

void SurfaceDistance::build(int index, int begin, int end, std::vector<Centroid>& items, int leaf_size) {
  if (end - begin <= leaf_size) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return;
  }
  double lower[3] = {infinity, infinity, infinity}, upper[3] = {-infinity, -infinity, -infinity};
  for (int s = begin; s < end; ++s)
    for (int k = 0; k < 3; ++k) {
      lower[k] = std::min(lower[k], items[s].position[k]);
      upper[k] = std::max(upper[k], items[s].position[k]);
    }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (upper[k] - lower[k] > upper[axis] - lower[axis]) axis = k;
  const int middle = begin + (end - begin) / 2;
  std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
                   [axis](const Centroid& x, const Centroid& y) {
    const double cx = x.position[axis], cy = y.position[axis];
    return cx < cy || (cx == cy && x.face < y.face);  // a total order: the tree does not depend on the STL
  });
  const int right = index + 1 + subtree_size(middle - begin, leaf_size);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  auto build_left = [&] { build(index + 1, begin, middle, items, leaf_size); };
  auto build_right = [&] { build(right, middle, end, items, leaf_size); };
  if (end - begin > 16384) {
    tbb::parallel_invoke(build_left, build_right);  // disjoint slots and nodes: same tree
  } else {
    build_left();
    build_right();
  }
}

namespace {
inline double box_squared_distance(const double* q, const double* lower, const double* upper) {
  double d = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double below = lower[k] - q[k], above = q[k] - upper[k];
    const double gap = std::max(0.0, std::max(below, above));
    d += gap * gap;
  }
  return d;
}
}  // namespace

double SurfaceDistance::closest_point(const double* query, int& face, double* point) const {
  int slot = -1;
  const double squared = search(query, -1.0, slot, point);
  face = face_of_slot_[slot];
  return squared;
}

double SurfaceDistance::squared_distance_unless_below(const double* query, double squared_threshold,
                                                     int& hint) const {
  double point[3];
  return search(query, squared_threshold, hint, point);
}

double SurfaceDistance::search(const double* query, double stop_below, int& best_slot, double* point) const {
  struct Pending {
    int node;
    double squared_distance;
  };
  Pending stack[128];
  int top = 0;
  stack[top++] = {0, box_squared_distance(query, nodes_[0].lower, nodes_[0].upper)};
  double best = infinity;
  double candidate[3];
  if (best_slot >= 0) {  // a hint: an upper bound to prune with from the start
    const double* corner = &corners_[9 * static_cast<std::size_t>(best_slot)];
    closest_on_triangle(query, corner, corner + 3, corner + 6, flat_[best_slot] != 0, point);
    best = squared_distance(query, point);
  }
  while (top > 0 && best > stop_below) {
    const Pending pending = stack[--top];
    if (pending.squared_distance >= best) continue;
    const Node& node = nodes_[pending.node];
    if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s) {
        const double* corner = &corners_[9 * static_cast<std::size_t>(s)];
        closest_on_triangle(query, corner, corner + 3, corner + 6, flat_[s] != 0, candidate);
        const double d = squared_distance(query, candidate);
        if (d < best) {
          best = d;
          best_slot = s;
          std::copy(candidate, candidate + 3, point);
        }
      }
      continue;
    }
    const int left = pending.node + 1, right = node.first;
    const double d_left = box_squared_distance(query, nodes_[left].lower, nodes_[left].upper);
    const double d_right = box_squared_distance(query, nodes_[right].lower, nodes_[right].upper);
    // Push the farther child first so the nearer one is searched first (ties: left first).
    if (d_left <= d_right) {
      if (d_right < best) stack[top++] = {right, d_right};
      if (d_left < best) stack[top++] = {left, d_left};
    } else {
      if (d_left < best) stack[top++] = {left, d_left};
      if (d_right < best) stack[top++] = {right, d_right};
    }
  }
  return best;
}

ClosestPoints SurfaceDistance::closest_points(const VertexRef& Q, const Progress& progress) const {
  validate_queries(Q);
  ClosestPoints out;
  out.distances.resize(Q.rows());
  out.faces.resize(Q.rows());
  out.points.resize(Q.rows(), 3);
  parallel_for_with_progress(Q.rows(), progress, "closest points", [&](Eigen::Index i) {
    const double query[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
    int face = -1;
    out.distances[i] = std::sqrt(closest_point(query, face, out.points.row(i).data()));
    out.faces[i] = face;
  });
  return out;
}

Eigen::VectorXd SurfaceDistance::distances(const VertexRef& Q, const Progress& progress) const {
  validate_queries(Q);
  Eigen::VectorXd out(Q.rows());
  // Each search starts from the previous query's triangle: only the (exact, unique) distance is
  // returned, so this cannot make the result depend on how the range is split between threads.
  parallel_ranges_with_progress(Q.rows(), progress, "distances", [&](Eigen::Index begin, Eigen::Index end) {
    int hint = -1;
    double point[3];
    for (Eigen::Index i = begin; i < end; ++i) {
      const double query[3] = {Q(i, 0), Q(i, 1), Q(i, 2)};
      out[i] = std::sqrt(search(query, -1.0, hint, point));
    }
  });
  return out;
}

std::pair<VertexMatrix, Eigen::VectorXd> surface_samples(const VertexRef& V, const FaceRef& F,
                                                         const SurfaceSampling& sampling,
                                                         const std::vector<int>& face_order) {
  validate_mesh(V, F);
  validate_sampling(F, sampling);
  if (!face_order.empty() && static_cast<Eigen::Index>(face_order.size()) != F.rows())
    throw InputError("face_order has " + std::to_string(face_order.size()) + " entries but F has " +
                     std::to_string(F.rows()) + " rows");
  const Eigen::VectorXd areas = face_areas(V, F);
  const Eigen::Index n = V.rows(), k = sampling.samples_per_face;
  VertexMatrix points(n + F.rows() * k, 3);
  points.topRows(n) = V;
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(points.rows());
  if (k == 0) {
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int j = 0; j < 3; ++j) weights[F(f, j)] += areas[f] / 3.0;
    return {std::move(points), std::move(weights)};
  }
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, F.rows(), 1024), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index place = range.begin(); place < range.end(); ++place) {
      const Eigen::Index f = face_order.empty() ? place : face_order[place];
      if (f < 0 || f >= F.rows()) throw InputError("face_order holds " + std::to_string(f) + ", not a face index");
      const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      for (Eigen::Index s = 0; s < k; ++s) {
        const std::uint64_t key = mix(sampling.seed ^ mix(static_cast<std::uint64_t>(f * k + s)));
        const double root = std::sqrt(unit_uniform(key)), r2 = unit_uniform(mix(key));
        // Uniform in the triangle (Osada et al. 2002): corners weighted 1 − √r1, √r1 (1 − r2), √r1 r2.
        points.row(n + place * k + s) = (1.0 - root) * a + root * (1.0 - r2) * b + root * r2 * c;
        weights[n + place * k + s] = areas[f] / static_cast<double>(k);
      }
    }
  });
  return {std::move(points), std::move(weights)};
}

namespace {

/// Both surfaces checked, sampled and put in AABB trees: what both distances below start from.
struct SampledSurfaces {
  VertexMatrix samples_a, samples_b;
  Eigen::VectorXd weights_a, weights_b;
  SurfaceDistance tree_a, tree_b;
};

SampledSurfaces sample_surfaces(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB, const FaceRef& FB,
                                const SurfaceSampling& sampling, const Progress& progress) {
  validate_named_mesh(VA, FA, "A");
  validate_named_mesh(VB, FB, "B");
  validate_sampling(FA, sampling);
  validate_sampling(FB, sampling);
  progress.report(0.0, "sampling and AABB trees");
  SurfaceDistance tree_a(VA, FA), tree_b(VB, FB);
  // Face samples in leaf order: consecutive queries are near each other (fast hinted searches).
  auto [samples_a, weights_a] = surface_samples(VA, FA, sampling, tree_a.faces_in_leaf_order());
  auto [samples_b, weights_b] = surface_samples(VB, FB, sampling, tree_b.faces_in_leaf_order());
  return {std::move(samples_a), std::move(samples_b), std::move(weights_a), std::move(weights_b),
          std::move(tree_a), std::move(tree_b)};
}

/// max over the rows of P of the distance to the surface of `tree`. Queries stop as soon as they
/// find a triangle no farther than the largest distance found so far (shared between threads):
/// such a query cannot raise the maximum. Every query that does raise it is computed exactly, so
/// the result is the exact maximum, whatever the thread count or order.
double max_distance(const SurfaceDistance& tree, const VertexMatrix& P, const Progress& progress) {
  std::atomic<double> largest{0.0};  // squared
  parallel_ranges_with_progress(P.rows(), progress, "Hausdorff distance", [&](Eigen::Index begin, Eigen::Index end) {
    int hint = -1;  // consecutive samples (of one face, or neighbouring vertices) are near each other
    for (Eigen::Index i = begin; i < end; ++i) {
      const double found =
          tree.squared_distance_unless_below(P.row(i).data(), largest.load(std::memory_order_relaxed), hint);
      double current = largest.load(std::memory_order_relaxed);
      while (found > current && !largest.compare_exchange_weak(current, found, std::memory_order_relaxed)) {
      }
    }
  });
  return std::sqrt(largest.load());
}

SurfaceDistances hausdorff_normalized(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB, const FaceRef& FB,
                                      const SurfaceSampling& sampling, const Progress& progress) {
  const SampledSurfaces surfaces = sample_surfaces(VA, FA, VB, FB, sampling, progress);
  SurfaceDistances out;
  out.a_to_b = max_distance(surfaces.tree_b, surfaces.samples_a, progress.subrange(0.05, 0.5));
  out.b_to_a = max_distance(surfaces.tree_a, surfaces.samples_b, progress.subrange(0.5, 1.0));
  out.symmetric = std::max(out.a_to_b, out.b_to_a);
  return out;
}

SurfaceDistances mean_normalized(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB, const FaceRef& FB,
                                 const SurfaceSampling& sampling, const Progress& progress) {
  const SampledSurfaces s = sample_surfaces(VA, FA, VB, FB, sampling, progress);
  const double area_a = s.weights_a.sum(), area_b = s.weights_b.sum();
  if (!(area_a > 0.0)) throw InputError("mesh A has zero total area: its mean distance is undefined");
  if (!(area_b > 0.0)) throw InputError("mesh B has zero total area: its mean distance is undefined");
  SurfaceDistances out;
  out.a_to_b = s.weights_a.dot(s.tree_b.distances(s.samples_a, progress.subrange(0.05, 0.5))) / area_a;
  out.b_to_a = s.weights_b.dot(s.tree_a.distances(s.samples_b, progress.subrange(0.5, 1.0))) / area_b;
  out.symmetric = (area_a * out.a_to_b + area_b * out.b_to_a) / (area_a + area_b);
  return out;
}

/// `measure` on both meshes in one normalized frame (core/normalization.h: the frame of the
/// larger of the two), distances mapped back: area weights are products of two coordinates and
/// their products with distances of three, which overflowed from 1e100 (NaN means).
template <typename Measure>
SurfaceDistances in_common_frame(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB, const FaceRef& FB,
                                 const SurfaceSampling& sampling, const Progress& progress, Measure measure) {
  validate_named_mesh(VA, FA, "A");
  validate_named_mesh(VB, FB, "B");
  CoordinateFrame frame;
  frame.exponent = std::max(normalizing_frame(VA).exponent, normalizing_frame(VB).exponent);
  SurfaceDistances out = measure(frame.normalize_vertices(VA), FA, frame.normalize_vertices(VB), FB, sampling, progress);
  out.symmetric = frame.to_input(out.symmetric, 1, "the surface distance");
  out.a_to_b = frame.to_input(out.a_to_b, 1, "the surface distance from A to B");
  out.b_to_a = frame.to_input(out.b_to_a, 1, "the surface distance from B to A");
  return out;
}

}  // namespace

SurfaceDistances hausdorff_distance(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB, const FaceRef& FB,
                                    const SurfaceSampling& sampling, const Progress& progress) {
  return in_common_frame(VA, FA, VB, FB, sampling, progress, hausdorff_normalized);
}

SurfaceDistances mean_surface_distance(const VertexRef& VA, const FaceRef& FA, const VertexRef& VB,
                                       const FaceRef& FB, const SurfaceSampling& sampling,
                                       const Progress& progress) {
  return in_common_frame(VA, FA, VB, FB, sampling, progress, mean_normalized);
}

}  // namespace meshsmith::geometry
