// Iterative closest points (§2.3.1).
//
// How it works. Everything runs in the normalized frame of the target (core/normalization.h: one
// exact power-of-two scaling), the frame the kd-tree (points/kd_tree.h) searches in, so the
// closest-point queries need no conversion and the translation maps back exactly at the end.
// Set-up, once: the optional voxel reduction of both sets, the kd-tree on the target, the target
// normals for point-to-plane (given, or PCA on that same tree), and a Morton ordering of the
// source points so that consecutive queries walk the same tree nodes (cache-friendly).
// Each iteration: (1) closest target point of every transformed source point, in parallel, each
// query writing its own slot. The queries are the cost of ICP, so each point keeps what its last
// search found (its two nearest target points and where it was): a point that moved by less
// than half the gap between the two keeps its partner with no search (exact, by the triangle
// inequality: most points near convergence), the others search their 2 nearest with the
// distance to their previous two as a bound that prunes the tree from the root (see
// correspond); (2) outlier rejection: pairs beyond max_distance or failing the normal test,
// then all but the `trim` fraction of closest pairs (one nth_element); (3) the update: point-to-point by Horn's
// closed form on the cross-covariance of the inlier pairs, point-to-plane by the 6×6 normal
// equations of the linearised rotation about the source centroid (x ↦ x + ω × (x − c) + τ,
// then the exact rotation of ω by Rodrigues' formula, as in Low 2004). Sums are taken over fixed
// blocks of 2048 pairs and the blocks added in order, so the result does not depend on how TBB
// schedules them; sums are of coordinates relative to the current source centroid, which keeps
// them well conditioned. Convergence (IcpOptions, IcpResult::stop): an update that rotates by
// less than `tolerance` radians and translates by less than `tolerance` diagonals; a relative
// change of the inlier RMS and count below relative_rmse / relative_fitness (Open3D's test);
// a cycle (pairs or pose of up to `patience` iterations ago again) or a stall (no new least
// RMS for `patience` iterations), both of which end on the pose of least RMS.
#include <meshsmith/registration/icp.h>

#include "horn.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/spatial_order.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/points/kd_tree.h>
#include <meshsmith/points/normals.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

namespace meshsmith::registration {

namespace {

constexpr Eigen::Index kBlock = 2048;

/// Σ over [0, n) of body(i, partial) in fixed blocks added in block order: deterministic.
template <typename Partial, typename Body>
Partial block_sum(Eigen::Index n, const Body& body) {
  const Eigen::Index blocks = (n + kBlock - 1) / kBlock;
  std::vector<Partial> partial(static_cast<std::size_t>(blocks));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, blocks, 1), [&](const tbb::blocked_range<Eigen::Index>& r) {
    for (Eigen::Index b = r.begin(); b < r.end(); ++b) {
      Partial& sum = partial[static_cast<std::size_t>(b)];
      const Eigen::Index end = std::min(n, (b + 1) * kBlock);
      for (Eigen::Index i = b * kBlock; i < end; ++i) body(i, sum);
    }
  });
  Partial total;
  for (const Partial& p : partial) total += p;
  return total;
}

struct PointMoments {  // pairs (p, q) relative to a reference point
  double count = 0.0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), q = Eigen::Vector3d::Zero();
  Eigen::Matrix3d pq = Eigen::Matrix3d::Zero();  // Σ p qᵀ
  PointMoments& operator+=(const PointMoments& o) {
    count += o.count; p += o.p; q += o.q; pq += o.pq;
    return *this;
  }
};

struct PlaneSystem {  // normal equations of the linearised point-to-plane residuals
  Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> Jtr = Eigen::Matrix<double, 6, 1>::Zero();
  PlaneSystem& operator+=(const PlaneSystem& o) {
    JtJ += o.JtJ; Jtr += o.Jtr;
    return *this;
  }
};

/// Points grouped by occupied voxel: group g holds order[offsets[g] .. offsets[g+1]), groups in
/// lexicographic order of the voxel's integer coordinates.
struct VoxelGroups {
  std::vector<std::int64_t> order, offsets;
};

VoxelGroups voxel_groups(const VertexRef& P, double voxel_size, const char* name) {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size))
    throw InputError(std::string("voxel_size = ") + number_text(voxel_size) + ": expected a positive finite length");
  const Eigen::RowVector3d low = P.colwise().minCoeff(), high = P.colwise().maxCoeff();
  constexpr double kMaxCells = double(1 << 21);
  for (int axis = 0; axis < 3; ++axis) {
    const double cells = (high(axis) / voxel_size - low(axis) / voxel_size);  // halves: no overflow
    if (!(cells < kMaxCells - 1))
      throw InputError(std::string("voxel_size = ") + number_text(voxel_size) + ": " + name +
                       " would need 2^21 or more voxels along axis " + std::to_string(axis) +
                       "; use a larger voxel size");
  }
  const Eigen::Index n = P.rows();
  std::vector<std::uint64_t> key(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    std::uint64_t k = 0;
    for (int axis = 0; axis < 3; ++axis) {
      double c = std::floor(P(i, axis) / voxel_size - low(axis) / voxel_size);
      c = std::clamp(c, 0.0, kMaxCells - 1);
      k = (k << 21) | static_cast<std::uint64_t>(c);
    }
    key[static_cast<std::size_t>(i)] = k;
  }
  VoxelGroups groups;
  groups.order.resize(static_cast<std::size_t>(n));
  std::iota(groups.order.begin(), groups.order.end(), std::int64_t(0));
  std::stable_sort(groups.order.begin(), groups.order.end(),
                   [&](std::int64_t a, std::int64_t b) { return key[std::size_t(a)] < key[std::size_t(b)]; });
  for (std::size_t k = 0; k < groups.order.size(); ++k)
    if (k == 0 || key[std::size_t(groups.order[k])] != key[std::size_t(groups.order[k - 1])])
      groups.offsets.push_back(static_cast<std::int64_t>(k));
  groups.offsets.push_back(n);
  return groups;
}

VertexMatrix group_centroids(const VertexRef& P, const VoxelGroups& groups) {
  const Eigen::Index count = static_cast<Eigen::Index>(groups.offsets.size()) - 1;
  VertexMatrix out(count, 3);
  for (Eigen::Index g = 0; g < count; ++g) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    const auto begin = groups.offsets[std::size_t(g)], end = groups.offsets[std::size_t(g + 1)];
    for (auto k = begin; k < end; ++k) sum += P.row(groups.order[std::size_t(k)]);
    out.row(g) = sum / double(end - begin);
  }
  return out;
}

