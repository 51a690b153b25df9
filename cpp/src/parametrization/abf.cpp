#include <meshsmith/parametrization/abf.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/parametrization/angle_reconstruction.h>

#include "mesh_cholesky.h"
#include "input_checks.h"

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace meshsmith::parametrization {

namespace {

constexpr double kPi = M_PI;

// ------------------------------------------------------------------------------------------
// Input: a topological disk
// ------------------------------------------------------------------------------------------

/// What the Newton iteration needs of the disk's topology.
struct Disk {
  std::vector<int> interior_index;  // #V: index among the interior vertices, −1 on the boundary
  int n_interior = 0;
  std::vector<int> boundary_loop;
};

Disk check_disk(const VertexRef& V, const FaceRef& F) {
  detail::CheckedMesh mesh = detail::check_mesh(V, F, detail::Requirement::disk, "abf");
  Disk disk;
  disk.boundary_loop = std::move(mesh.boundary_loops.front());
  disk.interior_index.assign(V.rows(), 0);
  for (int v : disk.boundary_loop) disk.interior_index[v] = -1;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (disk.interior_index[v] >= 0) disk.interior_index[v] = disk.n_interior++;
  return disk;
}

void check_options(const AbfOptions& options) {
  if (options.max_iterations < 1) {
    throw InputError("abf: max_iterations = " + std::to_string(options.max_iterations) + ": expected at least 1");
  }
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance)) {
    throw InputError("abf: tolerance must be positive and finite");
  }
  if (!(options.minimum_angle > 0.0 && options.minimum_angle < kPi / 6)) {
    throw InputError("abf: minimum_angle must be in (0, π/6) radians");
  }
}

// ------------------------------------------------------------------------------------------
// Optimal angles
// ------------------------------------------------------------------------------------------

/// 3D corner angles, atan2(|e1 × e2|, e1 · e2): accurate for needles and near-flat corners.
/// (check_mesh has ruled out zero-area faces, so no corner has a zero-length side.)
AngleMatrix corner_angles(const VertexRef& V, const FaceRef& F) {
  AngleMatrix angles(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = V.row(F(f, k)).transpose();
      const Eigen::Vector3d e1 = V.row(F(f, (k + 1) % 3)).transpose() - p;
      const Eigen::Vector3d e2 = V.row(F(f, (k + 2) % 3)).transpose() - p;
      const double cross = e1.cross(e2).norm(), dot = e1.dot(e2);
      angles(f, k) = std::atan2(cross, dot);
    }
  }
  return angles;
}

/// β: 3D angles, rescaled to sum 2π around interior vertices, clamped to [m, π − m].
AngleMatrix optimal_angles(const VertexRef& V, const FaceRef& F, const Disk& disk, double minimum_angle) {
  AngleMatrix beta = corner_angles(V, F);
  std::vector<double> sums(disk.n_interior, 0.0);
  for (Eigen::Index c = 0; c < beta.size(); ++c) {
    const int i = disk.interior_index[F.data()[c]];
    if (i >= 0) sums[i] += beta.data()[c];
  }
  for (Eigen::Index c = 0; c < beta.size(); ++c) {
    const int i = disk.interior_index[F.data()[c]];
    if (i >= 0 && sums[i] > 0.0) beta.data()[c] *= 2.0 * kPi / sums[i];
    beta.data()[c] = std::clamp(beta.data()[c], minimum_angle, kPi - minimum_angle);
  }
  return beta;
}

// ------------------------------------------------------------------------------------------
// The Newton iteration
// ------------------------------------------------------------------------------------------

/// The KKT system of one Newton step: H δα + J1ᵀ δλ1 + J2ᵀ δλ2 = b1, J1 δα = b2, J2 δα = b3, with
/// H = diag(2w) the Hessian of the energy (ABF++ §3: the curvature of the log-sine terms is left
/// out; it can make the diagonal indefinite, and the iteration converges in a few steps without
/// it), J1 the triangle conditions (one row per face, ones on its corners) and J2 the
/// vertex conditions (rows 0..ni−1: angle sums; ni..2ni−1: wheel conditions, ±cot α).
struct NewtonSystem {
  Eigen::VectorXd cotangent; // 3#F, cot α (the wheel rows of J2 are ±these)
  Eigen::VectorXd b1;        // 3#F, −∇_α L
  Eigen::VectorXd b2;        // #F, −(triangle conditions)
  Eigen::VectorXd b3;        // 2 ni, −(vertex conditions)
};

