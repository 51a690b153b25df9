#include <meshsmith/parametrization/angle_reconstruction.h>

#include <meshsmith/core/errors.h>

#include "constrained_solve.h"

#include <Eigen/SparseCore>

#include <cmath>
#include <complex>
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
  // Unknown z_v = u_v + i v_v at column v; one complex row per face, the sine-law equation
  //   (z_c − z_a) − ρ e^{iα_a} (z_b − z_a) = 0,  ρ = sin α_b / sin α_c.
  // Minimizing |A z|² with the pins fixed gives the Hermitian normal equations
  // (AᴴA)_FF z_F = −(AᴴA)_FP z_P (the real 2n×2n system written as n×n complex, as LSCM's).
  using Complex = std::complex<double>;
  std::vector<Eigen::Triplet<Complex>> entries;
  entries.reserve(static_cast<size_t>(F.rows()) * 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    // c: the corner of largest sine (the ratio divides by it); a, b follow it.
    int c = 0;
    for (int k = 1; k < 3; ++k)
      if (std::sin(angles(f, k)) > std::sin(angles(f, c))) c = k;
    const int a = (c + 1) % 3, b = (c + 2) % 3;
    const Complex rotation = std::polar(std::sin(angles(f, b)) / std::sin(angles(f, c)), angles(f, a));
    entries.emplace_back(f, F(f, a), rotation - 1.0);
    entries.emplace_back(f, F(f, b), -rotation);
    entries.emplace_back(f, F(f, c), 1.0);
  }
  Eigen::SparseMatrix<Complex> A(F.rows(), n_vertices);
  A.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SparseMatrix<Complex> normal = Eigen::SparseMatrix<Complex>(A.adjoint()) * A;
  progress.report(0.3, "laying out the angles");
  const std::vector<int> fixed{pins.vertices[0], pins.vertices[1]};
  Eigen::MatrixXcd fixed_values(2, 1);
  for (int p = 0; p < 2; ++p) fixed_values(p, 0) = Complex(pins.positions[p].x(), pins.positions[p].y());
  const Eigen::MatrixXcd z = detail::solve_with_fixed<Complex>(normal, fixed, fixed_values,
                                                             detail::SystemKind::positive_definite, "uv_from_angles");
  geometry::ParameterMatrix uv(n_vertices, 2);
  uv.col(0) = z.col(0).real();
  uv.col(1) = z.col(0).imag();
  progress.report(1.0, "laying out the angles");
  return uv;
}

}  // namespace meshsmith::parametrization
