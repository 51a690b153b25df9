#pragma once
/// \file align.h
/// The optimal rigid or similarity transform between corresponding point sets (§2.3.1; Horn,
/// "Closed-form solution of absolute orientation using unit quaternions", JOSA A 4(4), 1987):
/// the rotation is the unit quaternion of the largest eigenvalue of a 4×4 symmetric matrix built
/// from the cross-covariance of the centred point sets, the translation comes from the centroids
/// and the scale from the spreads. ICP (icp.h) solves its point-to-point step with it.
#include <meshsmith/core/types.h>

#include <Eigen/Core>

namespace meshsmith::registration {

/// A 4×4 homogeneous transform [sR t; 0 1]: x ↦ sRx + t.
using Transform = Eigen::Matrix4d;

/// The transform T that minimises Σ w_i ‖T a_i − b_i‖² over rotations R and translations t (and
/// over scales s > 0 if `with_scale`): maps row i of A onto row i of B.
/// A, B: n×3 corresponding points. weights: n non-negative weights, or empty for all 1.
/// The scale comes from the spreads, s = sqrt(Σ w‖b'_i‖² / Σ w‖a'_i‖²) (a', b' centred: Horn's
/// symmetric scale, so align(B, A) is the inverse of align(A, B)); under noise it differs from the
/// least-squares scale of Umeyama (1991), which shrinks towards 0. For noise-free data
/// B = sRA + t either way the answer is exact to round-off (about 1e-15 relative).
/// \pre n >= 3 points of positive weight, not all on one line in A nor in B.
/// \throw InputError if A or B is empty or holds a NaN/Inf, their shapes differ, a weight is
///        negative or not finite, weights has the wrong length, fewer than 3 points have positive
///        weight, or A or B is degenerate (all points identical or collinear: the rotation is then
///        not unique). Complexity O(n).
Transform align(const VertexRef& A, const VertexRef& B, const Eigen::Ref<const Eigen::VectorXd>& weights,
                bool with_scale = false);

/// The same with all weights 1.
Transform align(const VertexRef& A, const VertexRef& B, bool with_scale = false);

/// The rotation angle of the rotation part of T (radians, in [0, π]), after dividing out its scale.
double rotation_angle(const Transform& T);

}  // namespace meshsmith::registration