/// Corner c = 3f + k of face f: its vertex, and the vertices of the two other corners. The
/// angle at corner k is the "next" angle of the wheel at corner k − 1 and the "previous" angle of
/// the wheel at corner k + 1 (mod 3).
struct Corners {
  const FaceRef& F;
  const Disk& disk;
  int interior(Eigen::Index c) const { return disk.interior_index[F.data()[c]]; }
  // Interior index of the vertex whose wheel has corner c as its next (+cot) / previous (−cot) angle.
  int wheel_as_next(Eigen::Index c) const { return interior(3 * (c / 3) + (c % 3 + 2) % 3); }
  int wheel_as_previous(Eigen::Index c) const { return interior(3 * (c / 3) + (c % 3 + 1) % 3); }
};

class AbfSolver {
 public:
  AbfSolver(const FaceRef& F, const Disk& disk, const AngleMatrix& beta, const AbfOptions& options)
      : corners_{F, disk}, options_(options), m_(F.rows()), ni_(disk.n_interior) {
    const Eigen::Index n_corners = 3 * m_;
    beta_ = Eigen::Map<const Eigen::VectorXd>(beta.data(), n_corners);
    weight_ = beta_.cwiseInverse().cwiseAbs2();
    hessian_ = 2.0 * weight_;
    inverse_hessian_ = hessian_.cwiseInverse();
    alpha_ = beta_;
    lambda_triangle_ = Eigen::VectorXd::Zero(m_);
    lambda_vertex_ = Eigen::VectorXd::Zero(2 * ni_);
  }

  const Eigen::VectorXd& alpha() const { return alpha_; }

  /// Fills the right-hand sides and the cotangents at the current (α, λ); returns the
  /// constraint residual (∞-norm of the triangle, vertex and wheel conditions).
  double evaluate(NewtonSystem& system) const {
    const Eigen::Index n_corners = 3 * m_;
    system.cotangent.resize(n_corners);
    system.b1.resize(n_corners);
    system.b2.resize(m_);
    system.b3 = Eigen::VectorXd::Zero(2 * ni_);
    for (Eigen::Index c = 0; c < n_corners; ++c) {
      const double s = std::sin(alpha_[c]);
      system.cotangent[c] = std::cos(alpha_[c]) / s;
      const double log_sine = std::log(s);
      double gradient = 2.0 * weight_[c] * (alpha_[c] - beta_[c]) + lambda_triangle_[c / 3];
      if (const int i = corners_.interior(c); i >= 0) {
        gradient += lambda_vertex_[i];
        system.b3[i] -= alpha_[c];
      }
      if (const int i = corners_.wheel_as_next(c); i >= 0) {
        gradient += lambda_vertex_[ni_ + i] * system.cotangent[c];
        system.b3[ni_ + i] -= log_sine;
      }
      if (const int i = corners_.wheel_as_previous(c); i >= 0) {
        gradient -= lambda_vertex_[ni_ + i] * system.cotangent[c];
        system.b3[ni_ + i] += log_sine;
      }
      system.b1[c] = -gradient;
    }
    for (Eigen::Index f = 0; f < m_; ++f) system.b2[f] = kPi - (alpha_[3 * f] + alpha_[3 * f + 1] + alpha_[3 * f + 2]);
    for (Eigen::Index i = 0; i < ni_; ++i) system.b3[i] += 2.0 * kPi;
    return std::max(system.b2.lpNorm<Eigen::Infinity>(), system.b3.size() ? system.b3.lpNorm<Eigen::Infinity>() : 0.0);
  }

