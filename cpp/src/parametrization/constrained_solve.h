#pragma once
// Internal to the parametrization chapter: minimizing a quadratic energy (or solving a linear
// "equilibrium" system) with some variables held fixed, the step shared by harmonic maps,
// stretch-minimizing maps and LSCM.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace meshsmith::parametrization::detail {

/// How the free block of the system is factorized.
enum class SystemKind {
  symmetric_positive_definite,  ///< Q symmetric, Q_FF positive definite: CHOLMOD
  general,                      ///< Q non-symmetric (mean-value weights): sparse LU
};

/// Solves Q_FF X_F = −Q_FP X_P for the free variables F (those not in `fixed`), column by column
/// of X, and returns the full N×c matrix X with X_P = fixed_values on the fixed rows.
/// Q: N×N, given as its TRANSPOSE in CSC (column i holds row i of Q; for a symmetric Q pass Q).
/// fixed: distinct indices in [0, N); fixed_values: #fixed×c.
/// \throw SolverError naming `function` if the factorization or the solve fails (a singular or,
/// for the symmetric kind, indefinite free block).
Eigen::MatrixXd solve_with_fixed(const Eigen::SparseMatrix<double>& Q_transposed, const std::vector<int>& fixed,
                                 const Eigen::MatrixXd& fixed_values, SystemKind kind, const char* function);

}  // namespace meshsmith::parametrization::detail
