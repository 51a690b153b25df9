#pragma once
// Internal to the deformation chapter: the best-fit rotation of a 3×3 covariance, the local step
// of ARAP and the handle rotation of Poisson editing.
#include <Eigen/Core>

namespace meshsmith::deformation::detail {

/// The rotation R ∈ SO(3) maximizing tr(Rᵀ M), i.e. minimizing Σ w ‖e′ − R e‖² for
/// M = Σ w e′ eᵀ: U diag(1, 1, det(UVᵀ)) Vᵀ from the SVD M = U Σ Vᵀ. Identity for M = 0 or a
/// non-finite M.
Eigen::Matrix3d best_rotation(const Eigen::Matrix3d& M);

}  // namespace meshsmith::deformation::detail