  /// Takes the step (δα, δλ1, δλ2), halved until every angle stays inside (0, π).
  void apply_step(const Eigen::VectorXd& d_alpha, const Eigen::VectorXd& d_lambda_triangle,
                  const Eigen::VectorXd& d_lambda_vertex) {
    double step = 1.0;
    const double margin = 0.5 * options_.minimum_angle;
    for (int halving = 0; halving < 40; ++halving) {
      const Eigen::VectorXd trial = alpha_ + step * d_alpha;
      if ((trial.array() > margin).all() && (trial.array() < kPi - margin).all()) break;
      step *= 0.5;
    }
    alpha_ += step * d_alpha;
    lambda_triangle_ += step * d_lambda_triangle;
    lambda_vertex_ += step * d_lambda_vertex;
  }

  /// One ABF++ step: eliminate δα (H diagonal), then δλ1 (J1 H⁻¹ J1ᵀ diagonal), and solve
  /// J2 (H⁻¹ − H⁻¹ J1ᵀ D⁻¹ J1 H⁻¹) J2ᵀ δλ2 = r with CHOLMOD.
  void reduced_step(const NewtonSystem& s) {
    const Eigen::Index n_corners = 3 * m_;
    const Eigen::VectorXd& d = inverse_hessian_;
    Eigen::VectorXd d_alpha(n_corners), d_lambda_triangle(m_), d_lambda_vertex = Eigen::VectorXd::Zero(2 * ni_);
    Eigen::VectorXd triangle_sum(m_), triangle_rhs(m_);  // D_t = Σ d, u_t = Σ d b1 − b2
    for (Eigen::Index f = 0; f < m_; ++f) {
      const Eigen::Index c = 3 * f;
      triangle_sum[f] = d[c] + d[c + 1] + d[c + 2];
      triangle_rhs[f] = d[c] * s.b1[c] + d[c + 1] * s.b1[c + 1] + d[c + 2] * s.b1[c + 2] - s.b2[f];
    }
    if (ni_ > 0) {
      assemble_reduced(s, d, triangle_sum);
      if (!analyzed_) {
        detail::configure_cholesky(cholmod_, detail::CholeskyKind::abf_reduced);
        cholmod_.analyzePattern(reduced_);
        analyzed_ = true;
      }
      cholmod_.factorize(reduced_);
      if (cholmod_.info() != Eigen::Success) {
        throw SolverError("abf: CHOLMOD could not factorize the reduced ABF++ system (the vertex conditions "
                          "are not independent, or an angle collapsed)");
      }
      // r = J2 H⁻¹ (b1 − J1ᵀ D⁻¹ u) − b3
      Eigen::VectorXd q(n_corners);
      for (Eigen::Index c = 0; c < n_corners; ++c) q[c] = d[c] * (s.b1[c] - triangle_rhs[c / 3] / triangle_sum[c / 3]);
      Eigen::VectorXd r = -s.b3;
      multiply_j2(s, q, r);
      d_lambda_vertex = cholmod_.solve(r);
    }
    // δλ1 = D⁻¹ (u − J1 H⁻¹ J2ᵀ δλ2); δα = H⁻¹ (b1 − J1ᵀ δλ1 − J2ᵀ δλ2)
    Eigen::VectorXd j2t_lambda = Eigen::VectorXd::Zero(n_corners);
    multiply_j2_transpose(s, d_lambda_vertex, j2t_lambda);
    for (Eigen::Index f = 0; f < m_; ++f) {
      const Eigen::Index c = 3 * f;
      const double coupled = d[c] * j2t_lambda[c] + d[c + 1] * j2t_lambda[c + 1] + d[c + 2] * j2t_lambda[c + 2];
      d_lambda_triangle[f] = (triangle_rhs[f] - coupled) / triangle_sum[f];
    }
    for (Eigen::Index c = 0; c < n_corners; ++c) {
      d_alpha[c] = d[c] * (s.b1[c] - d_lambda_triangle[c / 3] - j2t_lambda[c]);
    }
    check_finite(d_alpha, d_lambda_vertex);
    apply_step(d_alpha, d_lambda_triangle, d_lambda_vertex);
  }

