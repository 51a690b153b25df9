// Laplacian and Taubin smoothing (laplacian_smoothing.h).
//
// Everything runs on normalized coordinates (core/normalization.h: one exact power-of-two
// scaling), so results are exactly scale-covariant and ε is compared in the same units; the
// weights are scale-invariant. The umbrella operator and the explicit step are in umbrella.cpp.
//
// Implicit steps solve (I − λU) p' = p on the moving vertices, multiplied by D so that the system
// is symmetric for symmetric weights: (D − λL)_FF p'_F = D_F p_F + λ L_FP p_P, F the moving and
// P the held vertices (whose positions never change, so the second term is computed once).
// (D − λL)_FF = D_FF + λ(−L)_FF is positive definite whenever every moving vertex has a positive
// weight sum, because −L is positive semi-definite for uniform and cot weights (also negative
// ones: it is the Dirichlet energy's matrix). It is factorized once by CHOLMOD (the core's
// MeshCholesky, supernodal, AMD) and each iteration is one solve with three right-hand sides by
// the core's SupernodalSolve (two threads, one pass over the factor for the three columns:
// CHOLMOD's own supernodal solve spent its time in OpenBLAS's packing of 3-column panels; on the
// 100k-vertex torus, cotan weights, each further iteration took 196 ms at load 7 before); the
// non-symmetric mean-value system uses Eigen's sparse LU (COLAMD ordering) instead, also
// factorized once.
#include <meshsmith/smoothing/laplacian_smoothing.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/laplacian.h>
#include <meshsmith/geometry/normals.h>

#include "../core/mesh_cholesky.h"
#include "../core/supernodal_solve.h"
#include "umbrella.h"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseLU>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <memory>
#include <string>

namespace meshsmith::smoothing {

namespace {

void check_options(const SmoothingOptions& options, const char* function) {
  if (options.iterations < 0) {
    throw InputError(std::string(function) + ": iterations = " + std::to_string(options.iterations) +
                     ": expected an integer >= 0");
  }
  validate_error_control(options.error_control, function);
}

void check_step(double value, const char* name, const char* function, bool positive) {
  if (!std::isfinite(value) || (positive ? !(value > 0.0) : !(value < 0.0))) {
    throw InputError(std::string(function) + ": " + name + " = " + number_text(value) + ": expected a finite number " +
                     (positive ? "> 0" : "< 0"));
  }
}

/// The weights' Laplacian, with row i holding vertex i's weights in column i of the result.
Eigen::SparseMatrix<double> laplacian_rows(const VertexMatrix& V, const FaceRef& F, SmoothingWeights weights) {
  switch (weights) {
    case SmoothingWeights::uniform: return geometry::uniform_laplacian(F, V.rows());
    case SmoothingWeights::cotan: return geometry::cotan_laplacian(V, F);
    case SmoothingWeights::cotan_delaunay: return geometry::intrinsic_delaunay_cotan_laplacian(V, F);
    case SmoothingWeights::mean_value: {
      Eigen::SparseMatrix<double> rows = geometry::mean_value_laplacian(V, F).transpose();
      return rows;
    }
  }
  return {};
}

/// What a run shares: normalized positions, the umbrella operator, the restriction, the bound
/// (the last two point into the others: built in place, never copied or moved).
struct Setup {
  Setup() = default;
  Setup(const Setup&) = delete;
  Setup& operator=(const Setup&) = delete;
  CoordinateFrame frame;
  VertexMatrix V;
  Eigen::SparseMatrix<double> L_rows;
  detail::Umbrella U;
  detail::Restriction restriction;
  detail::Bound bound;
};

void prepare(Setup& setup, const VertexRef& input_V, const FaceRef& F, const SmoothingOptions& options,
             const char* function) {
  validate_mesh(input_V, F);
  check_options(options, function);
  setup.frame = normalizing_frame(input_V);
  setup.V = setup.frame.normalize_vertices(input_V);
  setup.L_rows = laplacian_rows(setup.V, F, options.weights);
  setup.U = detail::umbrella_operator(setup.L_rows, options.fixed, function);
  if (options.direction != SmoothingDirection::full) {
    const bool normal = options.direction == SmoothingDirection::normal;
    const detail::Umbrella* U = &setup.U;
    // F is a view of the caller's faces, alive for the whole call.
    setup.restriction = [F, normal, U](const VertexMatrix& before, VertexMatrix& after) {
      const VertexMatrix N = geometry::vertex_normals(before, F);
      tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, before.rows(), 4096),
                        [&](const tbb::blocked_range<Eigen::Index>& range) {
        for (Eigen::Index i = range.begin(); i != range.end(); ++i) {
          if (!U->moves[i]) continue;
          const Eigen::Vector3d n = N.row(i).transpose();
          const Eigen::Vector3d d = (after.row(i) - before.row(i)).transpose();
          const double along = n.dot(d);
          if (normal) {
            after.row(i) = before.row(i) + along * n.transpose();
          } else {
            after.row(i) = before.row(i) + (d - along * n).transpose();
          }
        }
      });
    };
  }
  setup.bound.control = options.error_control;
  if (options.error_control.bound != ErrorBound::none) {
    setup.bound.control.epsilon = setup.frame.to_normalized(options.error_control.epsilon, 1);
    if (!(setup.bound.control.epsilon > 0.0)) {
      throw InputError(std::string(function) + ": the error bound " + number_text(options.error_control.epsilon) +
                       " is too small for coordinates of size 2^" + std::to_string(setup.frame.exponent));
    }
    setup.bound.original = &setup.V;
    if (options.error_control.bound == ErrorBound::error_slab) setup.bound.axes = geometry::vertex_normals(setup.V, F);
  }
}

