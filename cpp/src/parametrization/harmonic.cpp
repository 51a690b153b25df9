#include <meshsmith/parametrization/harmonic.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/geometry/laplacian.h>

#include "constrained_solve.h"
#include "input_checks.h"

#include <oneapi/tbb/parallel_invoke.h>

#include <exception>

namespace meshsmith::parametrization {

Eigen::SparseMatrix<double> weight_laplacian(const VertexRef& V, const FaceRef& F, HarmonicWeights weights) {
  switch (weights) {
    case HarmonicWeights::cotan: return geometry::cotan_laplacian(V, F);
    case HarmonicWeights::mean_value: return geometry::mean_value_laplacian(V, F);
    default: return geometry::uniform_laplacian(F, V.rows());
  }
}

namespace detail {

geometry::ParameterMatrix solve_harmonic(const Eigen::SparseMatrix<double>& L, const BoundaryMap& boundary,
                                         bool symmetric, const VertexRef* positions) {
  if (L.rows() != L.cols()) throw InputError("harmonic: the Laplacian is not square");
  if (positions && positions->rows() != L.rows()) throw InputError("harmonic: the positions do not match the Laplacian");
  check_constrained_vertices(boundary.indices, boundary.uv, L.rows(), "boundary", "harmonic");
  if (boundary.indices.empty()) throw InputError("harmonic: no boundary vertex is fixed");
  // Equilibrium at the free vertices: (−L)_FF X_F = −(−L)_FB X_B; −L is positive semi-definite
  // for symmetric weights. The solver reads row i of −L from column i of its transpose.
  const Eigen::SparseMatrix<double> rows = symmetric ? Eigen::SparseMatrix<double>(-L)
                                                     : Eigen::SparseMatrix<double>(-L.transpose());
  return solve_with_fixed<double>(rows, boundary.indices, Eigen::MatrixXd(boundary.uv),
                                  symmetric ? SystemKind::positive_definite : SystemKind::general, "harmonic",
                                  positions);
}

}  // namespace detail

geometry::ParameterMatrix harmonic_from_laplacian(const Eigen::SparseMatrix<double>& L, const BoundaryMap& boundary,
                                                  bool symmetric) {
  return detail::solve_harmonic(L, boundary, symmetric, nullptr);
}

geometry::ParameterMatrix harmonic(const VertexRef& input_V, const FaceRef& F, const BoundaryMap& boundary,
                                   HarmonicWeights weights) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  detail::check_mesh(V, F, detail::Requirement::any, "harmonic");
  return detail::solve_harmonic(weight_laplacian(V, F, weights), boundary, weights != HarmonicWeights::mean_value, &V);
}

geometry::ParameterMatrix harmonic(const VertexRef& input_V, const FaceRef& F, const HarmonicOptions& options) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  // The checks and the Laplacian read the same arrays and are independent: they run
  // concurrently (the Laplacian validates its own input), and a failed check is reported first.
  detail::CheckedMesh mesh;
  Eigen::SparseMatrix<double> L;
  std::exception_ptr check_failure, laplacian_failure;
  tbb::parallel_invoke(
      [&] {
        try {
          mesh = detail::check_mesh(V, F, detail::Requirement::disk, "harmonic");
        } catch (...) {
          check_failure = std::current_exception();
        }
      },
      [&] {
        try {
          L = weight_laplacian(V, F, options.weights);
        } catch (...) {
          laplacian_failure = std::current_exception();
        }
      });
  if (check_failure) std::rethrow_exception(check_failure);
  if (laplacian_failure) std::rethrow_exception(laplacian_failure);
  const BoundaryMap boundary = map_boundary_loop(V, mesh.boundary_loops.front(), options.shape);
  return detail::solve_harmonic(L, boundary, options.weights != HarmonicWeights::mean_value, &V);
}

}  // namespace meshsmith::parametrization
