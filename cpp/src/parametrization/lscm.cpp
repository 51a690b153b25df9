#include <meshsmith/parametrization/lscm.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/geometry/laplacian.h>

#include "constrained_solve.h"
#include "input_checks.h"
#include "mesh_cholesky.h"

#include <Eigen/CholmodSupport>
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <cmath>
#include <complex>
#include <string>
#include <utility>
#include <vector>

namespace meshsmith::parametrization {

namespace {

using Sparse = Eigen::SparseMatrix<double>;

/// Boundary sides i → j (in the faces' orientation) of a checked mesh.
std::vector<std::pair<int, int>> boundary_sides(const FaceRef& F, const topology::EdgeIncidence& incidence) {
  std::vector<std::pair<int, int>> sides;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) != 1) continue;
    const int s = incidence.edge_sides[incidence.edge_offsets[e]];
    sides.emplace_back(F(s / 3, s % 3), F(s / 3, (s % 3 + 1) % 3));
  }
  return sides;
}

Sparse energy_matrix(const VertexRef& V, const FaceRef& F, const std::vector<std::pair<int, int>>& sides) {
  const Eigen::Index n = V.rows();
  const Sparse L = geometry::cotan_laplacian(V, F);
  // The area term couples u and v of the two ends of each boundary side i → j:
  // −(u_i v_j − u_j v_i) gives Q(u_i, v_j) = −½ and Q(u_j, v_i) = +½ (and their mirrors).
  // coupling[k] for k < n: entries (row v_*, value) of column u_k; k ≥ n: (row u_*, value) of column v_{k−n}.
  std::vector<std::vector<std::pair<int, double>>> coupling(2 * n);
  for (const auto& [i, j] : sides) {
    coupling[i].emplace_back(static_cast<int>(n + j), -0.5);
    coupling[n + j].emplace_back(i, -0.5);
    coupling[j].emplace_back(static_cast<int>(n + i), 0.5);
    coupling[n + i].emplace_back(j, 0.5);
  }
  for (auto& column : coupling) {
    std::sort(column.begin(), column.end());
    std::size_t kept = 0;  // merge repeated rows
    for (std::size_t k = 0; k < column.size(); ++k) {
      if (kept > 0 && column[kept - 1].first == column[k].first) column[kept - 1].second += column[k].second;
      else column[kept++] = column[k];
    }
    column.resize(kept);
  }
  Sparse Q(2 * n, 2 * n);
  std::vector<int> outer(2 * n + 1, 0);
  for (Eigen::Index c = 0; c < 2 * n; ++c) {
    const Eigen::Index j = c % n;
    outer[c + 1] = outer[c] + (L.outerIndexPtr()[j + 1] - L.outerIndexPtr()[j]) + static_cast<int>(coupling[c].size());
  }
  Q.resizeNonZeros(outer[2 * n]);
  std::copy(outer.begin(), outer.end(), Q.outerIndexPtr());
  for (Eigen::Index c = 0; c < 2 * n; ++c) {
    const Eigen::Index j = c % n;
    int at = outer[c];
    auto put = [&](int row, double value) { Q.innerIndexPtr()[at] = row, Q.valuePtr()[at++] = value; };
    if (c >= n) for (const auto& [row, value] : coupling[c]) put(row, value);  // u rows come first
    for (Sparse::InnerIterator it(L, j); it; ++it) put(static_cast<int>(it.row() + (c >= n ? n : 0)), -it.value());
    if (c < n) for (const auto& [row, value] : coupling[c]) put(row, value);  // then v rows
  }
  return Q;
}

int farthest_on_loop(const VertexRef& V, const std::vector<int>& loop, int from) {
  int best = loop.front();
  double best_distance = -1.0;
  for (const int v : loop) {
    const double d = (V.row(v) - V.row(from)).squaredNorm();
    if (d > best_distance) best_distance = d, best = v;
  }
  return best;
}

PinnedVertices pins_on_loop(const VertexRef& V, const std::vector<int>& loop) {
  const int a = farthest_on_loop(V, loop, loop.front());
  const int b = farthest_on_loop(V, loop, a);
  PinnedVertices pins;
  pins.indices = {a, b};
  pins.uv.resize(2, 2);
  pins.uv << 0.0, 0.0, (V.row(a) - V.row(b)).norm(), 0.0;
  return pins;
}

