#include <meshsmith/parametrization/angle_reconstruction.h>

#include <meshsmith/core/errors.h>

#include "constrained_solve.h"

#include <Eigen/SparseCore>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace meshsmith::parametrization {

namespace {

void check_layout_input(const FaceRef& F, Eigen::Index n_vertices, const AngleRef& angles, const AnglePins& pins) {
  if (angles.rows() != F.rows()) {
    throw InputError("uv_from_angles: angles has " + std::to_string(angles.rows()) + " rows, F has " +
                     std::to_string(F.rows()) + ": expected one row of three angles per face");
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const double a = angles(f, k);
      if (!(a > 0.0 && a < M_PI)) {
        std::ostringstream message;
        message << "uv_from_angles: angle " << a << " at corner " << k << " of face " << f
                << " is not in (0, π)";
        throw InputError(message.str());
      }
      if (F(f, k) < 0 || F(f, k) >= n_vertices) {
        throw InputError("uv_from_angles: face " + std::to_string(f) + " has vertex index " +
                         std::to_string(F(f, k)) + " outside [0, " + std::to_string(n_vertices) + ")");
      }
    }
  }
  for (int p = 0; p < 2; ++p) {
    if (pins.vertices[p] < 0 || pins.vertices[p] >= n_vertices) {
      throw InputError("uv_from_angles: pinned vertex " + std::to_string(pins.vertices[p]) + " is outside [0, " +
                       std::to_string(n_vertices) + ")");
    }
    if (!pins.positions[p].allFinite()) throw InputError("uv_from_angles: a pinned position is not finite");
  }
  if (pins.vertices[0] == pins.vertices[1] || pins.positions[0] == pins.positions[1]) {
    throw InputError("uv_from_angles: the two pins must be distinct vertices at distinct positions");
  }
}

}  // namespace

geometry::ParameterMatrix uv_from_angles(const FaceRef& F, Eigen::Index n_vertices, const AngleRef& angles,
                                         const AnglePins& pins, const Progress& progress) {
  check_layout_input(F, n_vertices, angles, pins);
  progress.report(0.0, "laying out the angles");
  std::vector<char> used(n_vertices, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[F(f, k)] = 1;
  for (Eigen::Index v = 0; v < n_vertices; ++v) {
    if (!used[v]) {
      throw InputError("uv_from_angles: vertex " + std::to_string(v) +
                       " is used by no face: its position would be undetermined");
    }
  }
  // Unknowns (x_v, y_v) at columns 2v, 2v + 1; two rows per face (real and imaginary part of the
  // complex sine-law equation). Minimizing |A x|² with the pins fixed gives the normal equations
  // (AᵀA)_FF x_F = −(AᵀA)_FP x_P.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(F.rows()) * 10);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    // c: the corner of largest sine (the sine-law ratio divides by it); a, b follow it.
    int c = 0;
    for (int k = 1; k < 3; ++k)
      if (std::sin(angles(f, k)) > std::sin(angles(f, c))) c = k;
    const int a = (c + 1) % 3, b = (c + 2) % 3;
    const double ratio = std::sin(angles(f, b)) / std::sin(angles(f, c));
    const double cos_a = ratio * std::cos(angles(f, a)), sin_a = ratio * std::sin(angles(f, a));
    // x_c − x_a − [cos_a (x_b − x_a) − sin_a (y_b − y_a)] = 0
    // y_c − y_a − [sin_a (x_b − x_a) + cos_a (y_b − y_a)] = 0
    const int vertex[3] = {F(f, a), F(f, b), F(f, c)};
    const double coefficients[2][6] = {
        // (x_a, y_a, x_b, y_b, x_c, y_c)
        {cos_a - 1.0, -sin_a, -cos_a, sin_a, 1.0, 0.0},
        {sin_a, cos_a - 1.0, -sin_a, -cos_a, 0.0, 1.0},
    };
    for (int row = 0; row < 2; ++row)
      for (int corner = 0; corner < 3; ++corner)
        for (int axis = 0; axis < 2; ++axis)
          entries.emplace_back(2 * f + row, 2 * vertex[corner] + axis, coefficients[row][2 * corner + axis]);
  }
  Eigen::SparseMatrix<double> A(2 * F.rows(), 2 * n_vertices);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<double> normal = Eigen::SparseMatrix<double>(A.transpose()) * A;
  progress.report(0.3, "laying out the angles");
  std::vector<int> fixed;
  Eigen::MatrixXd fixed_values(4, 1);
  for (int p = 0; p < 2; ++p) {
    for (int axis = 0; axis < 2; ++axis) {
      fixed.push_back(2 * pins.vertices[p] + axis);
      fixed_values(2 * p + axis, 0) = pins.positions[p][axis];
    }
  }
  const Eigen::MatrixXd x = detail::solve_with_fixed(normal, fixed, fixed_values,
                                                     detail::SystemKind::symmetric_positive_definite,
                                                     "uv_from_angles");
  progress.report(1.0, "laying out the angles");
  return Eigen::Map<const geometry::ParameterMatrix>(x.data(), n_vertices, 2);
}

}  // namespace meshsmith::parametrization
