#include <meshsmith/parametrization/stretch.h>

#include <meshsmith/core/errors.h>

#include "constrained_solve.h"
#include "input_checks.h"

#include <cmath>
#include <string>

namespace meshsmith::parametrization {

StretchResult stretch_minimizing(const VertexRef& input_V, const FaceRef& F, const StretchOptions& options,
                                 const Progress& progress) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  if (options.iterations < 0) {
    throw InputError("stretch_minimizing: iterations must be >= 0, not " + std::to_string(options.iterations));
  }
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::disk, "stretch_minimizing");
  const BoundaryMap boundary = map_boundary_loop(V, mesh.boundary_loops.front(), options.shape);
  const bool symmetric = options.weights != HarmonicWeights::mean_value;
  Eigen::SparseMatrix<double> L = weight_laplacian(V, F, options.weights);
  StretchResult result;
  geometry::ParameterMatrix uv = detail::solve_harmonic(L, boundary, symmetric, &V);
  for (int step = 0;; ++step) {
    progress.report(static_cast<double>(step) / (options.iterations + 1), "stretch minimization");
    const geometry::TriangleDistortion distortion = geometry::triangle_distortion(V, F, uv);
    const double stretch = distortion.normalized_global_stretch_l2;
    const bool better = result.stretch.empty() || stretch < result.stretch[result.best_iteration];
    result.stretch.push_back(stretch);
    if (better) {
      result.uv = uv;
      result.best_iteration = step;
    }
    // Stop after the last step, when the stretch grew, or when it is undefined (a degenerate
    // parameter triangle makes it infinite).
    if (step == options.iterations || !better || !std::isfinite(stretch)) break;
    const Eigen::VectorXd& s = distortion.vertex_stretch_l2;
    for (Eigen::Index j = 0; j < L.outerSize(); ++j) {
      double off_diagonal = 0.0;
      double* diagonal = nullptr;
      for (Eigen::SparseMatrix<double>::InnerIterator it(L, j); it; ++it) {
        if (it.row() == j) {
          diagonal = &it.valueRef();
        } else {
          it.valueRef() /= 0.5 * (s[it.row()] + s[j]);
          off_diagonal += it.value();
        }
      }
      // Rows sum to zero; for the (column-stored) symmetric case column sums equal row sums.
      if (diagonal && symmetric) *diagonal = -off_diagonal;
    }
    if (!symmetric) {
      // Mean-value weights: rows hold a vertex's weights; recompute each row's diagonal.
      Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(L.rows());
      for (Eigen::Index j = 0; j < L.outerSize(); ++j) {
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, j); it; ++it) {
          if (it.row() != j) row_sums[it.row()] += it.value();
        }
      }
      for (Eigen::Index j = 0; j < L.outerSize(); ++j) L.coeffRef(j, j) = -row_sums[j];
    }
    uv = detail::solve_harmonic(L, boundary, symmetric, &V);
  }
  progress.report(1.0, "stretch minimization");
  return result;
}

}  // namespace meshsmith::parametrization
