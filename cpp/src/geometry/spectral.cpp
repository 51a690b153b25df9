#include <meshsmith/geometry/spectral.h>

#include <meshsmith/core/normalization.h>

#include <meshsmith/core/errors.h>

#include "triangle_corners.h"

#include <Eigen/CholmodSupport>
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <numeric>
#include <sstream>
#include <vector>

namespace meshsmith::geometry {

namespace {

// y = (A − σB)⁻¹ x for Spectra's shift-and-invert mode, with A − σB factorised once by CHOLMOD
// (A = −L is positive semi-definite and σ < 0, so A − σB is positive definite).
class CholmodShiftInvert {
 public:
  using Scalar = double;

  CholmodShiftInvert(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& B,
                     const Progress& progress)
      : A_(A), B_(B), progress_(progress) {}

  Eigen::Index rows() const { return A_.rows(); }
  Eigen::Index cols() const { return A_.cols(); }

  void set_shift(double sigma) {
    shifted_ = A_ - sigma * B_;
    solver_.compute(shifted_);
    if (solver_.info() != Eigen::Success) {
      throw SolverError("laplacian_eigenpairs: CHOLMOD could not factorise −L − σM (is the mesh "
                        "free of degenerate triangles?)");
    }
  }

  void perform_op(const double* x_in, double* y_out) const {
    ++applications_;
    progress_.report(std::min(0.95, 0.1 + 0.85 * (1.0 - 1.0 / (1.0 + applications_ / 50.0))),
                     "Lanczos iterations");
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    y = solver_.solve(x);
  }

 private:
  const Eigen::SparseMatrix<double>& A_;
  const Eigen::SparseMatrix<double>& B_;
  const Progress& progress_;
  Eigen::SparseMatrix<double> shifted_;
  Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
  mutable long applications_ = 0;
};

}  // namespace

LaplacianEigenpairs laplacian_eigenpairs(const VertexRef& input_V, const FaceRef& F, Eigen::Index k,
                                         MassMatrixType mass, const Progress& progress) {
  detail::validate_surface(input_V, F);
  // On normalized coordinates (core/normalization.h): the shift-invert solve and its tolerances
  // need masses near 1 (at 1e±150 they under- or overflow the Lanczos iteration). Eigenvalues
  // scale as length^-2 and M-orthonormal vectors as length^-1, both mapped back exactly.
  const CoordinateFrame frame = normalizing_frame(input_V);
  const VertexMatrix V = frame.normalize_vertices(input_V);
  const Eigen::Index n = V.rows();
  if (k < 1 || k >= n) {
    throw InputError("k = " + std::to_string(k) + " eigenpairs requested: expected 1 <= k < #V = " +
                     std::to_string(n));
  }
  const Eigen::SparseMatrix<double> M = mass_matrix(V, F, mass);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(M.valuePtr()[i] > 0.0)) {
      std::ostringstream message;
      message << "vertex " << i << " has zero area (used by no non-degenerate face): the mass "
              << "matrix must be positive definite; remove unreferenced vertices first";
      throw InputError(message.str());
    }
  }
  progress.report(0.0, "assembling");
  const Eigen::SparseMatrix<double> A = -cotan_laplacian(V, F);
  // Any σ < 0 puts the k smallest eigenvalues first in shift-and-invert mode; a small one (on the
  // scale of the first non-zero eigenvalue, ~1/area) keeps the iteration fast.
  const double sigma = -1e-2 / M.sum();
  CholmodShiftInvert op(A, M, progress);
  Spectra::SparseSymMatProd<double> mass_product(M);
  // Lanczos from one start vector finds a multiple eigenvalue's copies only through round-off,
  // so it can stop before it has all 2l+1 copies of a cluster (it happens on spheres). Asking
  // for a margin of extra pairs and keeping the k smallest makes that far less likely.
  const Eigen::Index wanted = std::min(n - 1, k + std::max<Eigen::Index>(10, k / 2));
  const Eigen::Index ncv = std::min(n, std::max<Eigen::Index>(2 * wanted + 1, wanted + 20));
  progress.report(0.05, "factorising");
  Spectra::SymGEigsShiftSolver<CholmodShiftInvert, Spectra::SparseSymMatProd<double>,
                               Spectra::GEigsMode::ShiftInvert>
      solver(op, mass_product, wanted, ncv, sigma);
  solver.init();
  solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
  if (solver.info() != Spectra::CompInfo::Successful) {
    throw SolverError("laplacian_eigenpairs: the Lanczos iteration did not converge for k = " +
                      std::to_string(k));
  }
  const Eigen::VectorXd values = solver.eigenvalues();
  const Eigen::MatrixXd vectors = solver.eigenvectors();
  std::vector<Eigen::Index> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return values[a] < values[b]; });
  LaplacianEigenpairs result;
  result.values.resize(k);
  result.vectors.resize(n, k);
  for (Eigen::Index i = 0; i < k; ++i) {
    result.values[i] = values[order[i]];
    Eigen::VectorXd u = vectors.col(order[i]);
    // Spectra returns M-orthonormal vectors; normalise again against round-off, and fix the sign
    // (largest-magnitude entry positive) so results are reproducible.
    u /= std::sqrt(u.dot(M * u));
    Eigen::Index largest;
    u.cwiseAbs().maxCoeff(&largest);
    if (u[largest] < 0.0) u = -u;
    result.vectors.col(i) = u;
  }
  progress.report(1.0, "done");
  frame.to_input(result.values.data(), result.values.size(), -2, "laplacian_eigenpairs: eigenvalue");
  frame.to_input(result.vectors.data(), result.vectors.size(), -1, "laplacian_eigenpairs: eigenvector entry");
  return result;
}

}  // namespace meshsmith::geometry