/// Sum of unit normals per group, each made to agree in sign with the group's first one.
VertexMatrix group_normals(const VertexMatrix& N, const VoxelGroups& groups) {
  const Eigen::Index count = static_cast<Eigen::Index>(groups.offsets.size()) - 1;
  VertexMatrix out(count, 3);
  for (Eigen::Index g = 0; g < count; ++g) {
    const auto begin = groups.offsets[std::size_t(g)], end = groups.offsets[std::size_t(g + 1)];
    const Eigen::RowVector3d first = N.row(groups.order[std::size_t(begin)]);
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (auto k = begin; k < end; ++k) {
      const Eigen::RowVector3d n = N.row(groups.order[std::size_t(k)]);
      sum += n.dot(first) >= 0.0 ? n : Eigen::RowVector3d(-n);
    }
    const double length = sum.norm();
    out.row(g) = length > 0.0 ? Eigen::RowVector3d(sum / length) : first;
  }
  return out;
}

void check_options(const IcpOptions& o) {
  if (o.max_iterations < 1)
    throw InputError("max_iterations = " + std::to_string(o.max_iterations) + ": expected at least 1");
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance))
    throw InputError("tolerance = " + number_text(o.tolerance) + ": expected a positive finite number");
  if (!(o.relative_rmse >= 0.0) || !std::isfinite(o.relative_rmse))
    throw InputError("relative_rmse = " + number_text(o.relative_rmse) + ": expected a finite fraction >= 0 (0: off)");
  if (!(o.relative_fitness >= 0.0) || !std::isfinite(o.relative_fitness))
    throw InputError("relative_fitness = " + number_text(o.relative_fitness) + ": expected a finite fraction >= 0");
  if (o.patience < 0 || o.patience == 1)
    throw InputError("patience = " + std::to_string(o.patience) + ": expected 0 (off) or at least 2 iterations");
  if (!(o.max_distance >= 0.0))
    throw InputError("max_distance = " + number_text(o.max_distance) + ": expected a length >= 0 (0: no limit)");
  if (!(o.trim > 0.0 && o.trim <= 1.0))
    throw InputError("trim = " + number_text(o.trim) + ": expected a fraction in (0, 1]");
  if (!(o.voxel_size >= 0.0) || !std::isfinite(o.voxel_size))
    throw InputError("voxel_size = " + number_text(o.voxel_size) + ": expected a positive finite length (0: none)");
  if (!(o.normal_angle >= 0.0 && o.normal_angle <= 0.5 * M_PI + 1e-12))
    throw InputError("normal_angle = " + number_text(o.normal_angle) + ": expected an angle in [0, π/2] radians (0: off)");
  if (o.normal_neighbours < 3)
    throw InputError("normal_neighbours = " + std::to_string(o.normal_neighbours) + ": expected at least 3");
  if (!o.initial.allFinite() || o.initial.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw InputError("initial: expected a finite 4×4 affine transform with last row (0, 0, 0, 1)");
}

/// Closest pairs of the rows of S under (R, t) and the outlier rule: `index`, `squared` and
/// `inlier` get one entry per row; `inliers` counts the inliers.
struct Correspondences {
  std::vector<std::uint32_t> index;   // closest target point (valid where found)
  std::vector<double> squared;        // squared distance to it now; +inf: no pair (outlier)
  std::vector<char> inlier;
  Eigen::Index inliers = 0;
  std::uint64_t hash = 0;  // of the inlier pairs: equal sets of pairs give equal hashes
  // The cache of the last search of each point: where it was, the squared distance to its
  // closest target point then, and to the second closest (or a lower bound of it); its second.
  std::vector<double> searched_at, first_then, second_then;
  std::vector<std::uint32_t> second;
};

/// Normal compatibility of the pairs: source normals (rows of S's order, in the source frame)
/// turned by the current rotation against the target normals; off when `source` is null.
struct NormalTest {
  const VertexMatrix* source = nullptr;
  const VertexMatrix* target = nullptr;
  double min_cosine = 0.0;  // |cos| of the largest angle allowed
};

constexpr std::uint32_t kNoSecond = std::numeric_limits<std::uint32_t>::max();

