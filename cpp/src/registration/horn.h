#pragma once
// Horn's closed-form absolute orientation (1987), shared by align() and ICP's point-to-point step:
// the rotation R maximising Σ w⟨R a'_i, b'_i⟩ is the unit quaternion of the largest eigenvalue of
// the 4×4 symmetric matrix N(H), H = Σ w a'_i b'_iᵀ the cross-covariance of the centred sets.
#include <Eigen/Core>

namespace meshsmith::registration::detail {

/// The rotation of Horn's method for the 3×3 cross-covariance H = Σ w a' b'ᵀ (any positive
/// multiple of H gives the same rotation). Always a proper rotation (det +1).
Eigen::Matrix3d horn_rotation(const Eigen::Matrix3d& H);

/// The rotation by `angle` radians about unit `axis` composed into one matrix from the small
/// rotation vector ω = angle·axis (Rodrigues' formula, exact for any |ω|; the identity for ω = 0).
Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& omega);

}  // namespace meshsmith::registration::detail
