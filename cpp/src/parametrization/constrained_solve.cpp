#include "constrained_solve.h"

#include <meshsmith/core/errors.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseLU>

#include <string>

namespace meshsmith::parametrization::detail {

Eigen::MatrixXd solve_with_fixed(const Eigen::SparseMatrix<double>& Q_transposed, const std::vector<int>& fixed,
                                 const Eigen::MatrixXd& fixed_values, SystemKind kind, const char* function) {
  const Eigen::Index N = Q_transposed.rows(), columns = fixed_values.cols();
  // free_index[i]: position of variable i among the free ones (0 until numbered), or
  // −1 − (its position in `fixed`).
  std::vector<int> free_index(N, 0);
  for (std::size_t k = 0; k < fixed.size(); ++k) free_index[fixed[k]] = -1 - static_cast<int>(k);
  std::vector<int> free_variables;
  free_variables.reserve(N - fixed.size());
  for (Eigen::Index i = 0; i < N; ++i) {
    if (free_index[i] >= 0) {
      free_index[i] = static_cast<int>(free_variables.size());
      free_variables.push_back(static_cast<int>(i));
    }
  }
  const Eigen::Index n_free = static_cast<Eigen::Index>(free_variables.size());
  Eigen::MatrixXd X(N, columns);
  for (std::size_t k = 0; k < fixed.size(); ++k) X.row(fixed[k]) = fixed_values.row(k);
  if (n_free == 0) return X;

  // Column k of A_transposed holds row free_variables[k] of Q restricted to the free variables;
  // the fixed ones move to the right-hand side. Row order is preserved (the map is monotone).
  Eigen::SparseMatrix<double> A_transposed(n_free, n_free);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n_free, columns);
  std::vector<int> outer(n_free + 1, 0);
  for (Eigen::Index k = 0; k < n_free; ++k) {
    int count = 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q_transposed, free_variables[k]); it; ++it) {
      count += free_index[it.row()] >= 0;
    }
    outer[k + 1] = outer[k] + count;
  }
  A_transposed.resizeNonZeros(outer[n_free]);
  std::copy(outer.begin(), outer.end(), A_transposed.outerIndexPtr());
  for (Eigen::Index k = 0; k < n_free; ++k) {
    int at = outer[k];
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q_transposed, free_variables[k]); it; ++it) {
      const int j = free_index[it.row()];
      if (j >= 0) {
        A_transposed.innerIndexPtr()[at] = j;
        A_transposed.valuePtr()[at++] = it.value();
      } else {
        rhs.row(k) -= it.value() * fixed_values.row(-1 - j);
      }
    }
  }
  Eigen::MatrixXd solution;
  if (kind == SystemKind::symmetric_positive_definite) {
    Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> solver;
    solver.compute(A_transposed);
    if (solver.info() != Eigen::Success) {
      throw SolverError(std::string(function) + ": CHOLMOD could not factorize the system (it is not positive "
                        "definite: are the weights or the constraints degenerate?)");
    }
    solution = solver.solve(rhs);
    if (solver.info() != Eigen::Success) throw SolverError(std::string(function) + ": the CHOLMOD solve failed");
  } else {
    const Eigen::SparseMatrix<double> A = A_transposed.transpose();
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
    solver.compute(A);
    if (solver.info() != Eigen::Success) {
      throw SolverError(std::string(function) + ": the sparse LU factorization failed (singular system): " +
                        solver.lastErrorMessage());
    }
    solution = solver.solve(rhs);
    if (solver.info() != Eigen::Success) throw SolverError(std::string(function) + ": the sparse LU solve failed");
  }
  if (!solution.allFinite()) throw SolverError(std::string(function) + ": the solve produced non-finite values");
  for (Eigen::Index k = 0; k < n_free; ++k) X.row(free_variables[k]) = solution.row(k);
  return X;
}

}  // namespace meshsmith::parametrization::detail