/// The conformal energy as a Hermitian form in z = u + iv: z^H H z = xᵀQx, H = −L on the
/// cotangent Laplacian's pattern plus ±i/2 on each boundary side i → j (H_ij += i/2,
/// H_ji −= i/2, so that −(u_i v_j − u_j v_i) is reproduced). The pinned system in n complex
/// unknowns has the fill of the scalar Laplacian, which makes its Cholesky factorization about
/// twice as cheap as that of the 2n×2n real system with its 2×2 blocks.
Eigen::SparseMatrix<std::complex<double>> hermitian_energy_matrix(const VertexRef& V, const FaceRef& F,
                                                                  const std::vector<std::pair<int, int>>& sides) {
  Eigen::SparseMatrix<std::complex<double>> H = (-geometry::cotan_laplacian(V, F)).cast<std::complex<double>>();
  auto entry = [&H](int row, int column) -> std::complex<double>& {
    const int* begin = H.innerIndexPtr() + H.outerIndexPtr()[column];
    const int* end = H.innerIndexPtr() + H.outerIndexPtr()[column + 1];
    return H.valuePtr()[std::lower_bound(begin, end, row) - H.innerIndexPtr()];
  };
  for (const auto& [i, j] : sides) {
    entry(i, j) += std::complex<double>(0.0, 0.5);
    entry(j, i) -= std::complex<double>(0.0, 0.5);
  }
  return H;
}

geometry::ParameterMatrix solve_pinned(const VertexRef& V, const FaceRef& F,
                                       const std::vector<std::pair<int, int>>& sides, const PinnedVertices& pinned) {
  const Eigen::Index n = V.rows();
  Eigen::MatrixXcd values(pinned.indices.size(), 1);
  for (std::size_t k = 0; k < pinned.indices.size(); ++k) values(k, 0) = {pinned.uv(k, 0), pinned.uv(k, 1)};
  const Eigen::MatrixXcd z = detail::solve_with_fixed<std::complex<double>>(
      hermitian_energy_matrix(V, F, sides), pinned.indices, values, detail::SystemKind::positive_definite, "lscm", &V);
  geometry::ParameterMatrix uv(n, 2);
  uv.col(0) = z.col(0).real();
  uv.col(1) = z.col(0).imag();
  return uv;
}

void check_pins(const PinnedVertices& pinned, Eigen::Index n) {
  detail::check_constrained_vertices(pinned.indices, pinned.uv, n, "pinned", "lscm");
  if (pinned.indices.size() < 2) {
    throw InputError("lscm: at least two pinned vertices are needed (" + std::to_string(pinned.indices.size()) +
                     " given); use lscm_spectral for a map without pins");
  }
  for (Eigen::Index k = 1; k < pinned.uv.rows(); ++k) {
    if (pinned.uv.row(k) != pinned.uv.row(0)) return;
  }
  throw InputError("lscm: all pinned vertices are at the same position; pin two of them apart");
}

/// y = (Q − σB)⁻¹ x for Spectra's shift-and-invert mode (Q − σB is positive definite for σ < 0:
/// Q is positive semi-definite and B is positive on its null space, the translations).
class ShiftedConformalInverse {
 public:
  using Scalar = double;
  ShiftedConformalInverse(const Sparse& Q, const Sparse& B) : Q_(Q), B_(B) {
    detail::configure_cholesky(solver_, detail::CholeskyKind::vertex_laplacian);
  }
  Eigen::Index rows() const { return Q_.rows(); }
  Eigen::Index cols() const { return Q_.cols(); }
  void set_shift(double sigma) {
    shifted_ = Q_ - sigma * B_;
    solver_.compute(shifted_);
    if (solver_.info() != Eigen::Success) {
      throw SolverError("lscm_spectral: CHOLMOD could not factorize the shifted conformal energy");
    }
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd>(y_out, rows()) = solver_.solve(x);
  }

 private:
  const Sparse& Q_;
  const Sparse& B_;
  Sparse shifted_;
  detail::MeshCholesky<double> solver_;
};

}  // namespace

Eigen::SparseMatrix<double> conformal_energy_matrix(const VertexRef& input_V, const FaceRef& F) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto incidence = topology::edge_incidence(F, V.rows());
  return energy_matrix(V, F, boundary_sides(F, incidence));
}

PinnedVertices default_lscm_pins(const VertexRef& input_V, const FaceRef& F) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::disk, "lscm");
  PinnedVertices pins = pins_on_loop(V, mesh.boundary_loops.front());
  normalized.frame.to_input(pins.uv.data(), pins.uv.size(), 1, "lscm: pinned position");
  return pins;
}

geometry::ParameterMatrix lscm(const VertexRef& input_V, const FaceRef& F, const PinnedVertices& pinned) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::has_boundary, "lscm");
  check_pins(pinned, V.rows());
  return solve_pinned(V, F, boundary_sides(F, mesh.incidence), pinned);
}

