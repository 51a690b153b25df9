// Iterative closest points (§2.3.1).
//
// How it works. Everything runs in the normalized frame of the target (core/normalization.h: one
// exact power-of-two scaling), the frame the kd-tree (points/kd_tree.h) searches in, so the
// closest-point queries need no conversion and the translation maps back exactly at the end.
// Set-up, once: the optional voxel reduction of both sets, the kd-tree on the target, the target
// normals for point-to-plane (given, or PCA on that same tree), and a Morton ordering of the
// source points so that consecutive queries walk the same tree nodes (cache-friendly).
// Each iteration: (1) closest target point of every transformed source point, in parallel, each
// query writing its own slot; (2) outlier rejection: pairs beyond max_distance, then all but the
// `trim` fraction of closest pairs (one nth_element); (3) the update: point-to-point by Horn's
// closed form on the cross-covariance of the inlier pairs, point-to-plane by the 6×6 normal
// equations of the linearised rotation about the source centroid (x ↦ x + ω × (x − c) + τ,
// then the exact rotation of ω by Rodrigues' formula, as in Low 2004). Sums are taken over fixed
// blocks of 2048 pairs and the blocks added in order, so the result does not depend on how TBB
// schedules them; sums are of coordinates relative to the current source centroid, which keeps
// them well conditioned. Convergence: an update that rotates by less than `tolerance` radians
// and translates by less than `tolerance` diagonals.
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
  if (!(o.max_distance >= 0.0))
    throw InputError("max_distance = " + number_text(o.max_distance) + ": expected a length >= 0 (0: no limit)");
  if (!(o.trim > 0.0 && o.trim <= 1.0))
    throw InputError("trim = " + number_text(o.trim) + ": expected a fraction in (0, 1]");
  if (!(o.voxel_size >= 0.0) || !std::isfinite(o.voxel_size))
    throw InputError("voxel_size = " + number_text(o.voxel_size) + ": expected a positive finite length (0: none)");
  if (o.normal_neighbours < 3)
    throw InputError("normal_neighbours = " + std::to_string(o.normal_neighbours) + ": expected at least 3");
  if (!o.initial.allFinite() || o.initial.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
    throw InputError("initial: expected a finite 4×4 affine transform with last row (0, 0, 0, 1)");
}

/// Closest pairs of the rows of S under (R, t) and the outlier rule: `index`, `squared` and
/// `inlier` get one entry per row; returns the number of inliers.
struct Correspondences {
  std::vector<std::uint32_t> index;
  std::vector<double> squared;
  std::vector<char> inlier;
  Eigen::Index inliers = 0;
  double nearest = std::numeric_limits<double>::infinity();  // smallest squared distance
  std::uint64_t hash = 0;  // of the inlier pairs: equal sets of pairs give equal hashes
};

/// warm_squared > 0: c.index holds the pairs of the previous iteration, and a point whose previous
/// partner is within sqrt(warm_squared) (a few sample spacings: a ball of a few dozen points) is
/// searched in the ball of that radius (capped at max_distance), which holds the new closest
/// point and prunes the tree more than an unbounded search; a point with nothing within
/// max_distance gets squared distance +inf (an outlier either way). Other points: a plain search.
void correspond(const points::KdTree& tree, const VertexMatrix& S, const Eigen::Matrix3d& R,
                const Eigen::Vector3d& t, double max_squared, double trim, double warm_squared, Correspondences& c) {
  const Eigen::Index n = S.rows();
  c.index.resize(std::size_t(n));
  c.squared.resize(std::size_t(n));
  c.inlier.assign(std::size_t(n), 0);
  const VertexMatrix& Q = tree.normalized_points();
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 512), [&](const tbb::blocked_range<Eigen::Index>& r) {
    std::vector<std::pair<std::uint32_t, double>> matches;
    for (Eigen::Index i = r.begin(); i < r.end(); ++i) {
      const Eigen::Vector3d p = R * S.row(i).transpose() + t;
      std::uint32_t& index = c.index[std::size_t(i)];
      double& squared = c.squared[std::size_t(i)];
      const double previous = warm_squared > 0.0 ? (p - Q.row(index).transpose()).squaredNorm() : 0.0;
      if (warm_squared == 0.0 || !(previous <= warm_squared)) {
        tree.nearest(p.data(), 1, &index, &squared);
        continue;
      }
      const double radius = std::min(previous * (1.0 + 1e-12) + std::numeric_limits<double>::min(), max_squared);
      tree.within_radius(p.data(), radius, matches);
      if (matches.empty()) {
        squared = std::numeric_limits<double>::infinity();
      } else {
        index = matches.front().first;
        squared = matches.front().second;
      }
    }
  });
  double cut = max_squared;
  c.nearest = *std::min_element(c.squared.begin(), c.squared.end());
  if (trim < 1.0) {
    std::vector<double> kept;
    kept.reserve(std::size_t(n));
    for (double d : c.squared)
      if (d <= max_squared) kept.push_back(d);
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
    if (c.squared[std::size_t(i)] <= cut) {
      c.inlier[std::size_t(i)] = 1;
      pair = c.index[std::size_t(i)];
      ++count;
    }
    hash = (hash ^ pair) * 1099511628211ull;
  }
  c.inliers = count;
  c.hash = hash;
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

