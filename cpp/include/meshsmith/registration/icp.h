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
  /// Converged when one iteration moves the source by less than this: rotation angle in radians
  /// and translation as a fraction of the target's bounding-box diagonal (> 0); or when the
  /// pairs repeat those of 2 to 4 iterations earlier (a cycle between pair sets that differ at
  /// the rejection threshold: no further iteration can improve on it).
  double tolerance = 1e-6;
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
  bool converged = false;          ///< the tolerance was met before max_iterations
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
///        range (max_iterations < 1, tolerance <= 0, max_distance < 0, trim outside (0, 1],
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

/// Options of icp_multi().
struct IcpMultiOptions {
  /// The options of every pairwise registration (its `initial` is ignored: see `initial` below;
  /// its voxel_size reduces each scan once).
  IcpOptions icp;
  /// Start poses, one 4×4 transform per scan (into the common frame), or empty for the identity.
  std::vector<Transform> initial;
  /// Refinement rounds after the sequential pass (>= 0): each round re-registers every scan but
  /// the first onto the union of all the others at their current poses.
  int rounds = 10;
  /// The rounds stop once no pose moved by more than this in a round: rotation in radians and
  /// translation in diagonals of the largest scan (> 0). The poses settle slowly (each scan's
  /// fit moves the others' targets), so this is coarser than icp.tolerance.
  double round_tolerance = 1e-3;
};

/// Result of icp_multi().
struct IcpMultiResult {
  std::vector<Transform> transforms;    ///< per scan: maps it into the common frame (the first scan's start frame)
  std::vector<double> rms;              ///< per scan: RMS of its inlier pairs with the union of the others at the end
  std::vector<double> inlier_fraction;  ///< per scan: its inlier pairs / its (reduced) points
  std::vector<char> scan_converged;     ///< per scan: its last registration converged (the first: 1)
  int rounds = 0;                       ///< refinement rounds run
  bool converged = false;               ///< every registration converged and the last round moved no pose more than round_tolerance
};

/// Registration of k >= 2 scans into one frame (§2.3.1; the sequential registration to a
/// growing model of Chen & Medioni 1992, refined by registering each scan to all the others, as
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
///        non-affine entry, rounds < 0, round_tolerance not positive, or as icp() for a scan or the options (naming the scan).
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