/// warm = true: c holds the searches of the previous call on the same S. A point that has moved
/// by δ since its last search, whose closest target point was then at r1 and the second closest
/// at r2 >= r1 + 2δ (with a rounding margin), keeps its closest point with no search at all (by
/// the triangle inequality every other point is now at >= r2 − δ >= r1 + δ >= its distance), so
/// near convergence most points skip the tree. Any other point searches its 2 nearest, bounded
/// by its distance to the farther of its previous two (they are within it; the bound prunes from
/// the first node on), capped at max_distance. Nothing within max_distance, or a pair that fails
/// the normal test: squared distance +inf (an outlier). The result is that of a plain search.
void correspond(const points::KdTree& tree, const VertexMatrix& S, const Eigen::Matrix3d& R,
                const Eigen::Vector3d& t, double max_squared, double trim, bool warm, const NormalTest& normals,
                Correspondences& c) {
  const Eigen::Index n = S.rows();
  const auto rows = std::size_t(n);
  c.index.resize(rows), c.squared.resize(rows), c.inlier.assign(rows, 0);
  if (!warm) {
    c.searched_at.assign(3 * rows, 0.0), c.second.assign(rows, kNoSecond);
    c.first_then.assign(rows, std::numeric_limits<double>::infinity()), c.second_then.assign(rows, 0.0);
  }
  const VertexMatrix& Q = tree.normalized_points();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 512), [&](const tbb::blocked_range<Eigen::Index>& r) {
    for (Eigen::Index i = r.begin(); i < r.end(); ++i) {
      const std::size_t k = std::size_t(i);
      const Eigen::Vector3d p = R * S.row(i).transpose() + t;
      std::uint32_t& index = c.index[k];
      double& squared = c.squared[k];
      Eigen::Map<Eigen::Vector3d> at(&c.searched_at[3 * k]);
      // +inf for a pair whose normals differ by more than the angle allowed.
      auto test_normals = [&] {
        if (normals.source == nullptr || !(squared < kInf)) return;
        const double cosine = (R * normals.source->row(i).transpose()).dot(normals.target->row(index).transpose());
        if (!(std::abs(cosine) >= normals.min_cosine)) squared = kInf;
      };
      double bound = max_squared;
      if (warm && c.first_then[k] < kInf) {
        const double moved = (p - at).norm();
        const double r1 = std::sqrt(c.first_then[k]), r2 = std::sqrt(c.second_then[k]);
        if (r2 - r1 > 2.0 * moved + 1e-12 * (r2 + moved)) {  // the closest point is still the same
          squared = (p - Q.row(index).transpose()).squaredNorm();
          if (!(squared < max_squared)) squared = kInf;
          test_normals();
          continue;
        }
        if (c.second[k] != kNoSecond) {
          const double farther = std::max((p - Q.row(index).transpose()).squaredNorm(),
                                          (p - Q.row(c.second[k]).transpose()).squaredNorm());
          bound = std::min(farther * (1.0 + 1e-12) + std::numeric_limits<double>::min(), max_squared);
        }
      }
      std::uint32_t indices[2];
      double squares[2];
      const int hits = tree.nearest(p.data(), 2, indices, squares, bound);
      at = p;
      if (hits == 0) {
        squared = kInf, c.first_then[k] = kInf;
        continue;
      }
      index = indices[0], squared = squares[0], c.first_then[k] = squares[0];
      c.second[k] = hits == 2 ? indices[1] : kNoSecond;
      c.second_then[k] = hits == 2 ? squares[1] : std::min(bound, std::numeric_limits<double>::max());
      test_normals();
    }
  });
  double cut = max_squared;
  if (trim < 1.0) {
    std::vector<double> kept;
    kept.reserve(std::size_t(n));
    for (double d : c.squared)
      if (d <= max_squared && d < kInf) kept.push_back(d);
    if (!kept.empty()) {
      const auto k = std::size_t(std::max(1.0, std::ceil(trim * double(kept.size())))) - 1;
      std::nth_element(kept.begin(), kept.begin() + std::ptrdiff_t(k), kept.end());
      cut = std::min(cut, kept[k]);
    }
  }
  Eigen::Index count = 0;
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a over (pair or "no pair") per point
  for (Eigen::Index i = 0; i < n; ++i) {
    std::uint64_t pair = 0xffffffffull;
    if (c.squared[std::size_t(i)] <= cut && c.squared[std::size_t(i)] < kInf) {  // +inf: rejected
      c.inlier[std::size_t(i)] = 1;
      pair = c.index[std::size_t(i)];
      ++count;
    }
    hash = (hash ^ pair) * 1099511628211ull;
  }
  c.inliers = count;
  c.hash = hash;
}

/// The angle of a 3×3 rotation (radians).
double rotation_angle_3(const Eigen::Matrix3d& rotation) {
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() = rotation;
  return rotation_angle(T);
}

double inlier_rms(const Correspondences& c) {
  double sum = 0.0;
  for (std::size_t i = 0; i < c.squared.size(); ++i)
    if (c.inlier[i]) sum += c.squared[i];
  return c.inliers > 0 ? std::sqrt(sum / double(c.inliers)) : std::numeric_limits<double>::infinity();
}

}  // namespace

VertexMatrix voxel_downsample(const VertexRef& P, double voxel_size) {
  validate_vertices(P, "P");
  return group_centroids(P, voxel_groups(P, voxel_size, "P"));
}

namespace {

/// Unit rows of given normals. \throw InputError naming the row of a zero or non-finite one.
VertexMatrix unit_normals(const VertexRef& N, Eigen::Index rows, const char* name, const char* points) {
  if (N.rows() != rows)
    throw InputError(std::string(name) + " has " + std::to_string(N.rows()) + " rows for " + std::to_string(rows) +
                     " " + points + " points");
  VertexMatrix out(N.rows(), 3);
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const Eigen::RowVector3d n = N.row(i);
    const double length = n.norm();
    if (!n.allFinite() || !(length > 0.0) || !std::isfinite(length))
      throw InputError(std::string(name) + "[" + std::to_string(i) + "] = (" + number_text(n(0)) + ", " +
                       number_text(n(1)) + ", " + number_text(n(2)) + "): expected a nonzero finite normal");
    out.row(i) = n / length;
  }
  return out;
}

/// PCA normals of P (its own kd-tree). \throw InputError when P is too small for k neighbours.
VertexMatrix pca_normals(const VertexMatrix& P, int k, const char* what) {
  if (P.rows() <= k)
    throw InputError(std::string("icp: ") + what + " normals are estimated from normal_neighbours = " +
                     std::to_string(k) + " neighbours, but it has " + std::to_string(P.rows()) +
                     " points (give the normals, or lower normal_neighbours)");
  return points::estimate_normals(points::KdTree(P), {k, 0.0}).normals;
}

/// The rows of `all` whose group in `groups` they belong to: out[row] = per_group[group of row].
VertexMatrix spread_to_rows(const VertexMatrix& per_group, const VoxelGroups& groups, Eigen::Index rows) {
  VertexMatrix out(rows, 3);
  for (std::size_t g = 0; g + 1 < groups.offsets.size(); ++g)
    for (auto k = groups.offsets[g]; k < groups.offsets[g + 1]; ++k) out.row(groups.order[std::size_t(k)]) = per_group.row(Eigen::Index(g));
  return out;
}

}  // namespace

