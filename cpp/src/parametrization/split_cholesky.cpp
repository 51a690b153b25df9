#include "split_cholesky.h"
#include "mesh_cholesky.h"

#include <meshsmith/core/errors.h>

#include <oneapi/tbb/parallel_invoke.h>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace meshsmith::parametrization::detail {

namespace {

template <typename Scalar>
constexpr int cholmod_xtype = std::is_same_v<Scalar, double> ? CHOLMOD_REAL : CHOLMOD_COMPLEX;

/// A CHOLMOD view of an Eigen dense matrix (column-major, no copy).
template <typename Scalar>
cholmod_dense dense_view(Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>& matrix) {
  cholmod_dense view{};
  view.nrow = static_cast<std::size_t>(matrix.rows());
  view.ncol = static_cast<std::size_t>(matrix.cols());
  view.nzmax = view.nrow * view.ncol;
  view.d = view.nrow;
  view.x = matrix.data();
  view.xtype = cholmod_xtype<Scalar>;
  view.dtype = CHOLMOD_DOUBLE;
  return view;
}

}  // namespace

/// One bordered matrix Mᵢ = [Aᵢᵢ Aᵢₛ; Aₛᵢ Aₛₛ] (lower triangle, CSC) and its CHOLMOD factor.
template <typename Scalar>
struct SplitCholesky<Scalar>::Part {
  Eigen::Index begin = 0, size = 0, separator = 0;  // columns [begin, begin + size) of A; #S
  std::vector<int> starts, rows;
  std::vector<Scalar> values;
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  Dense schur_factor;  // chol(Tᵢ): the trailing #S×#S block of the factor, lower triangular

  Part() { cholmod_start(&common); }
  ~Part() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }

  /// Copies columns [begin, begin + size) and [separator_begin, n) of A's lower triangle.
  void gather(const Sparse& lower, Eigen::Index separator_begin) {
    const Eigen::Index n = lower.cols();
    separator = n - separator_begin;
    const auto local_row = [&](Eigen::Index row) {
      if (row >= begin && row < begin + size) return row - begin;
      if (row >= separator_begin) return size + row - separator_begin;
      throw std::logic_error("SplitCholesky: an entry joins the two parts");
    };
    starts.assign(1, 0);
    rows.reserve(lower.nonZeros());
    values.reserve(lower.nonZeros());
    const auto copy_column = [&](Eigen::Index column) {
      for (typename Sparse::InnerIterator it(lower, column); it; ++it) {
        rows.push_back(static_cast<int>(local_row(it.row())));
        values.push_back(it.value());
      }
      starts.push_back(static_cast<int>(rows.size()));
    };
    for (Eigen::Index c = begin; c < begin + size; ++c) copy_column(c);
    for (Eigen::Index c = separator_begin; c < n; ++c) copy_column(c);
  }

  /// Factorizes Mᵢ in the given order; false if CHOLMOD failed (`common.status` says why:
  /// CHOLMOD_NOT_POSDEF, CHOLMOD_OUT_OF_MEMORY, ...).
  bool factorize() {
    const SingleThreadedOpenMp one_thread;
    common.print = 0;
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_NATURAL;
    common.postorder = 0;  // keep the separator last (the order is a post-order already)
    configure_vertex_supernodes(common);
    cholmod_sparse matrix{};
    matrix.nrow = matrix.ncol = static_cast<std::size_t>(size + separator);
    matrix.nzmax = rows.size();
    matrix.p = starts.data();
    matrix.i = rows.data();
    matrix.x = values.data();
    matrix.stype = -1;
    matrix.itype = CHOLMOD_INT;
    matrix.xtype = cholmod_xtype<Scalar>;
    matrix.dtype = CHOLMOD_DOUBLE;
    matrix.sorted = 1;
    matrix.packed = 1;
    factor = cholmod_analyze(&matrix, &common);
    if (!factor || !cholmod_factorize(&matrix, factor, &common)) return false;
    if (common.status == CHOLMOD_OK && factor->minor < factor->n) common.status = CHOLMOD_NOT_POSDEF;
    if (common.status != CHOLMOD_OK || !factor->is_super) return false;
    const int* permutation = static_cast<const int*>(factor->Perm);
    for (std::size_t k = 0; k < factor->n; ++k) {
      if (permutation && permutation[k] != static_cast<int>(k)) throw std::logic_error("SplitCholesky: CHOLMOD reordered");
    }
    extract_schur_factor();
    return true;
  }

  /// schur_factor = rows and columns [size, size + #S) of the supernodal factor.
  void extract_schur_factor() {
    schur_factor = Dense::Zero(separator, separator);
    const int* super = static_cast<const int*>(factor->super);
    const int* row_starts = static_cast<const int*>(factor->pi);
    const int* value_starts = static_cast<const int*>(factor->px);
    const int* row_indices = static_cast<const int*>(factor->s);
    const Scalar* x = static_cast<const Scalar*>(factor->x);
    for (std::size_t s = 0; s < factor->nsuper; ++s) {
      const int first = super[s], last = super[s + 1];  // columns [first, last)
      if (last <= size) continue;
      const int n_rows = row_starts[s + 1] - row_starts[s];
      for (int column = std::max<int>(first, static_cast<int>(size)); column < last; ++column) {
        for (int r = column - first; r < n_rows; ++r) {
          const int row = row_indices[row_starts[s] + r];
          schur_factor(row - size, column - size) = x[value_starts[s] + (column - first) * n_rows + r];
        }
      }
    }
  }

  /// CHOLMOD's solve `system` (CHOLMOD_L or CHOLMOD_Lt) of the factor on y, in place.
  void triangular_solve(int system, Dense& y) const {
    cholmod_dense view = dense_view(y);
    cholmod_common& c = const_cast<cholmod_common&>(common);
    cholmod_dense* solution = cholmod_solve(system, factor, &view, &c);
    if (!solution) throw SolverError("the CHOLMOD solve failed");
    y = Eigen::Map<const Dense>(static_cast<const Scalar*>(solution->x), y.rows(), y.cols());
    cholmod_free_dense(&solution, &c);
  }
};

