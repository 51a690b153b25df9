#pragma once
// Internal to the parametrization chapter: minimizing a quadratic energy (or solving a linear
// "equilibrium" system) with some variables held fixed, the step shared by harmonic maps,
// stretch-minimizing maps and LSCM.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <complex>
#include <vector>

namespace meshsmith::parametrization::detail {

/// How the free block of the system is factorized.
enum class SystemKind {
  /// Q symmetric (real) or Hermitian (complex), Q_FF positive definite: CHOLMOD's
  /// supernodal LLᵀ with AMD ordering (mesh_cholesky.h says why).
  positive_definite,
  general,  ///< Q non-symmetric (mean-value weights): sparse LU (real only)
};

/// Solves Q_FF X_F = −Q_FP X_P for the free variables F (those not in `fixed`), column by column
/// of X, and returns the full N×c matrix X with X_P = fixed_values on the fixed rows.
/// Q: N×N in CSC; for the general kind pass Qᵀ (column i holds row i of Q), for the positive
/// definite kind pass Q itself (its columns are the conjugated rows).
/// fixed: distinct indices in [0, N); fixed_values: #fixed×c.
/// \throw SolverError naming `function` if the factorization or the solve fails (a singular or
/// indefinite free block).
template <typename Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> solve_with_fixed(
    const Eigen::SparseMatrix<Scalar>& Q, const std::vector<int>& fixed,
    const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& fixed_values, SystemKind kind, const char* function);

extern template Eigen::MatrixXd solve_with_fixed<double>(const Eigen::SparseMatrix<double>&, const std::vector<int>&,
                                                         const Eigen::MatrixXd&, SystemKind, const char*);
extern template Eigen::MatrixXcd solve_with_fixed<std::complex<double>>(
    const Eigen::SparseMatrix<std::complex<double>>&, const std::vector<int>&, const Eigen::MatrixXcd&, SystemKind,
    const char*);

}  // namespace meshsmith::parametrization::detail