  /// One ABF step: the whole KKT matrix [H J1ᵀ J2ᵀ; J1 0 0; J2 0 0] by sparse LU.
  ///
  /// The unknowns are ordered angles first, then the triangle multipliers, then the vertex
  /// multipliers in a minimum-degree order of their own coupling, and the LU keeps diagonal
  /// pivots where it can: eliminating an angle (a positive diagonal entry of H) fills only among
  /// the multipliers of its constraints, so the factor stays as sparse as the reduced system. A
  /// general fill-reducing order of the whole matrix (COLAMD) interleaves multipliers with
  /// angles and fills 35 times more (65M entries on a 70k-face mesh: 1 GB and 35 s per step).
  void full_step(const NewtonSystem& s, const Progress& progress, double fraction) {
    const Eigen::Index n_corners = 3 * m_, size = n_corners + m_ + 2 * ni_;
    if (kkt_order_.size() == 0) kkt_order_ = block_order();
    const Eigen::VectorXi& at = kkt_order_.indices();  // at[u]: position of unknown u
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(n_corners) * 11);
    auto symmetric = [&](Eigen::Index row, Eigen::Index column, double value) {
      entries.emplace_back(at[row], at[column], value);
      entries.emplace_back(at[column], at[row], value);
    };
    for (Eigen::Index c = 0; c < n_corners; ++c) {
      entries.emplace_back(at[c], at[c], hessian_[c]);
      symmetric(n_corners + c / 3, c, 1.0);
      if (const int i = corners_.interior(c); i >= 0) symmetric(n_corners + m_ + i, c, 1.0);
      if (const int i = corners_.wheel_as_next(c); i >= 0) symmetric(n_corners + m_ + ni_ + i, c, s.cotangent[c]);
      if (const int i = corners_.wheel_as_previous(c); i >= 0) {
        symmetric(n_corners + m_ + ni_ + i, c, -s.cotangent[c]);
      }
    }
    Eigen::SparseMatrix<double> kkt(size, size);
    kkt.setFromTriplets(entries.begin(), entries.end());
    kkt.makeCompressed();
    progress.report(fraction, "ABF: factorizing the KKT system");
    if (!analyzed_) {
      lu_.setPivotThreshold(1e-3);  // keep the diagonal pivots of the block order unless they are tiny
      lu_.analyzePattern(kkt);
      analyzed_ = true;
    }
    lu_.factorize(kkt);
    if (lu_.info() != Eigen::Success) {
      throw SolverError("abf: sparse LU could not factorize the ABF KKT system: " + lu_.lastErrorMessage());
    }
    progress.report(fraction, "ABF: solving the KKT system");
    Eigen::VectorXd rhs(size);
    rhs << s.b1, s.b2, s.b3;
    const Eigen::VectorXd x = kkt_order_.transpose() * Eigen::VectorXd(lu_.solve(kkt_order_ * rhs));
    const Eigen::VectorXd d_alpha = x.head(n_corners), d_lambda_vertex = x.tail(2 * ni_);
    check_finite(d_alpha, d_lambda_vertex);
    apply_step(d_alpha, x.segment(n_corners, m_), d_lambda_vertex);
  }

 private:
  static void check_finite(const Eigen::VectorXd& d_alpha, const Eigen::VectorXd& d_lambda) {
    if (!d_alpha.allFinite() || !d_lambda.allFinite()) {
      throw SolverError("abf: the Newton step is not finite (the KKT system is singular)");
    }
  }

  /// The block order of full_step's unknowns (angles, triangle multipliers, vertex multipliers),
  /// the vertex multipliers in the approximate-minimum-degree order of the interior vertices'
  /// adjacency (a vertex's angle-sum and wheel rows kept together).
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> block_order() const {
    const Eigen::Index n_corners = 3 * m_, size = n_corners + m_ + 2 * ni_;
    std::vector<Eigen::Triplet<double>> adjacency;
    adjacency.reserve(static_cast<size_t>(m_) * 9);
    for (Eigen::Index f = 0; f < m_; ++f)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          const int i = corners_.interior(3 * f + a), j = corners_.interior(3 * f + b);
          if (i >= 0 && j >= 0) adjacency.emplace_back(i, j, 1.0);
        }
    Eigen::SparseMatrix<double> pattern(ni_, ni_);
    pattern.setFromTriplets(adjacency.begin(), adjacency.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> vertex_order;
    if (ni_ > 0) Eigen::AMDOrdering<int>()(pattern, vertex_order);
    Eigen::VectorXi at(size);  // at[u]: position of unknown u
    for (Eigen::Index u = 0; u < n_corners + m_; ++u) at[u] = static_cast<int>(u);
    for (Eigen::Index k = 0; k < ni_; ++k) {      // AMD gives the vertex at each position k
      const int i = vertex_order.indices()[k], place = static_cast<int>(n_corners + m_ + 2 * k);
      at[n_corners + m_ + i] = place;             // angle-sum row of interior vertex i
      at[n_corners + m_ + ni_ + i] = place + 1;   // its wheel row
    }
    return Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>(at);
  }

  /// out += J2 x (x: one value per corner).
  void multiply_j2(const NewtonSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& out) const {
    for (Eigen::Index c = 0; c < 3 * m_; ++c) {
      if (const int i = corners_.interior(c); i >= 0) out[i] += x[c];
      if (const int i = corners_.wheel_as_next(c); i >= 0) out[ni_ + i] += s.cotangent[c] * x[c];
      if (const int i = corners_.wheel_as_previous(c); i >= 0) out[ni_ + i] -= s.cotangent[c] * x[c];
    }
  }

  /// out += J2ᵀ y (y: one value per vertex condition).
  void multiply_j2_transpose(const NewtonSystem& s, const Eigen::VectorXd& y, Eigen::VectorXd& out) const {
    if (ni_ == 0) return;
    for (Eigen::Index c = 0; c < 3 * m_; ++c) {
      if (const int i = corners_.interior(c); i >= 0) out[c] += y[i];
      if (const int i = corners_.wheel_as_next(c); i >= 0) out[c] += s.cotangent[c] * y[ni_ + i];
      if (const int i = corners_.wheel_as_previous(c); i >= 0) out[c] -= s.cotangent[c] * y[ni_ + i];
    }
  }

  /// reduced_ = Σ_faces J2_f P_f J2_fᵀ with P_f = diag(d) − d dᵀ / Σ d over the face's corners.
  void assemble_reduced(const NewtonSystem& s, const Eigen::VectorXd& d, const Eigen::VectorXd& triangle_sum) {
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(m_) * 36);
    for (Eigen::Index f = 0; f < m_; ++f) {
      // The face's rows of J2 (at most 6: angle sum and wheel of each interior corner vertex).
      int rows[6];
      Eigen::Matrix<double, 6, 3> J = Eigen::Matrix<double, 6, 3>::Zero();
      int n_rows = 0;
      for (int k = 0; k < 3; ++k) {
        const int i = corners_.interior(3 * f + k);
        if (i < 0) continue;
        rows[n_rows] = i;
        J(n_rows++, k) = 1.0;
        rows[n_rows] = ni_ + i;
        J(n_rows, (k + 1) % 3) = s.cotangent[3 * f + (k + 1) % 3];
        J(n_rows++, (k + 2) % 3) = -s.cotangent[3 * f + (k + 2) % 3];
      }
      if (n_rows == 0) continue;
      const Eigen::Vector3d df = d.segment<3>(3 * f);
      const Eigen::Matrix3d P = Eigen::Matrix3d(df.asDiagonal()) - df * df.transpose() / triangle_sum[f];
      const Eigen::Matrix<double, 6, 6> block = J * P * J.transpose();
      for (int a = 0; a < n_rows; ++a)
        for (int b = 0; b < n_rows; ++b)
          if (rows[b] <= rows[a]) entries.emplace_back(rows[a], rows[b], block(a, b));
    }
    reduced_.resize(2 * ni_, 2 * ni_);
    reduced_.setFromTriplets(entries.begin(), entries.end());
  }

  Corners corners_;
  const AbfOptions& options_;
  Eigen::Index m_, ni_;
  Eigen::VectorXd beta_, weight_, hessian_, inverse_hessian_, alpha_, lambda_triangle_, lambda_vertex_;
  Eigen::SparseMatrix<double> reduced_;  // lower triangle of the reduced system
  detail::MeshCholesky<double> cholmod_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::NaturalOrdering<int>> lu_;
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> kkt_order_;
  bool analyzed_ = false;
};