template <typename Scalar>
SplitCholesky<Scalar>::SplitCholesky(const Sparse& lower, Eigen::Index first_part, Eigen::Index second_part,
                                     const char* function)
    : separator_begin_(first_part + second_part) {
  const Eigen::Index n = lower.cols();
  const Eigen::Index separator = n - separator_begin_;
  for (int i = 0; i < 2; ++i) {
    parts_[i] = std::make_unique<Part>();
    parts_[i]->begin = i == 0 ? 0 : first_part;
    parts_[i]->size = i == 0 ? first_part : second_part;
    parts_[i]->gather(lower, separator_begin_);
  }
  bool factorized[2] = {false, false};
  const SingleThreadedBlas one_blas_thread;
  tbb::parallel_invoke([&] { factorized[0] = parts_[0]->factorize(); },
                       [&] { factorized[1] = parts_[1]->factorize(); });
  const auto not_positive_definite = [&] {
    return SolverError(std::string(function) + ": CHOLMOD could not factorize the system (it is not positive "
                       "definite: are the weights or the constraints degenerate?)");
  };
  for (int i = 0; i < 2; ++i) {
    if (factorized[i]) continue;
    if (parts_[i]->common.status == CHOLMOD_OUT_OF_MEMORY) {
      throw SolverError(std::string(function) + ": CHOLMOD ran out of memory factorizing the system");
    }
    throw not_positive_definite();
  }
  // A's Schur complement on S: T₁ + T₂ − Aₛₛ (lower triangles).
  Dense schur = Dense::Zero(separator, separator);
  for (Eigen::Index c = separator_begin_; c < n; ++c) {
    for (typename Sparse::InnerIterator it(lower, c); it; ++it) {
      schur(it.row() - separator_begin_, c - separator_begin_) = -it.value();
    }
  }
  for (const auto& part : parts_) schur.template selfadjointView<Eigen::Lower>().rankUpdate(part->schur_factor);
  schur_.compute(schur);
  if (schur_.info() != Eigen::Success) throw not_positive_definite();
}

template <typename Scalar>
SplitCholesky<Scalar>::~SplitCholesky() = default;

template <typename Scalar>
typename SplitCholesky<Scalar>::Dense SplitCholesky<Scalar>::solve(const Dense& b) const {
  const Eigen::Index separator = b.rows() - separator_begin_;
  const SingleThreadedBlas one_blas_thread;
  // Forward substitution in each part: y = L⁻¹ [bᵢ; 0], whose trailing block gives
  // Aₛᵢ Aᵢᵢ⁻¹ bᵢ = −chol(Tᵢ) yₛ.
  Dense y[2];
  const auto forward = [&](int i) {
    const Part& part = *parts_[i];
    y[i] = Dense::Zero(part.size + separator, b.cols());
    y[i].topRows(part.size) = b.middleRows(part.begin, part.size);
    part.triangular_solve(CHOLMOD_L, y[i]);
  };
  tbb::parallel_invoke([&] { forward(0); }, [&] { forward(1); });
  Dense separator_rhs = b.bottomRows(separator);
  for (int i = 0; i < 2; ++i) {
    separator_rhs += parts_[i]->schur_factor.template triangularView<Eigen::Lower>() * y[i].bottomRows(separator);
  }
  const Dense x_separator = schur_.solve(separator_rhs);
  // Back substitution: Lᴴ [xᵢ; xₛ] = [yᵢ; chol(Tᵢ)ᴴ xₛ] gives xᵢ = Aᵢᵢ⁻¹ (bᵢ − Aᵢₛ xₛ).
  const auto backward = [&](int i) {
    const Part& part = *parts_[i];
    y[i].bottomRows(separator) = part.schur_factor.template triangularView<Eigen::Lower>().adjoint() * x_separator;
    part.triangular_solve(CHOLMOD_Lt, y[i]);
  };
  tbb::parallel_invoke([&] { backward(0); }, [&] { backward(1); });
  Dense x(b.rows(), b.cols());
  for (int i = 0; i < 2; ++i) x.middleRows(parts_[i]->begin, parts_[i]->size) = y[i].topRows(parts_[i]->size);
  x.bottomRows(separator) = x_separator;
  return x;
}

template class SplitCholesky<double>;
template class SplitCholesky<std::complex<double>>;

}  // namespace meshsmith::parametrization::detail
