#include <meshsmith/parametrization/harmonic.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/geometry/laplacian.h>

#include "constrained_solve.h"
#include "input_checks.h"

namespace meshsmith::parametrization {

Eigen::SparseMatrix<double> weight_laplacian(const VertexRef& V, const FaceRef& F, HarmonicWeights weights) {
  switch (weights) {
    case HarmonicWeights::cotan: return geometry::cotan_laplacian(V, F);
    case HarmonicWeights::mean_value: return geometry::mean_value_laplacian(V, F);
    default: return geometry::uniform_laplacian(F, V.rows());
  }
}

geometry::ParameterMatrix harmonic_from_laplacian(const Eigen::SparseMatrix<double>& L, const BoundaryMap& boundary,
                                                  bool symmetric) {
  if (L.rows() != L.cols()) throw InputError("harmonic: the Laplacian is not square");
  detail::check_constrained_vertices(boundary.indices, boundary.uv, L.rows(), "boundary", "harmonic");
  if (boundary.indices.empty()) throw InputError("harmonic: no boundary vertex is fixed");
  // Equilibrium at the free vertices: (−L)_FF X_F = −(−L)_FB X_B; −L is positive semi-definite
  // for symmetric weights. The solver reads row i of −L from column i of its transpose.
  const Eigen::SparseMatrix<double> rows = symmetric ? Eigen::SparseMatrix<double>(-L)
                                                     : Eigen::SparseMatrix<double>(-L.transpose());
  const Eigen::MatrixXd X = detail::solve_with_fixed<double>(
      rows, boundary.indices, Eigen::MatrixXd(boundary.uv),
      symmetric ? detail::SystemKind::positive_definite : detail::SystemKind::general, "harmonic");
  return X;
}

geometry::ParameterMatrix harmonic(const VertexRef& V, const FaceRef& F, const BoundaryMap& boundary,
                                   HarmonicWeights weights) {
  detail::check_mesh(V, F, detail::Requirement::any, "harmonic");
  return harmonic_from_laplacian(weight_laplacian(V, F, weights), boundary, weights != HarmonicWeights::mean_value);
}

geometry::ParameterMatrix harmonic(const VertexRef& V, const FaceRef& F, const HarmonicOptions& options) {
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::disk, "harmonic");
  const BoundaryMap boundary = map_boundary_loop(V, mesh.boundary_loops.front(), options.shape);
  return harmonic_from_laplacian(weight_laplacian(V, F, options.weights), boundary,
                                 options.weights != HarmonicWeights::mean_value);
}

}  // namespace meshsmith::parametrization
