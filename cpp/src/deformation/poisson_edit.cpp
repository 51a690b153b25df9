// Poisson editing on the order-2 KHarmonicSolver: the right-hand side L (R δ) at the free
// vertices, the constraints through its coupling block. The rotation field interpolates the
// handle's rotation by its angle, about its own axis, with the bi-harmonic weight w (one more
// solve of the same factorization).
#include <meshsmith/deformation/poisson_edit.h>

#include "rotation_fit.h"
#include "vertex_sets.h"

#include <meshsmith/deformation/harmonic_deformer.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/laplacian.h>

#include <Eigen/Geometry>

#include <algorithm>

namespace meshsmith::deformation {

VertexMatrix poisson_edit(const VertexRef& V, const FaceRef& F, const std::vector<int>& handle,
                          const std::vector<int>& fixed, const VertexRef& handle_positions, bool rotate) {
  static const char* function = "poisson_edit";
  validate_mesh(V, F);
  detail::check_vertex_set(handle, V.rows(), "handle", function);
  detail::check_vertex_set(fixed, V.rows(), "fixed", function, /*allow_empty=*/true);
  detail::check_disjoint(handle, fixed, V.rows(), "handle", "fixed", function);
  detail::check_positions(handle_positions, static_cast<Eigen::Index>(handle.size()), "handle_positions", function);
  std::vector<int> constrained(handle);
  constrained.insert(constrained.end(), fixed.begin(), fixed.end());
  const KHarmonicSolver solver(V, F, constrained, 2);
  const Eigen::Index n = V.rows(), n_handle = static_cast<Eigen::Index>(handle.size());

  // Per-vertex rotations.
  std::vector<Eigen::Matrix3d> rotations(static_cast<std::size_t>(n), Eigen::Matrix3d::Identity());
  if (rotate) {
    Eigen::RowVector3d rest_centre = Eigen::RowVector3d::Zero(), moved_centre = Eigen::RowVector3d::Zero();
    for (Eigen::Index k = 0; k < n_handle; ++k) {
      rest_centre += V.row(handle[k]);
      moved_centre += handle_positions.row(k);
    }
    rest_centre /= static_cast<double>(n_handle);
    moved_centre /= static_cast<double>(n_handle);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (Eigen::Index k = 0; k < n_handle; ++k) {
      covariance += (handle_positions.row(k) - moved_centre).transpose() * (V.row(handle[k]) - rest_centre);
    }
    const Eigen::AngleAxisd handle_rotation(detail::best_rotation(covariance));
    Eigen::MatrixXd weights_at_constraints = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(constrained.size()), 1);
    weights_at_constraints.topRows(n_handle).setOnes();
    const Eigen::MatrixXd weights = solver.solve(weights_at_constraints);
    for (Eigen::Index v = 0; v < n; ++v) {
      const double w = std::clamp(weights(v, 0), 0.0, 1.0);
      rotations[v] = Eigen::AngleAxisd(w * handle_rotation.angle(), handle_rotation.axis()).toRotationMatrix();
    }
  }

  // δ = M⁻¹ L V, turned; b = L (R δ).
  const Eigen::SparseMatrix<double> L = geometry::cotan_laplacian(V, F);
  const Eigen::VectorXd areas = geometry::vertex_areas(V, F);
  const Eigen::MatrixXd LV = L * Eigen::MatrixXd(V);
  Eigen::MatrixXd turned(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    const double inverse_area = areas[v] > 0.0 ? 1.0 / areas[v] : 0.0;
    turned.row(v) = (rotations[v] * (inverse_area * LV.row(v).transpose())).transpose();
  }
  const Eigen::MatrixXd b = L * turned;
  const std::vector<int>& free = solver.free_vertices();
  Eigen::MatrixXd free_rhs(static_cast<Eigen::Index>(free.size()), 3);
  for (std::size_t r = 0; r < free.size(); ++r) free_rhs.row(static_cast<Eigen::Index>(r)) = b.row(free[r]);
  Eigen::MatrixXd held(static_cast<Eigen::Index>(constrained.size()), 3);
  for (Eigen::Index k = 0; k < n_handle; ++k) held.row(k) = handle_positions.row(k);
  for (std::size_t k = 0; k < fixed.size(); ++k) held.row(n_handle + static_cast<Eigen::Index>(k)) = V.row(fixed[k]);
  const Eigen::MatrixXd solution = solver.solve_free(held, free_rhs);

  VertexMatrix out = V;
  for (std::size_t k = 0; k < constrained.size(); ++k) out.row(constrained[k]) = held.row(static_cast<Eigen::Index>(k));
  for (std::size_t r = 0; r < free.size(); ++r) out.row(free[r]) = solution.row(static_cast<Eigen::Index>(r));
  return out;
}

}  // namespace meshsmith::deformation
