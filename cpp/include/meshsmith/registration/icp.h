#pragma once
/// \file icp.h
/// Iterative closest points (§2.3.1; Besl & McKay 1992 point-to-point, Chen & Medioni 1992
/// point-to-plane; trimmed ICP after Chetverikov et al. 2002): the rigid transform that maps a
/// source point set onto a target point set, alternating closest-point correspondences (the
/// points chapter's kd-tree, built once on the target) with the optimal transform for them
/// (Horn's method, align.h, or the linearised point-to-plane least squares).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/registration/align.h>

#include <string>
#include <utility>
#include <vector>

namespace meshsmith::registration {

enum class IcpMethod {
  point_to_point,  ///< minimise Σ ‖T p − q‖² (Horn's closed form each iteration)
  point_to_plane,  ///< minimise Σ ⟨T p − q, n_q⟩² (linearised rotation, one 6×6 solve each iteration)
};

struct IcpOptions {
  IcpMethod method = IcpMethod::point_to_point;
  /// At most this many correspondence/transform iterations (>= 1).
  int max_iterations = 50;
  /// Converged ("tolerance") when one iteration moves the source by less than this: rotation
  /// angle in radians and translation as a fraction of the target's bounding-box diagonal (> 0).
  double tolerance = 1e-6;
  /// Converged ("relative_change", Open3D's relative_rmse / relative_fitness, here as true
  /// relative changes) when, from one iteration to the next, the inlier RMS changes by at most
  /// relative_rmse of itself and the inlier count by at most relative_fitness of itself (>= 0;
  /// relative_rmse = 0: this test off).
  double relative_rmse = 1e-6;
  double relative_fitness = 1e-6;
  /// Cycle and stall detection over a window of the last `patience` iterations (0: off, else
  /// >= 2). Converged ("cycle") when the pairs repeat those of 2 .. patience iterations earlier,
  /// or the pose comes back to within `tolerance` of one of them; converged ("stalled") when no
  /// iteration of the last `patience` lowered the least RMS so far by more than relative_rmse of
  /// it nor raised the most inliers so far by more than relative_fitness of it. Both are an
  /// oscillation between pair sets that differ at a rejection threshold (trim, max_distance), at
  /// the noise level: no further iteration improves on it. The result is then the pose of least
  /// inlier RMS among the last `patience` iterations.
  int patience = 10;
  /// Pairs farther apart than this (input length units) are outliers; 0: no distance limit.
  double max_distance = 0.0;
  /// Trimmed ICP: only this fraction (0, 1] of the pairs within max_distance, the closest ones,
  /// is used in each iteration; 1: all of them.
  double trim = 1.0;
  /// If > 0, source and target are first reduced to one point (the centroid) per occupied cube
  /// of this edge length (see voxel_downsample); the reduction is done once. 0: no reduction.
  double voxel_size = 0.0;
  /// Normal compatibility (Rusinkiewicz & Levoy 2001): if > 0, a pair whose normals (the source
  /// normal turned by the current rotation, and the target normal) differ by more than this angle
  /// (radians, in (0, π/2]) is rejected, like a pair beyond max_distance, before trimming. Normals
  /// are compared as lines (either sign): estimated normals are unoriented. 0: off.
  double normal_angle = 0.0;
  /// Neighbours for the normals estimated (PCA) when none are given: the target's for
  /// point-to-plane or normal_angle, the source's for normal_angle (>= 3).
  int normal_neighbours = 16;
  /// The start: source points are mapped by it before the first iteration (a 4×4 affine
  /// transform, last row 0 0 0 1). The result includes it.
  Transform initial = Transform::Identity();
};

struct IcpResult {
  Transform transform;             ///< 4×4, maps the source onto the target (includes `initial`)
  double rms = 0.0;                ///< RMS distance of the inlier pairs at `transform`
  int iterations = 0;              ///< iterations run
  bool converged = false;          ///< a convergence test was met before max_iterations (see `stop`)
  /// Why the iterations stopped: converged by "tolerance", "relative_change", "cycle" or
  /// "stalled" (IcpOptions); not converged: "max_iterations", "lost_pairs" (fewer than 3 pairs,
  /// 6 for point-to-plane, within max_distance after the first iteration) or "singular" (the
  /// point-to-plane system had no finite solution).
  std::string stop;
  double inlier_fraction = 0.0;    ///< inliers / source points at `transform`
  std::vector<double> rms_history; ///< RMS of the inlier pairs at the start of each iteration
  std::vector<char> inliers;       ///< per source point (input rows): 1 if its pair is an inlier at `transform`
};

/// Rigid ICP from source (n×3) onto target (m×3).
/// target_normals: m×3 normals of the target (any nonzero length, either sign) for
/// point-to-plane or normal_angle, or an empty matrix to estimate them by PCA over
/// `normal_neighbours` neighbours (points/normals.h) on the (reduced) target once; ignored
/// otherwise. source_normals: the same for the source (n×3, in the source's own frame: `initial`
/// turns them), used by normal_angle only.
/// Deterministic: the result does not depend on the thread count (sums run in fixed blocks).
/// Not converging within max_iterations, or losing all pairs after the first iteration, is
/// reported (converged = false), never an exception.
/// \pre the start is close enough for closest points to lead to the right alignment (ICP is
///      local: about 30° and a tenth of the size for smooth shapes).
/// \throw InputError if source or target is empty or holds a NaN/Inf, target_normals has the
///        wrong shape or a zero or non-finite row (source_normals too), an option is out of
///        range (max_iterations < 1, tolerance <= 0, relative_rmse or relative_fitness < 0,
///        patience 1 or < 0, max_distance < 0, trim outside (0, 1],
///        voxel_size < 0, normal_angle outside [0, π/2], normal_neighbours < 3), `initial` is not
///        a finite affine transform, fewer than 3 points remain after the voxel reduction, or no
///        pair is within max_distance (and normal_angle) at the start. Cancelled through `progress`.
/// Complexity: O((n + m) log m) for the set-up, O(n log m) per iteration.
IcpResult icp(const VertexRef& source, const VertexRef& target, const VertexRef& source_normals,
              const VertexRef& target_normals, const IcpOptions& options, const Progress& progress = {});

/// The same with no source normals given (estimated when normal_angle needs them).
IcpResult icp(const VertexRef& source, const VertexRef& target, const VertexRef& target_normals,
              const IcpOptions& options = {}, const Progress& progress = {});

/// The same with no target normals given (estimated when point-to-plane needs them).
IcpResult icp(const VertexRef& source, const VertexRef& target, const IcpOptions& options = {},
              const Progress& progress = {});

/// How icp_multi() brings the scans into one frame.
enum class MultiStrategy {
  growing,     ///< each scan onto the union of the others (a growing model, then refinement rounds)
  pose_graph,  ///< pairwise ICP between overlapping scans, then a global least squares over the poses
};

/// Options of icp_multi().
struct IcpMultiOptions {
  MultiStrategy strategy = MultiStrategy::growing;
  /// The options of every pairwise registration (its `initial` is ignored: see `initial` below;
  /// its voxel_size reduces each scan once).
  IcpOptions icp;
  /// Start poses, one 4×4 transform per scan (into the common frame), or empty for the identity.
  std::vector<Transform> initial;
  /// growing: refinement rounds after the sequential pass (>= 0): each round re-registers every
  /// scan but the first onto the union of all the others at their current poses.
  /// pose_graph: at most this many iterations of the global solve (>= 1 there).
  int rounds = 10;
  /// The rounds stop once no pose moved by more than this in a round: rotation in radians and
  /// translation in diagonals of the largest scan (> 0). The poses settle slowly (each scan's
  /// fit moves the others' targets), so this is coarser than icp.tolerance.
  double round_tolerance = 1e-3;
  /// pose_graph: scans i < j are an edge of the graph when, after registering scan j onto scan i
  /// by icp() (from their start poses), at least `min_overlap` (in (0, 1]) of scan j's points lie
  /// within `overlap_distance` (input units, > 0; 0: 0.5% of the largest scan's diagonal; about
  /// 2–3 times the noise suits) of scan i; those points are the edge's samples.
  double overlap_distance = 0.0;
  double min_overlap = 0.2;
  /// pose_graph: at most this many correspondences per edge enter the global solve (evenly
  /// spaced among them, >= 3).
  int edge_samples = 2000;
};

/// Result of icp_multi().
struct IcpMultiResult {
  std::vector<Transform> transforms;    ///< per scan: maps it into the common frame (the first scan's start frame)
  std::vector<double> rms;              ///< per scan: RMS of its inlier pairs with the union of the others at the end
  std::vector<double> inlier_fraction;  ///< per scan: its inlier pairs / its (reduced) points
  std::vector<char> scan_converged;     ///< per scan: its last registration converged (the first: 1)
  int rounds = 0;                       ///< refinement rounds run (pose_graph: Gauss–Newton iterations)
  bool converged = false;               ///< every registration converged and the last round moved no pose more than round_tolerance
  /// pose_graph: the edges (i, j), i < j, of the graph, in lexicographic order; growing: empty.
  std::vector<std::pair<int, int>> edges;
};

/// Registration of k >= 2 scans into one frame (§2.3.1).
///
/// strategy pose_graph (multi-view registration as a pose graph, after Pulli 1999 and Lu &
/// Milios 1997): every pair of scans i < j is registered by icp() (scan j onto scan i, from
/// their start poses; not when icp.max_distance is set and fewer than 6 points of scan j are
/// within it of scan i at the start); a pair where at least min_overlap of scan j's points then
/// lie within overlap_distance of scan i (see IcpMultiOptions) is an edge, those points of scan
/// j (at most edge_samples) its samples. The poses start from the pairwise results composed
/// along a spanning tree grown from scan 0, then a multi-view ICP refines all of them at once:
/// each iteration pairs every edge's samples with their closest points in scan i at the
/// current poses (within overlap_distance), and takes one Gauss–Newton step of
/// Σ_edges Σ_pairs ‖X_i p − X_j q‖² (point-to-plane: ⟨X_i p − X_j q, n_p⟩²) over the poses
/// X_1 .. X_{k−1} (X_0 stays), rotations linearised about the centroid of scan 0 (then the exact
/// rotation); at most `rounds` iterations, until no pose moves by more than round_tolerance.
/// The error is spread over every loop of the graph at once, not along the order of the
/// scans. A scan with no path of edges to scan 0 keeps its start pose and is reported
/// (scan_converged 0, converged false); so is a scan with an edge whose pairwise ICP did not
/// converge.
///
/// strategy growing (the sequential registration to a growing model of Chen & Medioni 1992, refined by registering each scan to all the others, as
/// in Bergevin et al. 1996 and Pulli 1999). The first scan anchors the frame (its pose stays
/// `initial[0]`, the identity by default). Sequential pass: scan i (i = 1 .. k−1), from its start
/// pose, is registered by icp() onto the union of scans 0 .. i−1 at their poses so far (the model
/// grows). Then up to `rounds` refinement rounds: each scan i >= 1 in turn, onto the union of all
/// the others at their current poses (so errors accumulated along the sequence are spread out and
/// loops close); the rounds stop early once no pose moves by more than round_tolerance. Per scan, once: the voxel reduction and (when the method or normal_angle needs
/// them) the PCA normals, turned with the pose into the union's normals.
/// Scans overlap only partly, so set icp.trim (e.g. 0.6) or icp.max_distance.
/// Deterministic (independent of the thread count). Non-convergence is reported, not thrown.
/// \pre every pair of consecutive scans in the list (or a scan and the union of the earlier ones)
///      overlaps and starts within ICP's reach.
/// \throw InputError if fewer than 2 scans are given, `initial` has neither 0 nor k entries or a
///        non-affine entry, rounds < 0 (< 1 for pose_graph), round_tolerance not positive,
///        overlap_distance < 0, min_overlap outside (0, 1], edge_samples < 3, or as icp() for a scan or the options (naming the scan).
///        Cancelled through `progress`.
IcpMultiResult icp_multi(const std::vector<VertexMatrix>& scans, const IcpMultiOptions& options = {},
                         const Progress& progress = {});

/// One point per occupied cube of edge `voxel_size` of a grid anchored at the points' minimum
/// corner: the centroid of the points in it, in the order of the cubes' (x, y, z) integer
/// coordinates (lexicographic), so the output is deterministic.
/// \throw InputError if P is empty or holds a NaN/Inf, voxel_size is not positive and finite,
///        or the grid would need 2^21 cubes or more along an axis.
VertexMatrix voxel_downsample(const VertexRef& P, double voxel_size);

}  // namespace meshsmith::registration