/// The two boundary vertices (approximately) farthest apart: two sweeps of farthest-point search.
AnglePins farthest_boundary_pins(const VertexRef& V, const std::vector<int>& loop) {
  auto farthest_from = [&](int from) {
    int best = loop.front();
    double best_distance = -1.0;
    for (int v : loop) {
      const double distance = (V.row(v) - V.row(from)).squaredNorm();
      if (distance > best_distance) best_distance = distance, best = v;
    }
    return best;
  };
  AnglePins pins;
  pins.vertices[0] = farthest_from(loop.front());
  pins.vertices[1] = farthest_from(pins.vertices[0]);
  if (pins.vertices[1] == pins.vertices[0]) pins.vertices[1] = loop[loop[0] == pins.vertices[0] ? 1 : 0];
  double distance = (V.row(pins.vertices[1]) - V.row(pins.vertices[0])).norm();
  if (!(distance > 0.0)) distance = 1.0;  // a boundary collapsed to a point: any scale will do
  pins.positions[0] = Eigen::Vector2d::Zero();
  pins.positions[1] = Eigen::Vector2d(distance, 0.0);
  return pins;
}

/// Scales uv about the origin so that its total (signed) area equals the surface area of (V, F):
/// a developable surface then flattens isometrically.
void scale_to_surface_area(const VertexRef& V, const FaceRef& F, geometry::ParameterMatrix& uv) {
  double surface_area = 0.0, uv_area = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(),
                          c = V.row(F(f, 2)).transpose();
    surface_area += 0.5 * (b - a).cross(c - a).norm();
    const Eigen::Vector2d p = uv.row(F(f, 0)).transpose(), q = uv.row(F(f, 1)).transpose(),
                          r = uv.row(F(f, 2)).transpose();
    uv_area += 0.5 * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
  }
  if (surface_area > 0.0 && uv_area > 0.0) uv *= std::sqrt(surface_area / uv_area);
}

