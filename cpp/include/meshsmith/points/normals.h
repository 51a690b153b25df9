#pragma once
/// \file normals.h
/// Normals of point clouds (§2.2 steps 1 and 2; "Regression Line (Normal Estimation)" of §1):
/// unoriented normals by PCA of each point's neighbourhood, then a consistent orientation by
/// propagation along a minimum spanning tree of the kNN graph (Hoppe et al. 1992, "Surface
/// reconstruction from unorganized points").
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/points/kd_tree.h>

namespace meshsmith::points {

struct NormalEstimationOptions {
  /// Neighbourhood of point i: i itself and its k nearest other points (k + 1 points). k >= 3.
  int k = 16;
  /// If > 0, the neighbourhood is instead every point at distance < radius from i (i included);
  /// a ball holding fewer than 3 points is replaced by i's 3 nearest points (i included).
  double radius = 0.0;
};

struct NormalEstimate {
  /// n×3 unit normals, unoriented (the sign is arbitrary; see orient_normals).
  VertexMatrix normals;
  /// n surface variations λ0 / (λ0 + λ1 + λ2) of the neighbourhood covariance (λ0 smallest):
  /// 0 for a plane, at most 1/3 (isotropic); a quality measure of each normal.
  Eigen::VectorXd surface_variation;
};

/// PCA normal estimation: normal i is the eigenvector of the smallest eigenvalue of the centred
/// covariance M = Σ (p_j − c)(p_j − c)ᵀ of i's neighbourhood (c its centroid). The 3×3
/// eigenproblem is solved in closed form (Eigen's computeDirect), and re-solved iteratively where
/// the closed form's residual is not at round-off level.
/// Degenerate neighbourhoods (all points coincide up to 1e-12 × the bounding-box diagonal, or
/// × 1e-2 of the largest coordinate when that is larger: a cloud of identical points) get
/// the fallback normal (0, 0, 1) and surface variation 1/3; collinear ones get some unit normal
/// perpendicular to the line. Never NaN.
/// P: n×3 points. Parallel over points; the result does not depend on the thread count.
/// \pre n >= k + 1 (kNN neighbourhoods) or n >= 3 (radius neighbourhoods).
/// \throw InputError if P is empty or holds a NaN/Inf, k < 3, n <= k, or radius is negative/NaN.
NormalEstimate estimate_normals(const VertexRef& P, const NormalEstimationOptions& options = {},
                                const Progress& progress = {});

/// The same on the points of a prebuilt tree (reuse it for kNN queries elsewhere).
NormalEstimate estimate_normals(const KdTree& tree, const NormalEstimationOptions& options = {},
                                const Progress& progress = {});

struct NormalOrientationOptions {
  /// Graph: each point joined to its k nearest other points (symmetrised). k >= 1.
  int k = 16;
  /// Edge cost α‖p_i − p_j‖/h + β(1 − |⟨n_i, n_j⟩|), h the mean kNN edge length (so α is
  /// scale-free). α, β >= 0, α + β > 0; only their ratio matters (§2.2 takes α + β = 1).
  double alpha = 0.1;
  double beta = 0.9;
  /// Each connected component of the graph is seeded at its point with the largest coordinate
  /// along this axis (0, 1, 2 = x, y, z; ties: lowest index), whose normal is made to point
  /// towards +axis: outward for a closed surface.
  int axis = 2;
};

/// Consistent orientation of unoriented normals (§2.2 step 2, orientation propagation): builds
/// the symmetrised kNN graph with the cost above, grows a minimum spanning tree (Prim) from the
/// seed of each connected component, and flips each normal to agree (⟨n_parent, n_child⟩ >= 0)
/// with its parent in the tree. Returns N with some rows negated (lengths untouched).
/// P: n×3 points, N: n×3 normals (any nonzero length). Deterministic.
/// \throw InputError if P or N holds a NaN/Inf, shapes differ, a normal is zero, k < 1,
///        n <= k, axis outside {0, 1, 2}, or α, β are negative or both zero.
VertexMatrix orient_normals(const VertexRef& P, const VertexRef& N,
                            const NormalOrientationOptions& options = {},
                            const Progress& progress = {});

}  // namespace meshsmith::points