geometry::ParameterMatrix lscm(const VertexRef& input_V, const FaceRef& F) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::disk, "lscm");
  geometry::ParameterMatrix uv =
      solve_pinned(V, F, boundary_sides(F, mesh.incidence), pins_on_loop(V, mesh.boundary_loops.front()));
  normalized.frame.to_input(uv.data(), uv.size(), 1, "lscm: uv coordinate");
  return uv;
}

geometry::ParameterMatrix lscm_spectral(const VertexRef& input_V, const FaceRef& F) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::has_boundary, "lscm_spectral");
  const Eigen::Index n = V.rows();
  const auto sides = boundary_sides(F, mesh.incidence);
  const Sparse Q = energy_matrix(V, F, sides);
  Eigen::VectorXd boundary_mass = Eigen::VectorXd::Zero(2 * n);
  for (const auto& [i, j] : sides) {
    const double half = 0.5 * (V.row(i) - V.row(j)).norm();
    boundary_mass[i] += half, boundary_mass[j] += half;
    boundary_mass[n + i] += half, boundary_mass[n + j] += half;
  }
  Sparse B(2 * n, 2 * n);
  B.reserve(Eigen::VectorXi::Ones(2 * n));
  for (Eigen::Index k = 0; k < 2 * n; ++k) B.insert(k, k) = boundary_mass[k];
  B.makeCompressed();

  // Eigenvalues come in pairs (x and its 90° rotation); 0 holds the two translations (and, on a
  // flat mesh, the similarities too). Ask for a few pairs, remove the translations from each
  // vector and keep the lowest-energy vector with something left.
  const Eigen::Index wanted = std::min<Eigen::Index>(6, 2 * n - 1);
  const Eigen::Index ncv = std::min<Eigen::Index>(2 * n, 30);
  const double perimeter = boundary_mass.sum() / 2.0;
  const double sigma = -1e-3 / perimeter;
  ShiftedConformalInverse op(Q, B);
  Spectra::SparseSymMatProd<double> mass_product(B);
  Spectra::SymGEigsShiftSolver<ShiftedConformalInverse, Spectra::SparseSymMatProd<double>,
                               Spectra::GEigsMode::ShiftInvert>
      solver(op, mass_product, wanted, ncv, sigma);
  solver.init();
  solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
  if (solver.info() != Spectra::CompInfo::Successful) {
    throw SolverError("lscm_spectral: the Lanczos iteration did not converge");
  }
  const Eigen::VectorXd values = solver.eigenvalues();
  const Eigen::MatrixXd vectors = solver.eigenvectors();
  const double total_mass = perimeter;  // Σ B over the u (or v) half
  Eigen::VectorXd best;
  double best_energy = std::numeric_limits<double>::infinity();
  for (Eigen::Index k = 0; k < vectors.cols(); ++k) {
    Eigen::VectorXd x = vectors.col(k);
    const double mean_u = boundary_mass.head(n).dot(x.head(n)) / total_mass;
    const double mean_v = boundary_mass.tail(n).dot(x.tail(n)) / total_mass;
    x.head(n).array() -= mean_u;
    x.tail(n).array() -= mean_v;
    const double norm = x.dot(boundary_mass.cwiseProduct(x));
    if (!(norm > 0.1)) continue;  // (nearly) a translation
    const double energy = x.dot(Q * x) / norm;
    if (energy < best_energy) best_energy = energy, best = x;
  }
  if (best.size() == 0) throw SolverError("lscm_spectral: no non-trivial eigenvector was found");
  geometry::ParameterMatrix uv(n, 2);
  uv.col(0) = best.head(n);
  uv.col(1) = best.tail(n);
  // Scale to the surface's area; the orientation of the minimizer is the faces' (E_C favours a
  // positive signed area), mirrored only if round-off made it negative.
  double surface_area = 0.0, parameter_area = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    surface_area += 0.5 * (b - a).cross(c - a).norm();
    const Eigen::RowVector2d p = uv.row(F(f, 0)), q = uv.row(F(f, 1)), r = uv.row(F(f, 2));
    parameter_area += 0.5 * ((q - p)(0) * (r - p)(1) - (q - p)(1) * (r - p)(0));
  }
  if (parameter_area < 0.0) uv.col(1) = -uv.col(1);
  uv *= std::sqrt(surface_area / std::abs(parameter_area));
  normalized.frame.to_input(uv.data(), uv.size(), 1, "lscm_spectral: uv coordinate");
  return uv;
}

}  // namespace meshsmith::parametrization