/// The implicit step's factorized system (D − λL)_FF and its constant right-hand side part.
class ImplicitStep {
 public:
  ImplicitStep(const Eigen::SparseMatrix<double>& L_rows, const detail::Umbrella& U, double lambda,
               const VertexMatrix& start, bool symmetric)
      : symmetric_(symmetric) {
    const Eigen::Index n = U.size();
    index_.assign(n, -1);
    for (Eigen::Index i = 0; i < n; ++i)
      if (U.moves[i]) free_.push_back(static_cast<int>(i));
    for (std::size_t k = 0; k < free_.size(); ++k) index_[free_[k]] = static_cast<int>(k);
    const Eigen::Index m = static_cast<Eigen::Index>(free_.size());
    diagonal_.resize(m);
    held_.setZero(m, 3);
    // Column k of `rows` is row free_[k] of (D − λL)_FF (the matrix itself when symmetric).
    Eigen::SparseMatrix<double> rows(m, m);
    std::vector<int> counts(m);
    const int* outer = L_rows.outerIndexPtr();
    const int* inner = L_rows.innerIndexPtr();
    const double* values = L_rows.valuePtr();
    for (Eigen::Index k = 0; k < m; ++k) counts[k] = outer[free_[k] + 1] - outer[free_[k]] + 1;
    rows.reserve(counts);
    for (Eigen::Index k = 0; k < m; ++k) {
      const int i = free_[k];
      double total = 0.0;
      for (int e = outer[i]; e < outer[i + 1]; ++e) {
        const int j = inner[e];
        if (j == i) continue;
        total += values[e];
        if (index_[j] >= 0) {
          rows.insert(index_[j], k) = -lambda * values[e];
        } else {
          held_.row(k) += lambda * values[e] * start.row(j);
        }
      }
      diagonal_[k] = total;
      rows.insert(k, k) = (1.0 + lambda) * total;
    }
    rows.makeCompressed();
    if (m == 0) return;  // every vertex held: the step is the identity
    if (symmetric_) {
      cholesky_ = std::make_unique<meshsmith::detail::MeshCholesky<double>>();
      meshsmith::detail::configure_cholesky(*cholesky_, meshsmith::detail::CholeskyKind::vertex_laplacian);
      cholesky_->compute(rows);
      if (cholesky_->info() != Eigen::Success) {
        throw SolverError("laplacian_smoothing: CHOLMOD could not factorize D − λL (not positive definite)");
      }
      substitution_ = meshsmith::detail::SupernodalSolve(*cholesky_->factor());
    } else {
      lu_ = std::make_unique<Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>>();
      const Eigen::SparseMatrix<double> matrix = rows.transpose();
      lu_->compute(matrix);
      if (lu_->info() != Eigen::Success) {
        throw SolverError("laplacian_smoothing: the sparse LU factorization of D − λL failed: " + lu_->lastErrorMessage());
      }
    }
  }