IcpResult icp(const VertexRef& source_in, const VertexRef& target_in, const VertexRef& source_normals,
              const VertexRef& target_normals, const IcpOptions& options, const Progress& progress) {
  validate_vertices(source_in, "source");
  validate_vertices(target_in, "target");
  check_options(options);
  const bool plane = options.method == IcpMethod::point_to_plane;
  const bool filter = options.normal_angle > 0.0;
  const bool target_normals_given = (plane || filter) && target_normals.rows() > 0;
  const bool source_normals_given = filter && source_normals.rows() > 0;
  VertexMatrix given_target_normals, given_source_normals;
  if (target_normals_given) given_target_normals = unit_normals(target_normals, target_in.rows(), "target_normals", "target");
  if (source_normals_given) given_source_normals = unit_normals(source_normals, source_in.rows(), "source_normals", "source");

  // The source under the start transform (input units); given source normals turned with it
  // (by the inverse transpose of its linear part, which is the rotation for a rigid start).
  const Eigen::Matrix3d A0 = options.initial.topLeftCorner<3, 3>();
  const Eigen::Vector3d b0 = options.initial.topRightCorner<3, 1>();
  VertexMatrix source_start = (source_in * A0.transpose()).rowwise() + b0.transpose();
  if (!source_start.allFinite()) throw InputError("initial maps a source point outside the double range");
  if (source_normals_given) {
    const Eigen::Matrix3d normal_map = A0.inverse().transpose();
    if (!normal_map.allFinite()) throw InputError("initial: its 3×3 part is singular");
    given_source_normals = given_source_normals * normal_map.transpose();
    given_source_normals.rowwise().normalize();
  }

  // Voxel reduction, once; normals for the reduced sets (given ones averaged per voxel).
  VertexMatrix target_points, target_unit_normals, source_points, source_unit_normals, source_all_normals;
  VoxelGroups source_groups;
  if (options.voxel_size > 0.0) {
    const VoxelGroups tg = voxel_groups(target_in, options.voxel_size, "target");
    target_points = group_centroids(target_in, tg);
    if (target_normals_given) target_unit_normals = group_normals(given_target_normals, tg);
    source_groups = voxel_groups(source_start, options.voxel_size, "source");
    source_points = group_centroids(source_start, source_groups);
    if (source_normals_given) {
      source_unit_normals = group_normals(given_source_normals, source_groups);
      source_all_normals = std::move(given_source_normals);
    }
  } else {
    target_points = target_in;
    if (target_normals_given) target_unit_normals = std::move(given_target_normals);
    source_points = source_start;
    if (source_normals_given) source_unit_normals = std::move(given_source_normals);
  }
  const Eigen::Index needed = plane ? 6 : 3;
  if (source_points.rows() < 3 || target_points.rows() < needed)
    throw InputError("icp: " + std::to_string(source_points.rows()) + " source and " +
                     std::to_string(target_points.rows()) + " target points" +
                     (options.voxel_size > 0.0 ? " after the voxel reduction (voxel_size = " +
                                                     number_text(options.voxel_size) + ")" : std::string()) +
                     ": at least 3 source and " + std::to_string(needed) + " target points are needed");

  progress.report(0.0, "icp: kd-tree");
  const points::KdTree tree(target_points);
  const CoordinateFrame& frame = tree.frame();
  if ((plane || filter) && !target_normals_given) {
    if (target_points.rows() <= options.normal_neighbours)
      throw InputError("icp: " + std::string(plane ? "point_to_plane" : "normal_angle") + " needs target normals: " +
                       std::to_string(target_points.rows()) + " target points are too few for normal_neighbours = " +
                       std::to_string(options.normal_neighbours));
    target_unit_normals = points::estimate_normals(tree, {options.normal_neighbours, 0.0}).normals;
  }
  if (filter && !source_normals_given) {
    source_unit_normals = pca_normals(source_points, options.normal_neighbours, "the source's");
    if (options.voxel_size > 0.0) source_all_normals = spread_to_rows(source_unit_normals, source_groups, source_start.rows());
  }
  const VertexMatrix& Q = tree.normalized_points();
  const Eigen::Vector3d target_extent = (Q.colwise().maxCoeff() - Q.colwise().minCoeff()).transpose();
  const double diagonal = std::max(target_extent.norm(), std::numeric_limits<double>::min());

  // Source in the target's frame, in Morton order (queries of nearby points follow each other).
  const VertexMatrix source_frame = frame.normalize_vertices(source_points);
  const LargeVector<int> order = morton_order(source_frame);
  VertexMatrix S(source_frame.rows(), 3), SN;
  for (Eigen::Index k = 0; k < S.rows(); ++k) S.row(k) = source_frame.row(order[std::size_t(k)]);
  if (filter) {
    SN.resize(S.rows(), 3);
    for (Eigen::Index k = 0; k < S.rows(); ++k) SN.row(k) = source_unit_normals.row(order[std::size_t(k)]);
  }
  const NormalTest normal_test{filter ? &SN : nullptr, &target_unit_normals, std::cos(options.normal_angle)};
  const Eigen::Vector3d source_centroid = S.colwise().mean().transpose();

  const double max_squared = options.max_distance > 0.0
                                 ? std::pow(frame.to_normalized(options.max_distance, 1), 2)
                                 : std::numeric_limits<double>::infinity();
  IcpResult result;
  result.stop = "max_iterations";
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Correspondences c;
  // Per iteration: the pose at its start, the hash of its pairs and their RMS (normalized units).
  struct Visit {
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    std::uint64_t hash;
    double rms;
    Eigen::Index inliers;
  };
  std::vector<Visit> visits;
  // Progress: the least RMS and the most inliers so far, and the last visit that improved
  // either by more than relative_rmse / relative_fitness (with max_distance, pairs join as the
  // alignment improves and the RMS of the inliers may then grow: the count is progress too).
  double least_rms = std::numeric_limits<double>::infinity();
  Eigen::Index most_inliers = 0;
  std::size_t last_record = 0;
  const auto window = std::size_t(options.patience);
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    progress.report(double(iteration) / double(options.max_iterations), "icp");
    correspond(tree, S, R, t, max_squared, options.trim, iteration > 0, normal_test, c);
    if (c.inliers < needed) {
      if (iteration == 0) {
        double nearest = std::numeric_limits<double>::infinity();  // the closest pair, for the message
        for (Eigen::Index i = 0; i < S.rows(); ++i) {
          std::uint32_t j;
          double squared;
          if (tree.nearest_within(S.row(i).data(), nearest, j, squared)) nearest = squared;
        }
        throw InputError("max_distance = " + number_text(options.max_distance) +
                         (filter ? ", normal_angle = " + number_text(options.normal_angle) : std::string()) + ": " +
                         std::to_string(c.inliers) + " source point(s) are within it of the target at the "
                         "start (the nearest pair is " + number_text(frame.to_input(std::sqrt(nearest), 1, "distance")) +
                         " apart); at least " + std::to_string(needed) + " are needed");
      }
      result.stop = "lost_pairs";  // reported as not converged
      break;
    }
    const double rms = inlier_rms(c);
    visits.push_back({R, t, c.hash, rms, c.inliers});
    const std::size_t now = visits.size() - 1;
    if (now > 0) {
      const Visit& before = visits[now - 1];
      if (options.relative_rmse > 0.0 && std::abs(rms - before.rms) <= options.relative_rmse * before.rms &&
          double(std::abs(c.inliers - before.inliers)) <= options.relative_fitness * double(before.inliers)) {
        result.stop = "relative_change", result.converged = true;
        break;
      }
    }
    if (rms < (1.0 - options.relative_rmse) * least_rms ||
        double(c.inliers) > (1.0 + options.relative_fitness) * double(most_inliers))
      last_record = now;
    least_rms = std::min(least_rms, rms), most_inliers = std::max(most_inliers, c.inliers);
    if (window >= 2) {
      // A cycle: the pairs, or the pose to within the tolerance, of 2 .. patience iterations ago.
      const Eigen::Vector3d centre_now = R * source_centroid + t;
      bool cycle = false;
      for (std::size_t back = 2; back <= window && back <= now && !cycle; ++back) {
        const Visit& v = visits[now - back];
        const double angle = rotation_angle_3(R * v.R.transpose());
        const double moved = (centre_now - (v.R * source_centroid + v.t)).norm();
        cycle = v.hash == c.hash || (angle < options.tolerance && moved < options.tolerance * diagonal);
      }
      const bool stalled = !cycle && now - last_record >= window;
      if (cycle || stalled) {
        result.stop = cycle ? "cycle" : "stalled", result.converged = true;
        std::size_t best = now;  // the pose of least RMS of the window
        for (std::size_t v = now - std::min(now, window); v < now; ++v)
          if (visits[v].rms < visits[best].rms) best = v;
        R = visits[best].R, t = visits[best].t;
        break;
      }
    }
    result.rms_history.push_back(frame.to_input(inlier_rms(c), 1, "rms"));
    ++result.iterations;
    const Eigen::Vector3d centre = R * source_centroid + t;  // the reference point of the sums
    Eigen::Matrix3d dR;
    Eigen::Vector3d dt;
    if (!plane) {
      const PointMoments m = block_sum<PointMoments>(S.rows(), [&](Eigen::Index i, PointMoments& sum) {
        if (!c.inlier[std::size_t(i)]) return;
        const Eigen::Vector3d p = R * S.row(i).transpose() + t - centre;
        const Eigen::Vector3d q = Q.row(c.index[std::size_t(i)]).transpose() - centre;
        sum.count += 1.0;
        sum.p += p;
        sum.q += q;
        sum.pq.noalias() += p * q.transpose();
      });
      const Eigen::Vector3d mp = m.p / m.count, mq = m.q / m.count;
      const Eigen::Matrix3d H = m.pq - m.count * mp * mq.transpose();
      dR = detail::horn_rotation(H);
      dt = (mq + centre) - dR * (mp + centre);
    } else {
      const PlaneSystem system = block_sum<PlaneSystem>(S.rows(), [&](Eigen::Index i, PlaneSystem& sum) {
        if (!c.inlier[std::size_t(i)]) return;
        const Eigen::Vector3d x = R * S.row(i).transpose() + t;
        const std::uint32_t j = c.index[std::size_t(i)];
        const Eigen::Vector3d n = target_unit_normals.row(j).transpose();
        Eigen::Matrix<double, 6, 1> J;
        J.head<3>() = (x - centre).cross(n);
        J.tail<3>() = n;
        const double r = (x - Q.row(j).transpose()).dot(n);
        sum.JtJ.selfadjointView<Eigen::Lower>().rankUpdate(J);
        sum.Jtr.noalias() += r * J;
      });
      Eigen::Matrix<double, 6, 6> JtJ = system.JtJ.selfadjointView<Eigen::Lower>();
      // A tiny damping keeps the solve defined where the target lets the source slide (a plane).
      JtJ.diagonal().array() += 1e-12 * JtJ.trace() + std::numeric_limits<double>::min();
      const Eigen::Matrix<double, 6, 1> x = JtJ.ldlt().solve(-system.Jtr);
      if (!x.allFinite()) {
        result.stop = "singular";
        break;
      }
      dR = detail::rotation_from_vector(x.head<3>());
      dt = centre + x.tail<3>() - dR * centre;
    }
    R = dR * R;
    t = dR * t + dt;
    const double angle = rotation_angle_3(dR);
    const double moved = (dR * centre + dt - centre).norm();  // how far the centroid moved
    if (angle < options.tolerance && moved < options.tolerance * diagonal) {
      result.stop = "tolerance", result.converged = true;
      break;
    }
  }
  progress.report(1.0, "icp");

  // The transform in input units: x ↦ R x + 2^e t after the start.
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() = R;
  T.topRightCorner<3, 1>() = t * std::ldexp(1.0, frame.exponent);
  result.transform = T * options.initial;
  if (!result.transform.allFinite()) throw InputError("icp: the transform leaves the double range");

  // Final correspondences of every input source row at the final transform.
  const bool reduced = options.voxel_size > 0.0;
  const VertexMatrix all = reduced ? frame.normalize_vertices(source_start) : S;
  const NormalTest final_test{filter ? (reduced ? &source_all_normals : &SN) : nullptr, &target_unit_normals,
                              normal_test.min_cosine};
  correspond(tree, all, R, t, max_squared, options.trim, !reduced, final_test, c);
  result.rms = c.inliers > 0 ? frame.to_input(inlier_rms(c), 1, "rms") : std::numeric_limits<double>::infinity();
  result.inlier_fraction = double(c.inliers) / double(all.rows());
  if (c.inliers < needed) result.converged = false, result.stop = "lost_pairs";
  result.inliers.assign(std::size_t(all.rows()), 0);
  for (Eigen::Index k = 0; k < all.rows(); ++k) {
    const std::size_t row = reduced ? std::size_t(k) : std::size_t(order[std::size_t(k)]);
    result.inliers[row] = c.inlier[std::size_t(k)];
  }
  return result;
}