const char* method_name(AbfMethod method) { return method == AbfMethod::AbfPlusPlus ? "ABF++" : "ABF"; }

}  // namespace

AbfResult abf(const VertexRef& input_V, const FaceRef& F, const AbfOptions& options, const Progress& progress) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  check_options(options);
  const Disk disk = check_disk(V, F);
  const Eigen::Index m = F.rows();
  AbfResult result;
  result.optimal_angles = optimal_angles(V, F, disk, options.minimum_angle);

  const Progress newton_progress = progress.subrange(0.0, 0.9);
  AbfSolver solver(F, disk, result.optimal_angles, options);
  NewtonSystem system;
  double residual = solver.evaluate(system);
  result.residual_history.push_back(residual);
  char stage[96];
  while (residual > options.tolerance) {
    if (result.iterations == options.max_iterations) {
      std::ostringstream message;
      message << "abf: " << method_name(options.method) << " did not converge in " << options.max_iterations
              << " Newton iterations: constraint residual (∞-norm) " << residual << " > tolerance "
              << options.tolerance;
      throw SolverError(message.str());
    }
    std::snprintf(stage, sizeof stage, "%s Newton iteration %d, residual %.3g", method_name(options.method),
                  result.iterations + 1, residual);
    newton_progress.report(static_cast<double>(result.iterations) / options.max_iterations, stage);
    if (options.method == AbfMethod::AbfPlusPlus) {
      solver.reduced_step(system);
    } else {
      solver.full_step(system, newton_progress, static_cast<double>(result.iterations) / options.max_iterations);
    }
    ++result.iterations;
    residual = solver.evaluate(system);
    result.residual_history.push_back(residual);
  }
  result.residual = residual;
  result.angles = Eigen::Map<const AngleMatrix>(solver.alpha().data(), m, 3);
  newton_progress.report(1.0, "Newton iterations done");
  result.uv = uv_from_angles(F, V.rows(), result.angles, farthest_boundary_pins(V, disk.boundary_loop),
                             progress.subrange(0.9, 1.0));
  scale_to_surface_area(V, F, result.uv);
  normalized.frame.to_input(result.uv.data(), result.uv.size(), 1, "abf: uv coordinate");
  return result;
}

}  // namespace meshsmith::parametrization