  void operator()(const VertexMatrix& before, VertexMatrix& after) const {
    const Eigen::Index m = static_cast<Eigen::Index>(free_.size());
    after = before;
    if (m == 0) return;
    Eigen::MatrixXd rhs(m, 3);
    for (Eigen::Index k = 0; k < m; ++k) rhs.row(k) = diagonal_[k] * before.row(free_[k]) + held_.row(k);
    const Eigen::MatrixXd solution = symmetric_ ? substitution_.solve(rhs) : Eigen::MatrixXd(lu_->solve(rhs));
    if (!solution.allFinite()) throw SolverError("laplacian_smoothing: the implicit solve gave non-finite positions");
    for (Eigen::Index k = 0; k < m; ++k) after.row(free_[k]) = solution.row(k);
  }

 private:
  bool symmetric_;
  std::vector<int> free_, index_;
  Eigen::VectorXd diagonal_;
  Eigen::MatrixXd held_;
  std::unique_ptr<meshsmith::detail::MeshCholesky<double>> cholesky_;  ///< owns the factor substitution_ reads
  meshsmith::detail::SupernodalSolve substitution_;
  std::unique_ptr<Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>> lu_;
};

VertexMatrix finish(const Setup& setup, const VertexMatrix& result) {
  return setup.frame.vertices_to_input(result, "a smoothed position");
}

}  // namespace

VertexMatrix laplacian_smoothing(const VertexRef& V, const FaceRef& F, const LaplacianSmoothingOptions& options,
                                 const Progress& progress) {
  check_step(options.lambda, "lam", "laplacian_smoothing", true);
  Setup setup;
  prepare(setup, V, F, options, "laplacian_smoothing");
  if (options.iterations == 0) return VertexMatrix(V);
  std::vector<detail::Step> steps;
  std::shared_ptr<ImplicitStep> implicit;
  if (options.implicit) {
    progress.report(0.0, "factorizing");
    implicit = std::make_shared<ImplicitStep>(setup.L_rows, setup.U, options.lambda, setup.V,
                                              options.weights != SmoothingWeights::mean_value);
    steps.emplace_back([implicit](const VertexMatrix& before, VertexMatrix& after) { (*implicit)(before, after); });
  } else {
    const detail::Umbrella* U = &setup.U;
    const double lambda = options.lambda;
    steps.emplace_back([U, lambda](const VertexMatrix& before, VertexMatrix& after) {
      detail::explicit_step(*U, lambda, before, after);
    });
  }
  const VertexMatrix result = detail::run_steps(setup.V, options.iterations, steps, setup.restriction, setup.bound,
                                                progress, "smoothing");
  return finish(setup, result);
}

VertexMatrix taubin_smoothing(const VertexRef& V, const FaceRef& F, const TaubinOptions& options,
                              const Progress& progress) {
  check_step(options.lambda, "lam", "taubin_smoothing", true);
  check_step(options.mu, "mu", "taubin_smoothing", false);
  Setup setup;
  prepare(setup, V, F, options, "taubin_smoothing");
  if (options.iterations == 0) return VertexMatrix(V);
  const detail::Umbrella* U = &setup.U;
  std::vector<detail::Step> steps;
  for (const double factor : {options.lambda, options.mu}) {
    steps.emplace_back([U, factor](const VertexMatrix& before, VertexMatrix& after) {
      detail::explicit_step(*U, factor, before, after);
    });
  }
  const VertexMatrix result = detail::run_steps(setup.V, options.iterations, steps, setup.restriction, setup.bound,
                                                progress, "smoothing");
  return finish(setup, result);
}

}  // namespace meshsmith::smoothing
