#include "constrained_solve.h"
#include "mesh_cholesky.h"

#include <meshsmith/core/errors.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseLU>

#include <string>
#include <type_traits>

namespace meshsmith::parametrization::detail {

template <typename Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> solve_with_fixed(
    const Eigen::SparseMatrix<Scalar>& Q, const std::vector<int>& fixed,
    const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& fixed_values, SystemKind kind, const char* function) {
  using Dense = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  using Sparse = Eigen::SparseMatrix<Scalar>;
  const Eigen::Index N = Q.rows(), columns = fixed_values.cols();
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
  Dense X(N, columns);
  for (std::size_t k = 0; k < fixed.size(); ++k) X.row(fixed[k]) = fixed_values.row(k);
  if (n_free == 0) return X;

  // Column k of `block` is column free_variables[k] of the given matrix restricted to the free
  // rows: Q_FF for the positive definite kind, (Q_FF)ᵀ for the general one. The fixed rows move
  // to the right-hand side, −Q(f, p) x_p, where Q(f, p) is the conjugate of the stored entry
  // (p, f) for a symmetric / Hermitian Q and the stored entry itself for a given Qᵀ.
  // Row order is preserved (the numbering of the free variables is monotone).
  const bool transposed = kind == SystemKind::general;
  Sparse block(n_free, n_free);
  Dense rhs = Dense::Zero(n_free, columns);
  std::vector<int> outer(n_free + 1, 0);
  for (Eigen::Index k = 0; k < n_free; ++k) {
    int count = 0;
    for (typename Sparse::InnerIterator it(Q, free_variables[k]); it; ++it) {
      count += free_index[it.row()] >= 0;
    }
    outer[k + 1] = outer[k] + count;
  }
  block.resizeNonZeros(outer[n_free]);
  std::copy(outer.begin(), outer.end(), block.outerIndexPtr());
  for (Eigen::Index k = 0; k < n_free; ++k) {
    int at = outer[k];
    for (typename Sparse::InnerIterator it(Q, free_variables[k]); it; ++it) {
      const int j = free_index[it.row()];
      if (j >= 0) {
        block.innerIndexPtr()[at] = j;
        block.valuePtr()[at++] = it.value();
      } else {
        rhs.row(k) -= (transposed ? it.value() : Eigen::numext::conj(it.value())) * fixed_values.row(-1 - j);
      }
    }
  }
  Dense solution;
  if (kind == SystemKind::positive_definite) {
    MeshCholesky<Scalar> solver;
    configure_cholesky(solver, CholeskyKind::vertex_laplacian);
    solver.compute(block);
    if (solver.info() != Eigen::Success) {
      throw SolverError(std::string(function) + ": CHOLMOD could not factorize the system (it is not positive "
                        "definite: are the weights or the constraints degenerate?)");
    }
    solution = solver.solve(rhs);
    if (solver.info() != Eigen::Success) throw SolverError(std::string(function) + ": the CHOLMOD solve failed");
  } else if constexpr (std::is_same_v<Scalar, double>) {
    const Sparse A = block.transpose();
    Eigen::SparseLU<Sparse> solver;
    solver.compute(A);
    if (solver.info() != Eigen::Success) {
      throw SolverError(std::string(function) + ": the sparse LU factorization failed (singular system): " +
                        solver.lastErrorMessage());
    }
    solution = solver.solve(rhs);
    if (solver.info() != Eigen::Success) throw SolverError(std::string(function) + ": the sparse LU solve failed");
  } else {
    throw SolverError(std::string(function) + ": complex systems must be Hermitian positive definite");
  }
  if (!solution.allFinite()) throw SolverError(std::string(function) + ": the solve produced non-finite values");
  for (Eigen::Index k = 0; k < n_free; ++k) X.row(free_variables[k]) = solution.row(k);
  return X;
}

template Eigen::MatrixXd solve_with_fixed<double>(const Eigen::SparseMatrix<double>&, const std::vector<int>&,
                                                  const Eigen::MatrixXd&, SystemKind, const char*);
template Eigen::MatrixXcd solve_with_fixed<std::complex<double>>(const Eigen::SparseMatrix<std::complex<double>>&,
                                                                 const std::vector<int>&, const Eigen::MatrixXcd&,
                                                                 SystemKind, const char*);

}  // namespace meshsmith::parametrization::detail