IcpResult icp(const VertexRef& source_in, const VertexRef& target_in, const VertexRef& target_normals,
              const IcpOptions& options, const Progress& progress) {
  validate_vertices(source_in, "source");
  validate_vertices(target_in, "target");
  check_options(options);
  const bool plane = options.method == IcpMethod::point_to_plane;
  const bool normals_given = plane && target_normals.rows() > 0;
  VertexMatrix given_normals;
  if (normals_given) {
    if (target_normals.rows() != target_in.rows())
      throw InputError("target_normals has " + std::to_string(target_normals.rows()) + " rows for " +
                       std::to_string(target_in.rows()) + " target points");
    given_normals.resize(target_normals.rows(), 3);
    for (Eigen::Index i = 0; i < target_normals.rows(); ++i) {
      const Eigen::RowVector3d n = target_normals.row(i);
      const double length = n.norm();
      if (!n.allFinite() || !(length > 0.0) || !std::isfinite(length))
        throw InputError("target_normals[" + std::to_string(i) + "] = (" + number_text(n(0)) + ", " +
                         number_text(n(1)) + ", " + number_text(n(2)) + "): expected a nonzero finite normal");
      given_normals.row(i) = n / length;
    }
  }

  // The source under the start transform (input units).
  const Eigen::Matrix3d A0 = options.initial.topLeftCorner<3, 3>();
  const Eigen::Vector3d b0 = options.initial.topRightCorner<3, 1>();
  VertexMatrix source_start = (source_in * A0.transpose()).rowwise() + b0.transpose();
  if (!source_start.allFinite()) throw InputError("initial maps a source point outside the double range");

  // Voxel reduction, once.
  VertexMatrix target_points, target_unit_normals;
  VertexMatrix source_points;
  if (options.voxel_size > 0.0) {
    const VoxelGroups tg = voxel_groups(target_in, options.voxel_size, "target");
    target_points = group_centroids(target_in, tg);
    if (normals_given) target_unit_normals = group_normals(given_normals, tg);
    source_points = group_centroids(source_start, voxel_groups(source_start, options.voxel_size, "source"));
  } else {
    target_points = target_in;
    if (normals_given) target_unit_normals = std::move(given_normals);
    source_points = source_start;
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
  if (plane && !normals_given) {
    if (target_points.rows() <= options.normal_neighbours)
      throw InputError("icp: point_to_plane needs target normals: " + std::to_string(target_points.rows()) +
                       " target points are too few for normal_neighbours = " +
                       std::to_string(options.normal_neighbours));
    target_unit_normals = points::estimate_normals(tree, {options.normal_neighbours, 0.0}).normals;
  }
  const VertexMatrix& Q = tree.normalized_points();
  const Eigen::Vector3d target_extent = (Q.colwise().maxCoeff() - Q.colwise().minCoeff()).transpose();
  const double diagonal = std::max(target_extent.norm(), std::numeric_limits<double>::min());

  // Source in the target's frame, in Morton order (queries of nearby points follow each other).
  const VertexMatrix source_frame = frame.normalize_vertices(source_points);
  const LargeVector<int> order = morton_order(source_frame);
  VertexMatrix S(source_frame.rows(), 3);
  for (Eigen::Index k = 0; k < S.rows(); ++k) S.row(k) = source_frame.row(order[std::size_t(k)]);
  const Eigen::Vector3d source_centroid = S.colwise().mean().transpose();

  const double max_squared = options.max_distance > 0.0
                                 ? std::pow(frame.to_normalized(options.max_distance, 1), 2)
                                 : std::numeric_limits<double>::infinity();
  // The target's sample spacing (median distance to the nearest other point over up to 1024
  // points spread over it) sets the ball of the warm-started searches: 3 spacings.
  double warm_squared = 0.0;
  if (Q.rows() > 1) {
    const Eigen::Index stride = std::max<Eigen::Index>(1, Q.rows() / 1024);
    std::vector<double> spacing;
    std::uint32_t found[2];
    double squared[2];
    for (Eigen::Index i = 0; i < Q.rows(); i += stride) {
      const int k = tree.nearest(Q.row(i).data(), 2, found, squared);
      if (k == 2) spacing.push_back(squared[1]);
    }
    std::nth_element(spacing.begin(), spacing.begin() + std::ptrdiff_t(spacing.size() / 2), spacing.end());
    warm_squared = 9.0 * spacing[spacing.size() / 2];
  }
  IcpResult result;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Correspondences c;
  std::vector<std::uint64_t> seen;  // hashes of the pair sets of the iterations so far
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    progress.report(double(iteration) / double(options.max_iterations), "icp");
    correspond(tree, S, R, t, max_squared, options.trim, iteration > 0 ? warm_squared : 0.0, c);
    if (c.inliers < needed) {
      if (iteration == 0)
        throw InputError("max_distance = " + number_text(options.max_distance) + ": " +
                         std::to_string(c.inliers) + " source point(s) are within it of the target at the "
                         "start (the nearest pair is " + number_text(frame.to_input(std::sqrt(c.nearest), 1, "distance")) +
                         " apart); at least " + std::to_string(needed) + " are needed");
      break;  // lost the pairs: reported as not converged
    }
    // The same pairs as 2 to 4 iterations ago: the iteration cycles between sets of pairs that
    // differ by a few points at the rejection threshold; nothing new can come (converged).
    bool cycle = false;
    for (std::size_t back = 2; back <= 4 && back <= seen.size(); ++back)
      cycle = cycle || seen[seen.size() - back] == c.hash;
    seen.push_back(c.hash);
    if (cycle) {
      result.converged = true;
      break;
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
      const PlaneSystem s = block_sum<PlaneSystem>(S.rows(), [&](Eigen::Index i, PlaneSystem& sum) {
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
      Eigen::Matrix<double, 6, 6> JtJ = s.JtJ.selfadjointView<Eigen::Lower>();
      // A tiny damping keeps the solve defined where the target lets the source slide (a plane).
      JtJ.diagonal().array() += 1e-12 * JtJ.trace() + std::numeric_limits<double>::min();
      const Eigen::Matrix<double, 6, 1> x = JtJ.ldlt().solve(-s.Jtr);
      if (!x.allFinite()) break;
      dR = detail::rotation_from_vector(x.head<3>());
      dt = centre + x.tail<3>() - dR * centre;
    }
    R = dR * R;
    t = dR * t + dt;
    const double angle = rotation_angle([&] {
      Transform D = Transform::Identity();
      D.topLeftCorner<3, 3>() = dR;
      return D;
    }());
    const double moved = (dR * centre + dt - centre).norm();  // how far the centroid moved
    if (angle < options.tolerance && moved < options.tolerance * diagonal) {
      result.converged = true;
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
  const VertexMatrix all = options.voxel_size > 0.0 ? frame.normalize_vertices(source_start) : S;
  correspond(tree, all, R, t, max_squared, options.trim, options.voxel_size == 0.0 ? warm_squared : 0.0, c);
  result.rms = c.inliers > 0 ? frame.to_input(inlier_rms(c), 1, "rms") : std::numeric_limits<double>::infinity();
  result.inlier_fraction = double(c.inliers) / double(all.rows());
  if (c.inliers < needed) result.converged = false;
  result.inliers.assign(std::size_t(all.rows()), 0);
  for (Eigen::Index k = 0; k < all.rows(); ++k) {
    const std::size_t row = options.voxel_size > 0.0 ? std::size_t(k) : std::size_t(order[std::size_t(k)]);
    result.inliers[row] = c.inlier[std::size_t(k)];
  }
  return result;
}

IcpResult icp(const VertexRef& source, const VertexRef& target, const IcpOptions& options,
              const Progress& progress) {
  return icp(source, target, VertexMatrix(0, 3), options, progress);
}

}  // namespace meshsmith::registration