IcpResult icp(const VertexRef& source, const VertexRef& target, const VertexRef& target_normals,
              const IcpOptions& options, const Progress& progress) {
  return icp(source, target, VertexMatrix(0, 3), target_normals, options, progress);
}

IcpResult icp(const VertexRef& source, const VertexRef& target, const IcpOptions& options,
              const Progress& progress) {
  return icp(source, target, VertexMatrix(0, 3), VertexMatrix(0, 3), options, progress);
}

IcpMultiResult icp_multi(const std::vector<VertexMatrix>& scans, const IcpMultiOptions& options,
                         const Progress& progress) {
  const std::size_t k = scans.size();
  if (k < 2) throw InputError("icp_multi: " + std::to_string(k) + " scan(s) given: expected at least 2");
  if (!options.initial.empty() && options.initial.size() != k)
    throw InputError("icp_multi: initial has " + std::to_string(options.initial.size()) + " transforms for " +
                     std::to_string(k) + " scans (expected one per scan, or none)");
  if (options.rounds < 0) throw InputError("rounds = " + std::to_string(options.rounds) + ": expected at least 0");
  if (!(options.round_tolerance > 0.0) || !std::isfinite(options.round_tolerance))
    throw InputError("round_tolerance = " + number_text(options.round_tolerance) + ": expected a positive finite number");
  check_options(options.icp);
  const bool graph = options.strategy == MultiStrategy::pose_graph;
  if (graph && options.rounds < 1)
    throw InputError("rounds = " + std::to_string(options.rounds) + ": the pose graph needs at least 1 iteration");
  if (!(options.overlap_distance >= 0.0) || !std::isfinite(options.overlap_distance))
    throw InputError("overlap_distance = " + number_text(options.overlap_distance) +
                     ": expected a finite length >= 0 (0: 1% of the largest scan's diagonal)");
  if (!(options.min_overlap > 0.0 && options.min_overlap <= 1.0))
    throw InputError("min_overlap = " + number_text(options.min_overlap) + ": expected a fraction in (0, 1]");
  if (options.edge_samples < 3)
    throw InputError("edge_samples = " + std::to_string(options.edge_samples) + ": expected at least 3");
  for (std::size_t i = 0; i < options.initial.size(); ++i)
    if (!options.initial[i].allFinite() || options.initial[i].row(3) != Eigen::RowVector4d(0, 0, 0, 1))
      throw InputError("initial[" + std::to_string(i) + "]: expected a finite 4×4 affine transform with last row (0, 0, 0, 1)");
  const bool plane = options.icp.method == IcpMethod::point_to_plane;
  const bool normals = plane || options.icp.normal_angle > 0.0;

  // Once per scan: the voxel reduction and the PCA normals (in the scan's own frame).
  std::vector<VertexMatrix> points(k), unit_normals(k);
  for (std::size_t i = 0; i < k; ++i) {
    const std::string name = "scans[" + std::to_string(i) + "]";
    validate_vertices(scans[i], name.c_str());
    points[i] = options.icp.voxel_size > 0.0 ? group_centroids(scans[i], voxel_groups(scans[i], options.icp.voxel_size, name.c_str()))
                                             : scans[i];
    if (points[i].rows() < 3)
      throw InputError("icp_multi: " + name + " has " + std::to_string(points[i].rows()) + " point(s)" +
                       (options.icp.voxel_size > 0.0 ? " after the voxel reduction" : "") + ": at least 3 are needed");
    if (normals) unit_normals[i] = pca_normals(points[i], options.icp.normal_neighbours, name.c_str());
  }
  IcpMultiResult result;
  result.transforms.assign(k, Transform::Identity());
  if (!options.initial.empty()) result.transforms = options.initial;
  result.rms.assign(k, 0.0), result.inlier_fraction.assign(k, 1.0), result.scan_converged.assign(k, 1);

  // The union of the scans `others` at their current poses, with their normals turned along.
  auto union_of = [&](const std::vector<std::size_t>& others, VertexMatrix& target, VertexMatrix& target_normals) {
    Eigen::Index rows = 0;
    for (std::size_t j : others) rows += points[j].rows();
    target.resize(rows, 3), target_normals.resize(normals ? rows : 0, 3);
    Eigen::Index at = 0;
    for (std::size_t j : others) {
      const Eigen::Matrix3d A = result.transforms[j].topLeftCorner<3, 3>();
      const Eigen::Vector3d b = result.transforms[j].topRightCorner<3, 1>();
      target.middleRows(at, points[j].rows()) = (points[j] * A.transpose()).rowwise() + b.transpose();
      if (normals) {
        VertexMatrix turned = unit_normals[j] * A.inverse();  // rows n ↦ A^-T n
        turned.rowwise().normalize();
        target_normals.middleRows(at, points[j].rows()) = turned;
      }
      at += points[j].rows();
    }
  };
  // Scan i onto the union of `others`, from its current pose; returns how far its pose moved.
  IcpOptions pairwise = options.icp;
  pairwise.voxel_size = 0.0;  // reduced above, once
  const int steps = int(k - 1) * (1 + options.rounds);
  int step = 0;
  auto register_onto = [&](std::size_t i, const std::vector<std::size_t>& others) {
    VertexMatrix target, target_normals;
    union_of(others, target, target_normals);
    pairwise.initial = result.transforms[i];
    const Progress part = progress.subrange(double(step) / steps, double(std::min(step + 1, steps)) / steps);
    ++step;
    IcpResult r;
    try {
      r = icp(points[i], target, normals ? unit_normals[i] : VertexMatrix(0, 3), target_normals, pairwise, part);
    } catch (const InputError& error) {
      throw InputError("icp_multi: scan " + std::to_string(i) + ": " + error.what());
    }
    const double angle = rotation_angle(r.transform * result.transforms[i].inverse());
    const double moved = (r.transform.topRightCorner<3, 1>() - result.transforms[i].topRightCorner<3, 1>()).norm();
    result.transforms[i] = r.transform;
    result.rms[i] = r.rms, result.inlier_fraction[i] = r.inlier_fraction, result.scan_converged[i] = r.converged;
    return std::pair<double, double>(angle, moved);
  };
  // The diagonal of all scans in their own frames: the unit of the rounds' translation test.
  double diagonal = 0.0;
  for (const VertexMatrix& P : points) diagonal = std::max(diagonal, (P.colwise().maxCoeff() - P.colwise().minCoeff()).norm());

  // Scan i's pairs with the union of the others at the final poses: its RMS and inlier fraction.
  auto evaluate = [&](std::size_t i) {
    std::vector<std::size_t> rest;
    for (std::size_t j = 0; j < k; ++j)
      if (j != i) rest.push_back(j);
    VertexMatrix target, target_normals;
    union_of(rest, target, target_normals);
    const points::KdTree tree(target);
    const CoordinateFrame& frame = tree.frame();
    const Eigen::Matrix3d A = result.transforms[i].topLeftCorner<3, 3>();
    const Eigen::Vector3d b = result.transforms[i].topRightCorner<3, 1>();
    const VertexMatrix S = frame.normalize_vertices(VertexMatrix((points[i] * A.transpose()).rowwise() + b.transpose()));
    VertexMatrix SN;
    if (options.icp.normal_angle > 0.0) {
      SN = unit_normals[i] * A.inverse();
      SN.rowwise().normalize();
    }
    const NormalTest test{options.icp.normal_angle > 0.0 ? &SN : nullptr, &target_normals,
                          std::cos(options.icp.normal_angle)};
    const double max_squared = options.icp.max_distance > 0.0
                                   ? std::pow(frame.to_normalized(options.icp.max_distance, 1), 2)
                                   : std::numeric_limits<double>::infinity();
    Correspondences c;
    correspond(tree, S, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), max_squared, options.icp.trim, false, test, c);
    result.rms[i] = c.inliers > 0 ? frame.to_input(inlier_rms(c), 1, "rms") : std::numeric_limits<double>::infinity();
    result.inlier_fraction[i] = double(c.inliers) / double(S.rows());
  };
  if (graph) {
    // Pairwise registrations: scan j onto scan i from their start poses; an edge where they overlap.
    const double overlap = options.overlap_distance > 0.0 ? options.overlap_distance : 0.005 * diagonal;
    struct Edge {
      std::size_t i, j;
      std::vector<Eigen::Index> rows;  // the sampled rows of scan j that overlap scan i
    };
    std::vector<Edge> edges;
    std::vector<char> edge_converged;
    std::vector<Transform> relative_poses;  // per edge: the pairwise ICP's map of scan j into scan i's frame
    std::vector<points::KdTree> trees;
    trees.reserve(k);
    for (std::size_t i = 0; i < k; ++i) trees.emplace_back(points[i]);
    const std::size_t pair_count = k * (k - 1) / 2;
    std::size_t done = 0;
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = i + 1; j < k; ++j) {
        ++done;
        pairwise.initial = result.transforms[i].inverse() * result.transforms[j];
        auto moved_by = [&](const Transform& T) {
          return VertexMatrix((points[j] * T.topLeftCorner<3, 3>().transpose()).rowwise() +
                              T.topRightCorner<3, 1>().transpose());
        };
        if (options.icp.max_distance > 0.0) {  // too few pairs within max_distance at the start: no edge
          const points::KnnResult start = trees[i].query(moved_by(pairwise.initial), 1);
          if ((start.distances.array() <= options.icp.max_distance).count() < 6) continue;
        }
        const Progress part = progress.subrange(0.8 * double(done - 1) / double(pair_count),
                                                0.8 * double(done) / double(pair_count));
        IcpResult r;
        try {
          r = icp(points[j], points[i], normals ? unit_normals[j] : VertexMatrix(0, 3),
                  normals ? unit_normals[i] : VertexMatrix(0, 3), pairwise, part);
        } catch (const InputError& error) {
          throw InputError("icp_multi: scans " + std::to_string(i) + " and " + std::to_string(j) + ": " + error.what());
        }
        const points::KnnResult nearest = trees[i].query(moved_by(r.transform), 1);
        std::vector<Eigen::Index> close;
        for (Eigen::Index row = 0; row < points[j].rows(); ++row)
          if (nearest.distances(row, 0) <= overlap) close.push_back(row);
        if (double(close.size()) < options.min_overlap * double(points[j].rows()) || close.size() < 6) continue;
        Edge edge{i, j, {}};
        const std::size_t samples = std::min(close.size(), std::size_t(options.edge_samples));
        for (std::size_t n = 0; n < samples; ++n) edge.rows.push_back(close[n * close.size() / samples]);
        edges.push_back(std::move(edge));
        edge_converged.push_back(r.converged ? 1 : 0);
        result.edges.emplace_back(int(i), int(j));
        relative_poses.push_back(r.transform);
      }
    }
    // The scans that reach scan 0 through the edges start from the pairwise poses composed along
    // a spanning tree (grown from scan 0 in edge order); the others keep their start poses.
    std::vector<char> reached(k, 0);
    reached[0] = 1;
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t n = 0; n < edges.size(); ++n) {
        const Edge& e = edges[n];
        if (reached[e.i] == reached[e.j]) continue;
        if (reached[e.i]) result.transforms[e.j] = result.transforms[e.i] * relative_poses[n];
        else result.transforms[e.i] = result.transforms[e.j] * relative_poses[n].inverse();
        reached[e.i] = reached[e.j] = 1, grew = true;
      }
    }
    std::vector<int> variable(k, -1);
    int unknowns = 0;
    for (std::size_t s = 1; s < k; ++s)
      if (reached[s]) variable[s] = unknowns++;
    // Multi-view ICP over the graph: each iteration pairs every edge's rows of scan j with their
    // closest points of scan i at the current poses (pairs beyond overlap_distance left out),
    // then one Gauss–Newton step of Σ over the edges of the point-to-point ‖X_i p − X_j q‖² (or,
    // for point-to-plane, ⟨X_i p − X_j q, n⟩² with n the normal at p), each pose perturbed as
    // x ↦ c + R(ω)(x − c) + τ about the centroid c of scan 0.
    const Eigen::Vector3d c = (result.transforms[0].topLeftCorner<3, 3>() * points[0].colwise().mean().transpose() +
                               result.transforms[0].topRightCorner<3, 1>());
    auto skew = [](const Eigen::Vector3d& v) {
      Eigen::Matrix3d K;
      K << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
      return K;
    };
    bool settled = unknowns == 0;
    for (int iteration = 0; iteration < options.rounds && !settled; ++iteration) {
      progress.report(0.8 + 0.2 * double(iteration) / double(options.rounds), "icp_multi: pose graph");
      Eigen::MatrixXd H = Eigen::MatrixXd::Zero(6 * unknowns, 6 * unknowns);
      Eigen::VectorXd g = Eigen::VectorXd::Zero(6 * unknowns);
      for (const Edge& e : edges) {
        const int vi = variable[e.i], vj = variable[e.j];
        if (vi < 0 && vj < 0) continue;
        const Transform& Xi = result.transforms[e.i];
        const Transform& Xj = result.transforms[e.j];
        const Transform relative = Xi.inverse() * Xj;  // scan j into scan i's frame
        VertexMatrix Q(Eigen::Index(e.rows.size()), 3);
        for (std::size_t n = 0; n < e.rows.size(); ++n) Q.row(Eigen::Index(n)) = points[e.j].row(e.rows[n]);
        const VertexMatrix moved = (Q * relative.topLeftCorner<3, 3>().transpose()).rowwise() +
                                   relative.topRightCorner<3, 1>().transpose();
        const points::KnnResult nearest = trees[e.i].query(moved, 1);
        Eigen::Matrix<double, 6, 6> Hii = Eigen::Matrix<double, 6, 6>::Zero(), Hij = Hii, Hjj = Hii;
        Eigen::Matrix<double, 6, 1> gi = Eigen::Matrix<double, 6, 1>::Zero(), gj = gi;
        for (Eigen::Index n = 0; n < Q.rows(); ++n) {
          if (!(nearest.distances(n, 0) <= overlap)) continue;
          const Eigen::Index row_i = nearest.indices(n, 0);
          const Eigen::Vector3d a = Xi.topLeftCorner<3, 3>() * points[e.i].row(row_i).transpose() + Xi.topRightCorner<3, 1>() - c;
          const Eigen::Vector3d b = Xj.topLeftCorner<3, 3>() * Q.row(n).transpose() + Xj.topRightCorner<3, 1>() - c;
          if (plane) {  // one residual along the normal at p
            const Eigen::Vector3d normal = (Xi.topLeftCorner<3, 3>() * unit_normals[e.i].row(row_i).transpose()).normalized();
            Eigen::Matrix<double, 1, 6> Ji, Jj;
            Ji << a.cross(normal).transpose(), normal.transpose();
            Jj << normal.cross(b).transpose(), -normal.transpose();
            const double r = normal.dot(a - b);
            Hii.noalias() += Ji.transpose() * Ji, Hij.noalias() += Ji.transpose() * Jj, Hjj.noalias() += Jj.transpose() * Jj;
            gi.noalias() += Ji.transpose() * r, gj.noalias() += Jj.transpose() * r;
          } else {
            Eigen::Matrix<double, 3, 6> Ji, Jj;  // ∂(a − b)/∂(ω, τ) of pose i and of pose j
            Ji << -skew(a), Eigen::Matrix3d::Identity();
            Jj << skew(b), -Eigen::Matrix3d::Identity();
            const Eigen::Vector3d r = a - b;
            Hii.noalias() += Ji.transpose() * Ji, Hij.noalias() += Ji.transpose() * Jj, Hjj.noalias() += Jj.transpose() * Jj;
            gi.noalias() += Ji.transpose() * r, gj.noalias() += Jj.transpose() * r;
          }
        }
        if (vi >= 0) H.block<6, 6>(6 * vi, 6 * vi) += Hii, g.segment<6>(6 * vi) += gi;
        if (vj >= 0) H.block<6, 6>(6 * vj, 6 * vj) += Hjj, g.segment<6>(6 * vj) += gj;
        if (vi >= 0 && vj >= 0) {
          H.block<6, 6>(6 * vi, 6 * vj) += Hij;
          H.block<6, 6>(6 * vj, 6 * vi) += Hij.transpose();
        }
      }
      H.diagonal().array() += 1e-12 * H.trace() + std::numeric_limits<double>::min();
      const Eigen::VectorXd step = H.ldlt().solve(-g);
      if (!step.allFinite()) break;
      double largest_angle = 0.0, largest_move = 0.0;
      for (std::size_t s = 1; s < k; ++s) {
        if (variable[s] < 0) continue;
        const Eigen::Vector3d omega = step.segment<3>(6 * variable[s]), tau = step.segment<3>(6 * variable[s] + 3);
        Transform D = Transform::Identity();
        D.topLeftCorner<3, 3>() = detail::rotation_from_vector(omega);
        D.topRightCorner<3, 1>() = c + tau - D.topLeftCorner<3, 3>() * c;
        result.transforms[s] = D * result.transforms[s];
        largest_angle = std::max(largest_angle, omega.norm());
        largest_move = std::max(largest_move, tau.norm());
      }
      ++result.rounds;
      settled = largest_angle < options.round_tolerance && largest_move < options.round_tolerance * diagonal;
    }
    for (std::size_t s = 0; s < k; ++s) {
      bool ok = reached[s] != 0;
      for (std::size_t e = 0; e < edges.size(); ++e)
        if ((edges[e].i == s || edges[e].j == s) && !edge_converged[e]) ok = false;
      result.scan_converged[s] = ok ? 1 : 0;
      evaluate(s);
    }
    bool all = settled;
    for (char ok : result.scan_converged) all = all && ok;
    result.converged = all;
    progress.report(1.0, "icp_multi");
    return result;
  }

  std::vector<std::size_t> others;
  for (std::size_t i = 1; i < k; ++i) {  // sequential pass: onto the growing model
    others.push_back(i - 1);
    register_onto(i, others);
  }
  bool still = false;
  for (int round = 0; round < options.rounds && !still; ++round) {
    still = true;
    for (std::size_t i = 1; i < k; ++i) {
      others.clear();
      for (std::size_t j = 0; j < k; ++j)
        if (j != i) others.push_back(j);
      const auto [angle, moved] = register_onto(i, others);
      still = still && angle < options.round_tolerance && moved < options.round_tolerance * diagonal;
    }
    ++result.rounds;
  }
  evaluate(0);  // the first scan's pose stays: its RMS with the others at their final poses
  bool all = options.rounds == 0 || still;
  for (std::size_t i = 1; i < k; ++i) all = all && result.scan_converged[i];
  result.converged = all;
  progress.report(1.0, "icp_multi");
  return result;
}

}  // namespace meshsmith::registration
