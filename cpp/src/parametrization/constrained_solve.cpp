#include "constrained_solve.h"
#include "mesh_cholesky.h"
#include "nested_dissection.h"
#include "split_cholesky.h"

#include <meshsmith/core/errors.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseLU>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <string>
#include <type_traits>

namespace meshsmith::parametrization::detail {

namespace {

/// The free variables of an N-variable system with `fixed` held.
struct FreeVariables {
  /// index[i]: position of variable i among the free ones, or −1 − (its position in `fixed`).
  std::vector<int> index;
  std::vector<int> variables;  ///< the free variables, increasing
  FreeVariables(Eigen::Index N, const std::vector<int>& fixed) : index(N, 0) {
    for (std::size_t k = 0; k < fixed.size(); ++k) index[fixed[k]] = -1 - static_cast<int>(k);
    variables.reserve(N - fixed.size());
    for (Eigen::Index i = 0; i < N; ++i) {
      if (index[i] >= 0) {
        index[i] = static_cast<int>(variables.size());
        variables.push_back(static_cast<int>(i));
      }
    }
  }
  Eigen::Index count() const { return static_cast<Eigen::Index>(variables.size()); }
};

/// Elimination order of the free block of the symmetric Q: geometric nested dissection on the
/// free variables' positions. Entry c is the free variable (its position among the free ones)
/// that becomes column c.
template <typename Scalar>
DissectionOrder dissection_order(const Eigen::SparseMatrix<Scalar>& Q, const FreeVariables& free,
                                  const VertexRef& positions) {
  const Eigen::Index n_free = free.count();
  std::vector<int> starts(n_free + 1, 0), neighbours;
  neighbours.reserve(Q.nonZeros());
  VertexMatrix points(n_free, 3);
  for (Eigen::Index k = 0; k < n_free; ++k) {
    const int variable = free.variables[k];
    points.row(k) = positions.row(variable);
    for (typename Eigen::SparseMatrix<Scalar>::InnerIterator it(Q, variable); it; ++it) {
      const int j = free.index[it.row()];
      if (j >= 0 && j != k) neighbours.push_back(j);
    }
    starts[k + 1] = static_cast<int>(neighbours.size());
  }
  return nested_dissection_order(points, {starts.data(), neighbours.data()});
}

}  // namespace

template <typename Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> solve_with_fixed(
    const Eigen::SparseMatrix<Scalar>& Q, const std::vector<int>& fixed,
    const Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& fixed_values, SystemKind kind, const char* function,
    const VertexRef* positions) {
  using Dense = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  using Sparse = Eigen::SparseMatrix<Scalar>;
  const Eigen::Index N = Q.rows(), columns = fixed_values.cols();
  const FreeVariables free(N, fixed);
  const Eigen::Index n_free = free.count();
  Dense X(N, columns);
  for (std::size_t k = 0; k < fixed.size(); ++k) X.row(fixed[k]) = fixed_values.row(k);
  if (n_free == 0) return X;

  // Column c of `block` is column free.variables[order[c]] of the given matrix restricted to the
  // free rows, renumbered by `order`: the lower triangle of P Q_FF Pᵀ for the positive definite
  // kind (CHOLMOD reads only that), all of (Q_FF)ᵀ for the general one (order = identity). The
  // fixed rows move to the right-hand side, −Q(f, p) x_p, where Q(f, p) is the conjugate of the
  // stored entry (p, f) for a symmetric / Hermitian Q and the stored entry itself for a given Qᵀ.
  const bool positive_definite = kind == SystemKind::positive_definite;
  const bool dissected = positive_definite && positions != nullptr;
  DissectionOrder dissection;
  if (dissected) {
    dissection = dissection_order(Q, free, *positions);
  } else {
    dissection.order.resize(n_free);
    std::iota(dissection.order.begin(), dissection.order.end(), 0);
  }
  const std::vector<int>& order = dissection.order;
  std::vector<int> column_of(n_free);
  for (Eigen::Index c = 0; c < n_free; ++c) column_of[order[c]] = static_cast<int>(c);
  const auto kept = [&](int row, Eigen::Index c) { return !positive_definite || row >= c; };

  Sparse block(n_free, n_free);
  Dense rhs = Dense::Zero(n_free, columns);
  std::vector<int> outer(n_free + 1, 0);
  tbb::parallel_for(Eigen::Index(0), n_free, [&](Eigen::Index c) {
    int count = 0;
    for (typename Sparse::InnerIterator it(Q, free.variables[order[c]]); it; ++it) {
      const int j = free.index[it.row()];
      count += j >= 0 && kept(column_of[j], c);
    }
    outer[c + 1] = count;
  });
  std::partial_sum(outer.begin(), outer.end(), outer.begin());
  block.resizeNonZeros(outer[n_free]);
  std::copy(outer.begin(), outer.end(), block.outerIndexPtr());
  int* rows = block.innerIndexPtr();
  Scalar* values = block.valuePtr();
  tbb::parallel_for(Eigen::Index(0), n_free, [&](Eigen::Index c) {
    int at = outer[c];
    for (typename Sparse::InnerIterator it(Q, free.variables[order[c]]); it; ++it) {
      const int j = free.index[it.row()];
      if (j < 0) {
        rhs.row(c) -= (positive_definite ? Eigen::numext::conj(it.value()) : it.value()) * fixed_values.row(-1 - j);
      } else if (kept(column_of[j], c)) {
        // Insertion into the column's sorted rows (a handful per column; already sorted when
        // the order is the identity).
        int slot = at++;
        for (; slot > outer[c] && rows[slot - 1] > column_of[j]; --slot) {
          rows[slot] = rows[slot - 1];
          values[slot] = values[slot - 1];
        }
        rows[slot] = column_of[j];
        values[slot] = it.value();
      }
    }
  });
  Dense solution;
  if (dissection.first_part > 0 && dissection.second_part > 0) {
    solution = SplitCholesky<Scalar>(block, dissection.first_part, dissection.second_part, function).solve(rhs);
  } else if (positive_definite) {
    MeshCholesky<Scalar> solver;
    configure_cholesky(solver, dissected ? CholeskyKind::vertex_laplacian_ordered : CholeskyKind::vertex_laplacian);
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
  for (Eigen::Index c = 0; c < n_free; ++c) X.row(free.variables[order[c]]) = solution.row(c);
  return X;
}

template Eigen::MatrixXd solve_with_fixed<double>(const Eigen::SparseMatrix<double>&, const std::vector<int>&,
                                                  const Eigen::MatrixXd&, SystemKind, const char*, const VertexRef*);
template Eigen::MatrixXcd solve_with_fixed<std::complex<double>>(const Eigen::SparseMatrix<std::complex<double>>&,
                                                                 const std::vector<int>&, const Eigen::MatrixXcd&,
                                                                 SystemKind, const char*, const VertexRef*);

}  // namespace meshsmith::parametrization::detail
