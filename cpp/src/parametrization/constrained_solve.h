#pragma once
// Internal to the parametrization chapter: minimizing a quadratic energy (or solving a linear
// "equilibrium" system) with some variables held fixed, the step shared by harmonic maps,
// stretch-minimizing maps and LSCM.
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>
#include <meshsmith/parametrization/boundary_map.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <complex>
#include <vector>

namespace meshsmith::parametrization::detail {

/// How the free block of the system is factorized.
enum class SystemKind {
  /// Q symmetric (real) or Hermitian (complex), Q_FF positive definite: CHOLMOD's
  /// supernodal LLᵀ (mesh_cholesky.h says why).
  positive_definite,
  general,  ///< Q non-symmetric (mean-value weights): sparse LU (real only)
};

/// Solves Q_FF X_F = −Q_FP X_P for the free variables F (those not in `fixed`), column by column
/// of X, and returns the full N×c matrix X with X_P = fixed_values on the fixed rows.
/// Q: N×N in CSC; for the general kind pass Qᵀ (column i holds row i of Q), for the positive
/// definite kind pass Q itself (its columns are the conjugated rows; both triangles stored).
/// fixed: distinct indices in [0, N); fixed_values: #fixed×c.
/// positions: optional N×3 positions of the variables (one variable per mesh vertex); given,
/// a positive definite free block is ordered by geometric nested dissection
/// (nested_dissection.h) and its two halves are factorized side by side (split_cholesky.h),
/// otherwise it is ordered by AMD and factorized in one piece (mesh_cholesky.h).
/// \throw SolverError naming `function` if the factorization or the solve fails (a singular or
/// indefinite free block).
template <typename Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> solve_with_fixed(
    const Eigen::SparseMatrix<Scalar>& Q, const std::vector<int>& fixed,
    const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& fixed_values, SystemKind kind, const char* function,
    const VertexRef* positions = nullptr);

/// The harmonic map of the Laplacian L (harmonic_from_laplacian) with `boundary` fixed; given
/// the #V×3 vertex positions, its free block is ordered by nested dissection.
/// \throw InputError for a bad boundary or positions not matching L; SolverError as above.
geometry::ParameterMatrix solve_harmonic(const Eigen::SparseMatrix<double>& L, const BoundaryMap& boundary,
                                         bool symmetric, const VertexRef* positions);

extern template Eigen::MatrixXd solve_with_fixed<double>(const Eigen::SparseMatrix<double>&, const std::vector<int>&,
                                                         const Eigen::MatrixXd&, SystemKind, const char*,
                                                         const VertexRef*);
extern template Eigen::MatrixXcd solve_with_fixed<std::complex<double>>(
    const Eigen::SparseMatrix<std::complex<double>>&, const std::vector<int>&, const Eigen::MatrixXcd&, SystemKind,
    const char*, const VertexRef*);

}  // namespace meshsmith::parametrization::detail
