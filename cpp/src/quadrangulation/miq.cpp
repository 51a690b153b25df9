// MIQ in three steps.
//
// 1. Unknowns: (u, v) of every vertex copy of the cut mesh, and a translation t_s per seam
//    edge. Each seam edge gives, for both of its end vertices, the transition uv_b = R^{−r} uv_a
//    + t_s (a, b the copies on the two sides, r the seam's period jump, R the quarter turn).
//    These rows are eliminated one scalar row at a time (sparse Gaussian elimination with lazy
//    substitution): the pivot is a continuous unknown when the row has one, else an integer
//    unknown with coefficient ±1, so eliminated integers are integer combinations of free
//    integers. Consecutive seam edges of one seam arc reduce to t_s' = t_s; at seam nodes and
//    singular vertices the rows close cycles among the translations. The result is x = Z y + c
//    with y the free unknowns, and the energy becomes yᵀ (Zᵀ K Z) y − 2 (Zᵀ (b − K c))ᵀ y.
// 2. Greedy rounding: with the reduced matrix H factorized once, the integer block S = (H⁻¹)_II
//    of its inverse is formed by blocked solves. Rounding y_j to d_j moves the minimizer by
//    −H⁻¹e_j (y_j − d_j) / S_jj, so on the integer unknowns y_I −= S_Ij (y_j − d_j) / S_jj and
//    S −= S_Ij S_jI / S_jj (the Schur complement): the exact greedy of Bommes et al. (round the
//    unknown closest to an integer, re-solve, repeat) at O(N²) per rounding, with no
//    refactorization. Measured on a 100k-face mesh: see benchmarks/bench_quadrangulation.py.
// 3. The continuous unknowns are solved with the integers held (the held rows and columns
//    replaced by the identity, so every re-solve reuses the symbolic analysis), and triangles
//    that come out flipped are stiffened and the map re-solved, a few rounds (a round with more
//    flips is undone and the factor softened; stopping after three without fewer flips), each
//    re-solve on the unknowns within three quad edges of the stiffened faces only (pmp-bunny's
//    MIQ at 3,000 quads: 4.6 → 1.5 s, the same flips removed). With options.target_quads the
//    grid unit is calibrated on the continuous map before the rounding (its area is then the
//    requested count of unit squares; √(area / quads) alone gave 6–11% fewer quads). The
//    flips this leaves (7 of 69,666 on pmp-bunny at 3,000 quads, 7 on rocker-arm) sit at cones
//    0.2–0.3 quad edges from another cone, which the rounding puts on the same or the next
//    integer point; stiffening (×2 to ×20, 30 rounds), moving the integers those vertices depend
//    on by ±1 and splitting the cones' obtuse triangles removed none of them; cancelling or
//    separating such pairs in the field does (quadrangulation.merge_singularities, applied by
//    quadrangulate: 0 flips on the six shared meshes at 3,000 quads).
// Features (sharp_angle_degrees): the coordinate across a feature edge is held constant and
// integer on both sides. Two such lines (or a line and a cone) less than a quad edge apart were
// rounded onto one integer, collapsing the strip between them; the rounding now keeps them on
// distinct integers in their order (fandisk at 3,000 quads: 34 → 18 flips). The flips left sat
// 1–2 quad edges from a feature line next to a −1 cone beside it; the feature edges near them
// are released and the map solved again (→ 0 flips, 29 of 710 feature edges released).
#include <meshsmith/quadrangulation/miq.h>

#include "field_geometry.h"
#include "seamless_map.h"
#include "../core/supernodal_solve.h"

#include <meshsmith/core/errors.h>

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace meshsmith::quadrangulation {

namespace {

using detail::FieldMesh;
using Sparse = Eigen::SparseMatrix<double>;
using Solver = detail::Cholesky;

struct Term {
  int variable;
  double coefficient;
};

/// A linear expression Σ coefficient · variable + constant.
struct Expression {
  std::vector<Term> terms;
  double constant = 0.0;
};

/// Sparse elimination of linear equality rows with lazy substitution.
class Eliminator {
 public:
  Eliminator(int n_variables, std::vector<char> integer)
      : integer_(std::move(integer)), eliminated_(n_variables, -1) {}

  /// Holds variable v at `value` (the gauge).
  void hold(int v, double value) {
    eliminated_[v] = static_cast<int>(expressions_.size());
    expressions_.push_back({{}, value});
  }

  /// Adds the row Σ terms + constant = 0.
  void add_row(const std::vector<Term>& row, double constant) {
    Expression resolved = resolve({row, constant});
    if (resolved.terms.empty()) {
      if (std::abs(resolved.constant) > 1e-9) {
        throw SolverError("miq: the seam transition functions are inconsistent; please report this mesh");
      }
      return;
    }
    // Pivot: the continuous unknown of largest index, else an integer unknown with coefficient ±1.
    int pivot = -1;
    for (std::size_t k = 0; k < resolved.terms.size(); ++k) {
      const Term& t = resolved.terms[k];
      if (!integer_[t.variable] && (pivot < 0 || t.variable > resolved.terms[pivot].variable ||
                                    integer_[resolved.terms[pivot].variable])) {
        pivot = static_cast<int>(k);
      }
    }
    if (pivot < 0) {
      for (std::size_t k = 0; k < resolved.terms.size(); ++k) {
        if (std::abs(std::abs(resolved.terms[k].coefficient) - 1.0) < 1e-12) pivot = static_cast<int>(k);
      }
      if (pivot < 0) pivot = 0;
    }
    const Term p = resolved.terms[pivot];
    Expression expression;
    expression.constant = -resolved.constant / p.coefficient;
    for (std::size_t k = 0; k < resolved.terms.size(); ++k) {
      if (static_cast<int>(k) == pivot) continue;
      expression.terms.push_back({resolved.terms[k].variable, -resolved.terms[k].coefficient / p.coefficient});
    }
    eliminated_[p.variable] = static_cast<int>(expressions_.size());
    expressions_.push_back(std::move(expression));
  }

  bool is_free(int v) const { return eliminated_[v] < 0; }

  /// The expression of v in the free variables.
  Expression expression_of(int v) {
    if (is_free(v)) return {{{v, 1.0}}, 0.0};
    return resolved_expression(v);
  }

 private:
  const Expression& resolved_expression(int v) {
    Expression& stored = expressions_[eliminated_[v]];
    bool all_free = true;
    for (const Term& t : stored.terms) all_free &= is_free(t.variable);
    if (!all_free) {
      Expression copy = stored;
      expressions_[eliminated_[v]] = resolve(copy);
    }
    return expressions_[eliminated_[v]];
  }

  Expression resolve(const Expression& in) {
    Expression out;
    out.constant = in.constant;
    for (const Term& t : in.terms) {
      if (is_free(t.variable)) {
        out.terms.push_back(t);
        continue;
      }
      const Expression sub = resolved_expression(t.variable);
      out.constant += t.coefficient * sub.constant;
      for (const Term& s : sub.terms) out.terms.push_back({s.variable, t.coefficient * s.coefficient});
    }
    std::sort(out.terms.begin(), out.terms.end(), [](const Term& a, const Term& b) { return a.variable < b.variable; });
    std::size_t kept = 0;
    for (std::size_t k = 0; k < out.terms.size();) {
      Term merged = out.terms[k];
      for (++k; k < out.terms.size() && out.terms[k].variable == merged.variable; ++k) merged.coefficient += out.terms[k].coefficient;
      if (std::abs(merged.coefficient) > 1e-12) out.terms[kept++] = merged;
    }
    out.terms.resize(kept);
    return out;
  }

  std::vector<char> integer_;
  std::vector<int> eliminated_;
  std::vector<Expression> expressions_;
};

/// R^k applied as a matrix: the quarter turn R = [[0, −1], [1, 0]] to the power k mod 4.
Eigen::Matrix2d quarter_turns(int k) {
  k = ((k % 4) + 4) % 4;
  Eigen::Matrix2d R;
  switch (k) {
    case 0: R << 1, 0, 0, 1; break;
    case 1: R << 0, -1, 1, 0; break;
    case 2: R << -1, 0, 0, -1; break;
    default: R << 0, 1, -1, 0; break;
  }
  return R;
}

/// H with the rows and columns of `held` replaced by the identity (pattern kept).
Sparse with_held_identity(const Sparse& H, const std::vector<char>& held) {
  Sparse out = H;
  for (int c = 0; c < out.outerSize(); ++c) {
    for (Sparse::InnerIterator it(out, c); it; ++it) {
      if (held[it.row()] || held[c]) it.valueRef() = it.row() == c ? 1.0 : 0.0;
    }
  }
  return out;
}

/// The log conformal factor φ (#V) of the flat cone metric whose parallel transport the cross
/// field `theta` follows (Ben-Chen, Gotsman & Bunin 2008; Crane, Desbrun & Schröder 2010). Where
/// the field turns against the surface's transport by δ across edge i → j (δ reduced mod π/2,
/// from the face on the edge's left to the one on its right), a unit cross scaled by e^φ is the
/// gradient of a map when ∇φ = J∇θ (Cauchy–Riemann for φ − iθ): along the edge φ_j − φ_i =
/// δ · ℓ_ij / ℓ*_ij, ℓ* the dual edge's length. Least squares with the cotan weights ℓ*/ℓ
/// (clamped at 0.01: the right-hand side is then Σ ±δ alone), a 1e-8 diagonal for the constant;
/// the field's harmonic part (genus > 0) and its turning around cones are what no φ absorbs.
/// \throw SolverError if CHOLMOD fails.
Eigen::VectorXd conformal_log_scale(const FieldMesh& mesh, const FaceRef& F, const Eigen::VectorXd& theta) {
  const auto& incidence = mesh.checked.incidence;
  const Eigen::Index n = mesh.V.rows();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(4 * incidence.n_edges() + n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    const int i = incidence.edges(e, 0), j = incidence.edges(e, 1);
    double weight = 0;
    for (int side = 0; side < 2; ++side) {
      const int f = mesh.edge_faces(e, side);
      if (f < 0) continue;
      const int k = F(f, 0) != i && F(f, 0) != j ? F(f, 0) : F(f, 1) != i && F(f, 1) != j ? F(f, 1) : F(f, 2);
      const Eigen::Vector3d a = mesh.V.row(i) - mesh.V.row(k), b = mesh.V.row(j) - mesh.V.row(k);
      weight += 0.5 * a.dot(b) / std::max(a.cross(b).norm(), 1e-300);
    }
    weight = std::max(weight, 0.01);
    triplets.emplace_back(i, i, weight);
    triplets.emplace_back(j, j, weight);
    triplets.emplace_back(i, j, -weight);
    triplets.emplace_back(j, i, -weight);
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const double delta = detail::quarter_residual(theta[g] - theta[f] - mesh.connection[e]);
    rhs[j] += delta;
    rhs[i] -= delta;
  }
  for (Eigen::Index v = 0; v < n; ++v) triplets.emplace_back(v, v, 1e-8);
  Sparse L(n, n);
  L.setFromTriplets(triplets.begin(), triplets.end());
  Solver solver;
  detail::configure_cholmod(solver);
  solver.compute(L);
  if (solver.info() != Eigen::Success) throw SolverError("miq: CHOLMOD failed to factorize the conformal-scale system");
  Eigen::VectorXd phi = solver.solve(rhs);
  if (!phi.allFinite()) throw SolverError("miq: the conformal-scale solve did not give finite values");
  return phi;
}

/// The grid unit (one quad edge) in normalized lengths: options.target_edge_length, or twice
/// the mean edge length when it is 0.
double grid_unit(const FieldMesh& mesh, const MiqOptions& options) {
  double h = options.target_edge_length;
  const auto& incidence = mesh.checked.incidence;
  if (h > 0) {
    h = std::ldexp(h, -mesh.frame.exponent);
  } else {
    double total = 0;
    for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
      total += (mesh.V.row(incidence.edges(e, 1)) - mesh.V.row(incidence.edges(e, 0))).norm();
    }
    h = 2 * total / static_cast<double>(incidence.n_edges());
  }
  if (!(h > 0) || !std::isfinite(1 / h)) throw InputError("miq: target_edge_length is too small for this mesh");
  return h;
}

/// The map on one cut (steps 1–3), with the feature edges flagged in `released` left free.
MiqResult solve_map(const FieldMesh& mesh, const FaceRef& F, const MiqOptions& options, const Progress& progress,
                    FieldCut field_cut, const std::vector<char>& released) {
  MiqResult result;
  result.cut = std::move(field_cut);
  const auto& cut = result.cut.cut;
  const FaceMatrix& Fc = cut.F;
  const Eigen::Index m = F.rows(), nc = cut.V.rows(), n_seam = cut.seam_edges.rows();

  const auto& incidence = mesh.checked.incidence;
  double h = grid_unit(mesh, options);
  double s = 1 / h;

  VertexMatrix P(nc, 3);
  for (Eigen::Index i = 0; i < nc; ++i) P.row(i) = mesh.V.row(cut.vertex_origin[i]);
  VertexMatrix target_u(m, 3), target_v(m, 3);
  for (Eigen::Index f = 0; f < m; ++f) {
    const double a = result.cut.combed_theta[f];
    const Eigen::Vector3d d = std::cos(a) * mesh.e1.row(f) + std::sin(a) * mesh.e2.row(f);
    target_u.row(f) = s * d;
    target_v.row(f) = s * Eigen::Vector3d(mesh.normal.row(f)).cross(d);
  }

  // Step 1: unknowns and the elimination of the transition rows.
  const int n_variables = static_cast<int>(2 * nc + 2 * n_seam);
  std::vector<char> integer(n_variables, 0);
  std::vector<char> singular(mesh.V.rows(), 0);
  for (const int v : result.cut.singularities.vertices) singular[v] = 1;
  if (options.round_singularities) {
    for (Eigen::Index i = 0; i < nc; ++i) {
      if (singular[cut.vertex_origin[i]]) integer[2 * i] = integer[2 * i + 1] = 1;
    }
  }
  if (options.round_translations) {
    for (Eigen::Index k = 2 * nc; k < n_variables; ++k) integer[k] = 1;
  }
  // Feature edges: on each side, the coordinate across the edge is constant along it and an
  // integer (the edge lies on an integer iso-line), where the combed cross follows the edge to
  // within 10° (the field is hard-constrained to feature edges; a face with two features at an
  // angle follows only one of them).
  struct FeatureRow {
    int a, b;  // variables x_a = x_b, both integer
    Eigen::Index edge;
  };
  std::vector<FeatureRow> feature_rows;
  std::vector<char> held_on_line(n_variables, 0);
  if (!std::isfinite(options.sharp_angle_degrees)) throw InputError("miq: sharp_angle is not finite");
  if (options.sharp_angle_degrees > 0) {
    const double cos_sharp = std::cos(options.sharp_angle_degrees * detail::kPi / 180.0);
    const double aligned = std::cos(10.0 * detail::kPi / 180.0);
    for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
      const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
      if (g < 0 || mesh.normal.row(f).dot(mesh.normal.row(g)) >= cos_sharp) continue;
      if (released[e]) {
        ++result.released_feature_edges;
        continue;
      }
      const int i = incidence.edges(e, 0), j = incidence.edges(e, 1);
      const Eigen::Vector3d d = (mesh.V.row(j) - mesh.V.row(i)).normalized();
      for (const int face : {f, g}) {
        const double along_u = std::abs(d.dot(target_u.row(face)) / s);
        const double along_v = std::abs(d.dot(target_v.row(face)) / s);
        const int coordinate = along_u > aligned ? 1 : along_v > aligned ? 0 : -1;  // the constant one
        if (coordinate < 0) continue;
        int a = -1, b = -1;
        for (int c = 0; c < 3; ++c) {
          if (F(face, c) == i) a = Fc(face, c);
          if (F(face, c) == j) b = Fc(face, c);
        }
        feature_rows.push_back({2 * a + coordinate, 2 * b + coordinate, e});
        held_on_line[2 * a + coordinate] = held_on_line[2 * b + coordinate] = 1;
      }
    }
    // A triangle whose three corners are all held on iso-lines of one coordinate collapses to a
    // segment (a curved feature polyline with an "ear" triangle on it): its corner opposite the
    // longest side (the polyline's middle vertex) is released from that coordinate's line, so
    // the feature runs straight past it in (u, v), off it by a fraction of a triangle.
    for (bool changed = true; changed;) {
      changed = false;
      for (Eigen::Index f = 0; f < m; ++f) {
        for (int coordinate = 0; coordinate < 2; ++coordinate) {
          if (!held_on_line[2 * Fc(f, 0) + coordinate] || !held_on_line[2 * Fc(f, 1) + coordinate] ||
              !held_on_line[2 * Fc(f, 2) + coordinate]) {
            continue;
          }
          int middle = 0;
          double longest = -1;
          for (int c = 0; c < 3; ++c) {
            const double side = (mesh.V.row(F(f, (c + 1) % 3)) - mesh.V.row(F(f, (c + 2) % 3))).norm();
            if (side > longest) longest = side, middle = c;
          }
          held_on_line[2 * Fc(f, middle) + coordinate] = 0;
          changed = true;
        }
      }
    }
    std::vector<FeatureRow> kept;
    std::vector<char> edge_kept(incidence.n_edges(), 0);
    for (const FeatureRow& row : feature_rows) {
      if (!held_on_line[row.a] || !held_on_line[row.b]) continue;
      kept.push_back(row);
      integer[row.a] = integer[row.b] = 1;
      result.feature_edges += !edge_kept[row.edge];
      edge_kept[row.edge] = 1;
    }
    feature_rows = std::move(kept);
  }
  // The grid's scale e^{λφ} per face (φ averaged over its corners), normalized so that its
  // area-weighted mean square is 1 (the same count of unit squares as a uniform scale). After
  // the features: their test above reads the unit crosses.
  if (options.conformal_scale > 0) {
    const Eigen::VectorXd phi = conformal_log_scale(mesh, F, result.cut.combed_theta);
    Eigen::VectorXd log_scale(m);
    double mean_square = 0;
    for (Eigen::Index f = 0; f < m; ++f) {
      log_scale[f] = options.conformal_scale * (phi[F(f, 0)] + phi[F(f, 1)] + phi[F(f, 2)]) / 3;
      mean_square += mesh.area[f] * std::exp(2 * log_scale[f]);
    }
    log_scale.array() -= 0.5 * std::log(mean_square / mesh.area.sum());
    for (Eigen::Index f = 0; f < m; ++f) {
      target_u.row(f) *= std::exp(log_scale[f]);
      target_v.row(f) *= std::exp(log_scale[f]);
    }
    result.log_scale_min = log_scale.minCoeff();
    result.log_scale_max = log_scale.maxCoeff();
  }
  Eliminator eliminator(n_variables, integer);
  const int gauge = result.cut.singularities.vertices.empty() ? 0 : result.cut.singularities.vertices.front();
  eliminator.hold(2 * gauge, 0.0);
  eliminator.hold(2 * gauge + 1, 0.0);
  {
    Eigen::Index e = 0;
    for (Eigen::Index k = 0; k < n_seam; ++k) {
      const int i = cut.seam_edges(k, 0), j = cut.seam_edges(k, 1);
      while (incidence.edges(e, 0) != i || incidence.edges(e, 1) != j) ++e;
      const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
      const Eigen::Matrix2d M = quarter_turns(-result.cut.seam_jumps[k]);
      for (const int vertex : {i, j}) {
        int a = -1, b = -1;
        for (int c = 0; c < 3; ++c) {
          if (F(f, c) == vertex) a = Fc(f, c);
          if (F(g, c) == vertex) b = Fc(g, c);
        }
        for (int d = 0; d < 2; ++d) {
          std::vector<Term> row{{2 * b + d, 1.0}, {static_cast<int>(2 * nc + 2 * k + d), -1.0}};
          for (int c = 0; c < 2; ++c) {
            if (M(d, c) != 0) row.push_back({2 * a + c, -M(d, c)});
          }
          eliminator.add_row(row, 0.0);
        }
      }
    }
  }
  for (const FeatureRow& row : feature_rows) eliminator.add_row({{row.a, 1.0}, {row.b, -1.0}}, 0.0);
  progress.report(0.1, "miq: system");
  // x = Z y + c over the free unknowns y.
  std::vector<int> free_index(n_variables, -1), free_variables;
  for (int v = 0; v < n_variables; ++v) {
    if (eliminator.is_free(v)) free_index[v] = static_cast<int>(free_variables.size()), free_variables.push_back(v);
  }
  const auto n_free = static_cast<Eigen::Index>(free_variables.size());
  std::vector<Eigen::Triplet<double>> z_triplets;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(2 * nc);
  for (int v = 0; v < 2 * nc; ++v) {  // only the (u, v) rows carry energy
    const Expression expression = eliminator.expression_of(v);
    c[v] = expression.constant;
    for (const Term& t : expression.terms) z_triplets.emplace_back(v, free_index[t.variable], t.coefficient);
  }
  Sparse Z(2 * nc, n_free);
  Z.setFromTriplets(z_triplets.begin(), z_triplets.end());
  // Translations that no (u, v) depends on (none expected) would make H singular: hold them at 0.
  std::vector<int> integer_free;
  std::vector<char> held(n_free, 0);
  {
    Eigen::VectorXd column_weight = Eigen::VectorXd::Zero(n_free);
    for (int k = 0; k < Z.outerSize(); ++k)
      for (Sparse::InnerIterator it(Z, k); it; ++it) column_weight[k] += std::abs(it.value());
    for (Eigen::Index k = 0; k < n_free; ++k) {
      if (column_weight[k] == 0) held[k] = 1;
      else if (integer[free_variables[k]]) integer_free.push_back(static_cast<int>(k));
    }
  }
  result.integer_variables = static_cast<Eigen::Index>(integer_free.size());

  Eigen::VectorXd weight = Eigen::VectorXd::Ones(m);
  Sparse K;
  Eigen::VectorXd b;
  auto reduced_system = [&](Sparse& H, Eigen::VectorXd& g) {
    detail::assemble_energy(P, Fc, target_u, target_v, weight, 2 * nc, K, b);
    H = Sparse(Z.transpose() * K * Z);
    g = Z.transpose() * (b - K * c);
  };
  Sparse H;
  Eigen::VectorXd g;
  reduced_system(H, g);
  Solver solver;
  detail::configure_cholmod(solver);
  solver.analyzePattern(H);
  auto factorize = [&](const Sparse& A) {
    solver.factorize(A);
    if (solver.info() != Eigen::Success) throw SolverError("miq: CHOLMOD failed to factorize the parametrization system");
  };
  // Solve with `held` unknowns fixed at y's values.
  auto solve_held = [&](const std::vector<char>& fixed, Eigen::VectorXd& y) {
    Eigen::VectorXd fixed_values = Eigen::VectorXd::Zero(n_free);
    for (Eigen::Index k = 0; k < n_free; ++k) fixed_values[k] = fixed[k] ? y[k] : 0.0;
    Eigen::VectorXd rhs = g - H * fixed_values;
    for (Eigen::Index k = 0; k < n_free; ++k) {
      if (fixed[k]) rhs[k] = y[k];
    }
    factorize(with_held_identity(H, fixed));
    y = solver.solve(rhs);
    if (!y.allFinite()) throw SolverError("miq: the parametrization solve did not give finite values");
  };
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n_free);
  solve_held(held, y);
  // Calibration to options.target_quads: every constraint row is homogeneous (c = 0, the gauge
  // held at 0), so the continuous map is linear in s; scaling s, the targets, g and y by k
  // scales the map's (u, v) area by k², with no second solve.
  if (options.target_quads > 0 && c.isZero()) {
    const Eigen::VectorXd x = Z * y;
    double area = 0;
    for (Eigen::Index f = 0; f < m; ++f) {
      const Eigen::Index a = 2 * Fc(f, 0), b = 2 * Fc(f, 1), d = 2 * Fc(f, 2);
      area += 0.5 * ((x[b] - x[a]) * (x[d + 1] - x[a + 1]) - (x[b + 1] - x[a + 1]) * (x[d] - x[a]));
    }
    const double k = std::sqrt(options.target_quads / area);
    if (area > 0 && std::isfinite(k) && k > 0) {
      s *= k, h /= k;
      target_u *= k, target_v *= k;
      g *= k, y *= k;
    }
  }
  result.target_edge_length = std::ldexp(h, mesh.frame.exponent);
  progress.report(0.3, "miq: rounding");

  // Separations: two integer corners of one coordinate (feature-line corners, cones) on
  // different iso-lines (their difference is not identically 0) within a quad edge of each
  // other, the continuous map putting them apart mostly across that coordinate (|Δc| > |Δ
  // other|): the rounding must keep them on distinct lines in the same order. Rounding them onto
  // one integer collapses the strip of triangles between them (fandisk at 3,000 quads: two
  // feature lines 0.2 quad edges apart, a cone 0.4 quad edges from a feature line, all 34 flips).
  const auto N = static_cast<Eigen::Index>(integer_free.size());
  struct Separation {
    std::vector<Term> terms;  // over integer_free positions
    double constant = 0;
    double sign = 1;          // sign · (Σ terms + constant) ≥ 1 required
  };
  std::vector<Separation> separations;
  std::vector<std::vector<int>> separations_of(N);
  if (N > 0 && options.sharp_angle_degrees > 0) {
    std::vector<int> position(n_free, -1);
    for (Eigen::Index r = 0; r < N; ++r) position[integer_free[r]] = static_cast<int>(r);
    const Eigen::VectorXd x = Z * y + c;
    std::vector<std::vector<int>> neighbours(nc);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) neighbours[Fc(f, k)].push_back(Fc(f, (k + 1) % 3)), neighbours[Fc(f, (k + 2) % 3)].push_back(Fc(f, k));
    std::vector<double> reached(nc, -1);
    std::vector<int> visited;
    for (Eigen::Index i = 0; i < nc; ++i) {
      if (!integer[2 * i] && !integer[2 * i + 1]) continue;
      // the cut-mesh vertices within one quad edge (path length) of i: a small Dijkstra-like sweep
      visited.assign(1, static_cast<int>(i));
      reached[i] = 0;
      for (std::size_t head = 0; head < visited.size(); ++head) {
        const int a = visited[head];
        for (const int b : neighbours[a]) {
          const double d = reached[a] + (P.row(a) - P.row(b)).norm();
          if (d > h || (reached[b] >= 0 && reached[b] <= d)) continue;
          if (reached[b] < 0) visited.push_back(b);
          reached[b] = d;
        }
      }
      for (const int j : visited) {
        reached[j] = -1;
        if (j <= i) continue;
        for (int coordinate = 0; coordinate < 2; ++coordinate) {
          const int p = static_cast<int>(2 * i + coordinate), q = 2 * j + coordinate;
          if (!integer[p] || !integer[q]) continue;
          const double across = x[q] - x[p], along = x[2 * j + 1 - coordinate] - x[2 * i + 1 - coordinate];
          if (!(std::abs(across) > std::abs(along))) continue;
          Expression difference = eliminator.expression_of(q);
          const Expression other = eliminator.expression_of(p);
          difference.constant -= other.constant;
          for (const Term& t : other.terms) difference.terms.push_back({t.variable, -t.coefficient});
          std::sort(difference.terms.begin(), difference.terms.end(),
                    [](const Term& a, const Term& b) { return a.variable < b.variable; });
          Separation separation;
          separation.constant = difference.constant;
          separation.sign = across > 0 ? 1.0 : -1.0;
          bool integral = true;
          for (std::size_t k = 0; k < difference.terms.size();) {
            Term merged = difference.terms[k];
            for (++k; k < difference.terms.size() && difference.terms[k].variable == merged.variable; ++k)
              merged.coefficient += difference.terms[k].coefficient;
            if (std::abs(merged.coefficient) < 1e-12) continue;
            const int column = free_index[merged.variable];
            if (position[column] >= 0) separation.terms.push_back({position[column], merged.coefficient});
            else if (held[column]) separation.constant += merged.coefficient * y[column];
            else integral = false;
          }
          if (!integral || separation.terms.empty()) continue;  // the same iso-line, or not integer-valued
          for (const Term& t : separation.terms) separations_of[t.variable].push_back(static_cast<int>(separations.size()));
          separations.push_back(std::move(separation));
        }
      }
    }
  }

  result.separations = static_cast<Eigen::Index>(separations.size());

  // Step 2: greedy rounding on the integer block of H⁻¹ (with `held` already fixed).
  if (N > 0) {
    Eigen::MatrixXd S(N, N);
    // the core's supernodal substitution: its forward pass skips the supernodes a unit column
    // has not reached (pmp-bunny at 3,000 quads: MIQ 1.39 -> 1.32 s, medians of 6, load 5)
    const meshsmith::detail::SupernodalSolve substitution(*solver.factor());
    constexpr Eigen::Index kBlock = 32;
    for (Eigen::Index start = 0; start < N; start += kBlock) {
      const Eigen::Index width = std::min(kBlock, N - start);
      Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(n_free, width);
      for (Eigen::Index k = 0; k < width; ++k) unit(integer_free[start + k], k) = 1.0;
      const Eigen::MatrixXd columns = substitution.solve(unit);
      for (Eigen::Index k = 0; k < width; ++k)
        for (Eigen::Index r = 0; r < N; ++r) S(r, start + k) = columns(integer_free[r], k);
      progress.report(0.3 + 0.3 * static_cast<double>(start + width) / static_cast<double>(N), "miq: rounding");
    }
    Eigen::VectorXd yI(N);
    for (Eigen::Index r = 0; r < N; ++r) yI[r] = y[integer_free[r]];
    std::vector<char> rounded(N, 0);
    for (Eigen::Index step = 0; step < N; ++step) {
      Eigen::Index best = -1;
      double best_residual = std::numeric_limits<double>::infinity();
      for (Eigen::Index r = 0; r < N; ++r) {
        if (rounded[r]) continue;
        const double residual = std::abs(yI[r] - std::round(yI[r]));
        if (residual < best_residual) best_residual = residual, best = r;
      }
      result.rounding_residual = std::max(result.rounding_residual, best_residual);
      // The integer closest to yI[best] that keeps every separation whose other unknowns are
      // rounded (the nearest four tried; none: the nearest, counted as a conflict).
      double target = std::round(yI[best]);
      if (!separations_of[best].empty()) {
        const double nearest = target, side = yI[best] >= nearest ? 1.0 : -1.0;
        bool found = false;
        for (const double candidate : {nearest, nearest + side, nearest - side, nearest + 2 * side}) {
          bool kept = true;
          for (const int k : separations_of[best]) {
            const Separation& separation = separations[k];
            double value = separation.constant;
            bool complete = true;
            for (const Term& t : separation.terms) {
              if (t.variable == best) value += t.coefficient * candidate;
              else if (rounded[t.variable]) value += t.coefficient * yI[t.variable];
              else complete = false;
            }
            if (complete && separation.sign * value < 1 - 1e-9) kept = false;
          }
          if (kept) {
            target = candidate, found = true;
            break;
          }
        }
        result.separation_conflicts += !found;
      }
      const double delta = yI[best] - target, pivot = S(best, best);
      rounded[best] = 1;
      if (pivot > 1e-14 * S.diagonal().cwiseAbs().maxCoeff()) {
        const Eigen::VectorXd column = S.col(best);
        yI -= column * (delta / pivot);
        S.noalias() -= column * (column.transpose() / pivot);
      }
      yI[best] = target;
      if (step % 16 == 0) progress.report(0.6 + 0.2 * static_cast<double>(step) / static_cast<double>(N), "miq: rounding");
    }
    for (Eigen::Index r = 0; r < N; ++r) {
      y[integer_free[r]] = yI[r];
      held[integer_free[r]] = 1;
    }
  }

  // Step 3: the continuous unknowns with the integers held; then the repair of flips.
  auto corner_uv = [&](const Eigen::VectorXd& y_free) {
    const Eigen::VectorXd x = Z * y_free + c;
    CornerUV uv(m, 6);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) uv(f, 2 * k) = x[2 * Fc(f, k)], uv(f, 2 * k + 1) = x[2 * Fc(f, k) + 1];
    return uv;
  };
  solve_held(held, y);
  result.uv = corner_uv(y);
  std::vector<char> flipped;
  result.flipped_before = result.flipped_after = detail::count_flipped(result.uv, &flipped);

  // The repair re-solves locally: stiffening changes the weights of a few faces, and the map
  // re-solved on the unknowns within kRepairRadius quad edges of them (the rest kept at the
  // unit-weight map) costs a factorization of that block instead of the whole system (pmp-bunny
  // at 3,000 quads: 0.23 s a round for assembly + factorization of 69,666 unknowns). The
  // system's unit-weight part is kept; the stiffened faces' part is added to it.
  constexpr double kRepairRadius = 3.0;
  const Sparse H_unit = H;  // unit weights, the integers not yet held
  const Eigen::VectorXd g_unit = g;
  const Sparse Zt = Z.transpose();
  std::vector<std::vector<int>> vertex_neighbours(mesh.V.rows());
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    vertex_neighbours[incidence.edges(e, 0)].push_back(incidence.edges(e, 1));
    vertex_neighbours[incidence.edges(e, 1)].push_back(incidence.edges(e, 0));
  }
  // `base` (its integers held) re-solved with the face weights `stiffened` on the free
  // unknowns of the vertices within kRepairRadius quad edges (path length) of a stiffened face
  // (on a small mesh that is most of them: the block, assembled from H_unit's entries, then
  // costs less than re-assembling the whole system through Z).
  Solver block_solver;
  detail::configure_cholmod(block_solver);
  Sparse block_pattern;  // the block last analyzed by block_solver
  auto local_resolve = [&](const Eigen::VectorXd& stiffened, const Eigen::VectorXd& base) {
    std::vector<int> changed;
    for (Eigen::Index f = 0; f < m; ++f)
      if (stiffened[f] != 1.0) changed.push_back(static_cast<int>(f));
    std::vector<double> distance(mesh.V.rows(), std::numeric_limits<double>::infinity());
    std::vector<int> queue;
    for (const int f : changed)
      for (int k = 0; k < 3; ++k)
        if (distance[F(f, k)] != 0) distance[F(f, k)] = 0, queue.push_back(F(f, k));
    const double radius = kRepairRadius * h;
    for (std::size_t head = 0; head < queue.size(); ++head) {  // label-correcting sweep
      const int a = queue[head];
      for (const int b : vertex_neighbours[a]) {
        const double d = distance[a] + (mesh.V.row(a) - mesh.V.row(b)).norm();
        if (d > radius || d >= distance[b]) continue;
        distance[b] = d;
        queue.push_back(b);
      }
    }
    std::vector<int> local(n_free, -1), columns;
    for (Eigen::Index i = 0; i < nc; ++i) {
      if (!std::isfinite(distance[cut.vertex_origin[i]])) continue;
      for (int d = 0; d < 2; ++d) {
        for (Sparse::InnerIterator it(Zt, 2 * i + d); it; ++it) {
          const auto column = it.row();
          if (held[column] || local[column] >= 0) continue;
          local[column] = static_cast<int>(columns.size());
          columns.push_back(static_cast<int>(column));
        }
      }
    }
    Eigen::VectorXd candidate = base;
    // The block is assembled on the local columns only (through sparse products of the whole
    // system it took 12 of a round's 30 ms on pmp-bunny at 3,000 quads): the unit-weight part is
    // read off H_unit's columns, and the stiffened faces' added energy is assembled on their own
    // corners (numbered locally) and mapped through those corners' rows of Z. Unknowns outside
    // the block (held, or beyond the radius) keep base's values and move to the right-hand side.
    const auto n_local = static_cast<Eigen::Index>(columns.size());
    std::vector<Eigen::Triplet<double>> block_triplets;
    Eigen::VectorXd rhs(n_local);
    for (Eigen::Index j = 0; j < n_local; ++j) {
      double value = g_unit[columns[j]];
      for (Sparse::InnerIterator it(H_unit, columns[j]); it; ++it) {
        const int i = local[it.row()];
        if (i >= 0) block_triplets.emplace_back(i, static_cast<int>(j), it.value());
        else value -= it.value() * base[it.row()];
      }
      rhs[j] = value;
    }
    const auto n_changed = static_cast<Eigen::Index>(changed.size());
    std::vector<int> corner_slot(nc, -1), corners;
    FaceMatrix changed_faces(n_changed, 3);
    for (Eigen::Index k = 0; k < n_changed; ++k) {
      for (int a = 0; a < 3; ++a) {
        const int corner = Fc(changed[k], a);
        if (corner_slot[corner] < 0) corner_slot[corner] = static_cast<int>(corners.size()), corners.push_back(corner);
        changed_faces(k, a) = corner_slot[corner];
      }
    }
    const auto n_rows = 2 * static_cast<Eigen::Index>(corners.size());
    VertexMatrix corner_P(static_cast<Eigen::Index>(corners.size()), 3);
    for (std::size_t k = 0; k < corners.size(); ++k) corner_P.row(static_cast<Eigen::Index>(k)) = P.row(corners[k]);
    VertexMatrix changed_u(n_changed, 3), changed_v(n_changed, 3);
    Eigen::VectorXd added_weight(n_changed);
    for (Eigen::Index k = 0; k < n_changed; ++k) {
      changed_u.row(k) = target_u.row(changed[k]);
      changed_v.row(k) = target_v.row(changed[k]);
      added_weight[k] = stiffened[changed[k]] - 1.0;
    }
    Sparse added_K;
    Eigen::VectorXd added_b;
    detail::assemble_energy(corner_P, changed_faces, changed_u, changed_v, added_weight, n_rows, added_K, added_b);
    // x_r = Z_r y + c_r on the corners' rows: Z_r's local columns, and the rest with base's values
    std::vector<Eigen::Triplet<double>> z_local;
    Eigen::VectorXd x_fixed(n_rows);
    for (Eigen::Index r = 0; r < n_rows; ++r) {
      const Eigen::Index variable = 2 * corners[r / 2] + r % 2;
      x_fixed[r] = c[variable];
      for (Sparse::InnerIterator it(Zt, variable); it; ++it) {
        const int j = local[it.row()];
        if (j >= 0) z_local.emplace_back(static_cast<int>(r), j, it.value());
        else x_fixed[r] += it.value() * base[it.row()];
      }
    }
    Sparse Z_rows(n_rows, n_local);
    Z_rows.setFromTriplets(z_local.begin(), z_local.end());
    Sparse block(n_local, n_local);
    block.setFromTriplets(block_triplets.begin(), block_triplets.end());
    block += Sparse(Z_rows.transpose() * added_K * Z_rows);
    rhs += Z_rows.transpose() * (added_b - added_K * x_fixed);
    // Successive rounds often stiffen within one region: the same block pattern, whose ordering
    // and symbolic factorization are then reused.
    const bool same_pattern = block.nonZeros() == block_pattern.nonZeros() && block.cols() == block_pattern.cols() &&
                              std::equal(block.outerIndexPtr(), block.outerIndexPtr() + block.cols() + 1, block_pattern.outerIndexPtr()) &&
                              std::equal(block.innerIndexPtr(), block.innerIndexPtr() + block.nonZeros(), block_pattern.innerIndexPtr());
    if (!same_pattern) {
      block_solver.analyzePattern(block);
      block_pattern = block;
    }
    block_solver.factorize(block);
    if (block_solver.info() != Eigen::Success) throw SolverError("miq: CHOLMOD failed to factorize the repair system");
    const Eigen::VectorXd inside = block_solver.solve(rhs);
    if (!inside.allFinite()) throw SolverError("miq: the repair solve did not give finite values");
    for (std::size_t j = 0; j < columns.size(); ++j) candidate[columns[j]] = inside[static_cast<Eigen::Index>(j)];
    return candidate;
  };
  // The stiffening repair of the map `rounded` (integers held, solved at unit weights).
  auto repair = [&](const Eigen::VectorXd& rounded, CornerUV& uv, Eigen::Index& count, std::vector<char> flips) {
    return detail::repair_by_stiffening(
        F, mesh.V.rows(), options.repair_iterations, options.stiffening, Eigen::VectorXd::Ones(m), uv, count,
        std::move(flips),
        [&](const Eigen::VectorXd& stiffened) { return corner_uv(local_resolve(stiffened, rounded)); },
        [&](int round) { progress.report(0.8 + 0.15 * round / std::max(1, options.repair_iterations), "miq: repair"); });
  };
  result.repair_rounds = repair(y, result.uv, result.flipped_after, flipped);

  // Step 4: re-rounding. The flips the stiffening leaves are where the greedy rounding put two
  // cones onto one integer point or in an order the triangles between them cannot follow (kitten
  // at 2,000–5,000 quads: a +1 and a −1 cone on one edge, rounded onto one point, their two
  // triangles collapsed, det = 0; which roundings do so changed with the machine's BLAS kernel,
  // the continuous map being within rounding error of a half there). Each pass moves one integer
  // unknown that a corner near the flips (the flipped faces and their one ring) depends on by
  // ±1: every such move is solved once at unit weights (one factorization), the kRepairedMoves
  // with the fewest flips (then the least inverted area) are repaired by stiffening, and the
  // best is kept when it leaves fewer flips than before; at most kReroundPasses passes.
  constexpr int kReroundPasses = 4;
  constexpr std::size_t kRepairedMoves = 3;
  for (int pass = 0; options.reround && pass < kReroundPasses && result.flipped_after > 0; ++pass) {
    progress.report(0.95 + 0.05 * pass / kReroundPasses, "miq: re-rounding");
    std::vector<char> near(nc, 0), now_flipped;
    detail::count_flipped(result.uv, &now_flipped);
    for (Eigen::Index f = 0; f < m; ++f)
      if (now_flipped[f]) for (int k = 0; k < 3; ++k) near[Fc(f, k)] = 1;
    std::vector<char> corner(nc, 0);
    for (Eigen::Index f = 0; f < m; ++f)
      if (near[Fc(f, 0)] || near[Fc(f, 1)] || near[Fc(f, 2)]) for (int k = 0; k < 3; ++k) corner[Fc(f, k)] = 1;
    std::vector<int> candidates;
    std::vector<char> seen(n_free, 0);
    for (Eigen::Index i = 0; i < nc; ++i) {
      if (!corner[i]) continue;
      for (int d = 0; d < 2; ++d) {
        for (const Term& t : eliminator.expression_of(static_cast<int>(2 * i + d)).terms) {
          const int column = free_index[t.variable];
          if (column < 0 || seen[column] || !held[column] || !integer[t.variable]) continue;
          seen[column] = 1;
          candidates.push_back(column);
        }
      }
    }
    struct Move {
      Eigen::Index flips;
      double inverted;  // Σ max(0, −det) over the faces
      int column;
      double step;
    };
    std::vector<Move> moves;
    // `solver` still holds step 3's factorization: H at unit weights with these unknowns held
    // (the repair solves its own blocks; the re-rounding changes held values, not which are held).
    // y with one integer moved, solved at unit weights from that factorization. The map is
    // linear in the held values: a move is y's solve plus ±1 × the response to a unit change of
    // that unknown (H's column, negated, on the unknowns not held; 1 on its own row), and the
    // responses are solved kResponseBlock columns at a time (a solve per move and sign, one
    // column each, was half of MIQ's time on fandisk with sharp_angle=40).
    constexpr Eigen::Index kResponseBlock = 32;
    Eigen::VectorXd held_values = Eigen::VectorXd::Zero(n_free);
    for (Eigen::Index k = 0; k < n_free; ++k) held_values[k] = held[k] ? y[k] : 0.0;
    Eigen::VectorXd rhs = g - H * held_values;
    for (Eigen::Index k = 0; k < n_free; ++k)
      if (held[k]) rhs[k] = y[k];
    const Eigen::VectorXd unmoved = solver.solve(rhs);
    const meshsmith::detail::SupernodalSolve substitution(*solver.factor());  // (sparse columns: see step 2)
    auto responses = [&](const int* columns, Eigen::Index count) {
      Eigen::MatrixXd unit_changes = Eigen::MatrixXd::Zero(n_free, count);
      for (Eigen::Index k = 0; k < count; ++k) {
        for (Sparse::InnerIterator it(H, columns[k]); it; ++it)
          if (!held[it.row()]) unit_changes(it.row(), k) = -it.value();
        unit_changes(columns[k], k) = 1.0;
      }
      return Eigen::MatrixXd(substitution.solve(unit_changes));
    };
    auto moved = [&](int column, double step) { return Eigen::VectorXd(unmoved + step * responses(&column, 1).col(0)); };
    for (std::size_t start = 0; start < candidates.size(); start += kResponseBlock) {
      const auto count = std::min<Eigen::Index>(kResponseBlock, static_cast<Eigen::Index>(candidates.size() - start));
      const Eigen::MatrixXd response = responses(candidates.data() + start, count);
      for (Eigen::Index k = 0; k < count; ++k) {
        for (const double step : {-1.0, 1.0}) {
          const Eigen::VectorXd trial = unmoved + step * response.col(k);
          if (!trial.allFinite()) continue;
          const CornerUV uv = corner_uv(trial);
          Move move{detail::count_flipped(uv, nullptr), 0.0, candidates[start + static_cast<std::size_t>(k)], step};
          for (Eigen::Index f = 0; f < m; ++f) {
            const double det = (uv(f, 2) - uv(f, 0)) * (uv(f, 5) - uv(f, 1)) - (uv(f, 3) - uv(f, 1)) * (uv(f, 4) - uv(f, 0));
            move.inverted += std::max(0.0, -det);
          }
          moves.push_back(move);
        }
      }
    }
    std::sort(moves.begin(), moves.end(), [](const Move& a, const Move& b) {
      return a.flips != b.flips ? a.flips < b.flips : a.inverted < b.inverted;
    });
    bool improved = false;
    Eigen::VectorXd best_y;
    CornerUV best_uv;
    Eigen::Index best_count = result.flipped_after;
    int best_rounds = 0;
    std::vector<Eigen::VectorXd> trials;
    for (std::size_t k = 0; k < std::min(kRepairedMoves, moves.size()); ++k)
      trials.push_back(moved(moves[k].column, moves[k].step));
    for (Eigen::VectorXd& trial : trials) {
      CornerUV uv = corner_uv(trial);
      std::vector<char> trial_flipped;
      Eigen::Index count = detail::count_flipped(uv, &trial_flipped);
      const int rounds = repair(trial, uv, count, std::move(trial_flipped));
      if (count < best_count) {
        improved = true, best_count = count, best_y = trial, best_uv = std::move(uv), best_rounds = rounds;
        if (count == 0) break;
      }
    }
    if (!improved) break;
    y = std::move(best_y);
    result.uv = std::move(best_uv);
    result.flipped_after = best_count;
    result.repair_rounds += best_rounds;
    ++result.rerounded_integers;
  }
  return result;
}

}  // namespace

namespace detail {

void assemble_energy(const VertexMatrix& P, const FaceMatrix& Fc, const VertexMatrix& target_u,
                     const VertexMatrix& target_v, const Eigen::VectorXd& weight, Eigen::Index n_variables,
                     Eigen::SparseMatrix<double>& K, Eigen::VectorXd& b) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(18 * Fc.rows());
  b.setZero(n_variables);
  for (Eigen::Index f = 0; f < Fc.rows(); ++f) {
    const Eigen::Vector3d p[3] = {P.row(Fc(f, 0)), P.row(Fc(f, 1)), P.row(Fc(f, 2))};
    const Eigen::Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
    const double double_area = cross.norm();
    if (!(double_area > 0)) continue;
    const Eigen::Vector3d n = cross / double_area;
    Eigen::Vector3d gradient[3];
    for (int k = 0; k < 3; ++k) gradient[k] = n.cross(p[(k + 2) % 3] - p[(k + 1) % 3]) / double_area;
    const double wa = weight[f] * 0.5 * double_area;
    for (int a = 0; a < 3; ++a) {
      const int i = Fc(f, a);
      b[2 * i] += wa * target_u.row(f).dot(gradient[a]);
      b[2 * i + 1] += wa * target_v.row(f).dot(gradient[a]);
      for (int c = 0; c < 3; ++c) {
        const double value = wa * gradient[a].dot(gradient[c]);
        const int j = Fc(f, c);
        triplets.emplace_back(2 * i, 2 * j, value);
        triplets.emplace_back(2 * i + 1, 2 * j + 1, value);
      }
    }
  }
  K.resize(n_variables, n_variables);
  K.setFromTriplets(triplets.begin(), triplets.end());
}

Eigen::Index count_flipped(const CornerUV& uv, std::vector<char>* flipped) {
  Eigen::Index count = 0;
  if (flipped) flipped->assign(uv.rows(), 0);
  for (Eigen::Index f = 0; f < uv.rows(); ++f) {
    const double det = (uv(f, 2) - uv(f, 0)) * (uv(f, 5) - uv(f, 1)) - (uv(f, 3) - uv(f, 1)) * (uv(f, 4) - uv(f, 0));
    if (!(det > 0)) {
      ++count;
      if (flipped) (*flipped)[f] = 1;
    }
  }
  return count;
}

int repair_by_stiffening(const FaceRef& F, Eigen::Index n_vertices, int iterations, double stiffening,
                         Eigen::VectorXd weight, CornerUV& uv, Eigen::Index& flipped_count, std::vector<char> flipped,
                         const std::function<CornerUV(const Eigen::VectorXd&)>& resolve,
                         const std::function<void(int)>& on_round) {
  const Eigen::Index m = F.rows();
  // The faces around each vertex (for the stiffened neighbourhoods).
  std::vector<int> vertex_face_offsets(n_vertices + 1, 0), vertex_faces(3 * m);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) ++vertex_face_offsets[F(f, k) + 1];
  for (Eigen::Index v = 0; v < n_vertices; ++v) vertex_face_offsets[v + 1] += vertex_face_offsets[v];
  {
    std::vector<int> fill(vertex_face_offsets.begin(), vertex_face_offsets.end() - 1);
    for (Eigen::Index f = 0; f < m; ++f)
      for (int k = 0; k < 3; ++k) vertex_faces[fill[F(f, k)]++] = static_cast<int>(f);
  }
  // Each round stiffens the faces flipped in the best map so far (× stiffening) and the faces
  // around their corners (× √stiffening). (A region grown by one ring per round did worse on
  // pmp-bunny: 16 flips left instead of 6.)
  // A round that leaves more flips is undone (the weights go back to the best map's) and the
  // factor drops to its square root: at ×5 without backtracking rocker-arm kept all 13 of its
  // flips (every round overshot), with it 13 → 7 (at 3,000 quads).
  int stalled = 0, rounds = 0;
  double factor = stiffening;
  Eigen::VectorXd best_weight = weight;
  for (int round = 0; round < iterations && flipped_count > 0; ++round) {
    on_round(round);
    std::vector<char> stiffen(m, 0);
    for (Eigen::Index f = 0; f < m; ++f) {
      if (!flipped[f]) continue;
      for (int k = 0; k < 3; ++k)
        for (int j = vertex_face_offsets[F(f, k)]; j < vertex_face_offsets[F(f, k) + 1]; ++j) stiffen[vertex_faces[j]] = 1;
    }
    for (Eigen::Index f = 0; f < m; ++f) {
      // capped: beyond ~1e4 against the other faces the system loses its definiteness in floating point
      if (stiffen[f]) weight[f] = std::min(1e4, weight[f] * (flipped[f] ? factor : std::sqrt(factor)));
    }
    const CornerUV candidate = resolve(weight);
    std::vector<char> now_flipped;
    const Eigen::Index count = count_flipped(candidate, &now_flipped);
    ++rounds;
    if (count <= flipped_count) {
      stalled = count < flipped_count ? 0 : stalled + 1;
      uv = candidate;
      flipped_count = count;
      flipped = std::move(now_flipped);
      best_weight = weight;
    } else {
      ++stalled;
      weight = best_weight;
      factor = std::sqrt(factor);
    }
    if (stalled >= 3) break;  // three rounds without fewer flips: more stiffening does not help (pmp-bunny)
  }
  return rounds;
}

}  // namespace detail

MiqResult miq(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta, const MiqOptions& options,
              const Progress& progress) {
  const auto shared_mesh = detail::field_mesh(V, F, "miq");
  const FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "miq");
  // The many solves (the rounding's blocked solves, the re-rounding's scans) on one BLAS thread:
  // pmp-bunny's MIQ at 3,000 quads took the same wall time with OpenBLAS's two threads and 1.7×
  // the CPU time, its threads yielding to each other; and the result no longer depends on them.
  const meshsmith::detail::SingleThreadedBlas one_blas_thread;
  if (!std::isfinite(options.target_edge_length)) throw InputError("miq: target_edge_length is not finite");
  if (!std::isfinite(options.target_quads)) throw InputError("miq: target_quads is not finite");
  if (!std::isfinite(options.stiffening) || options.stiffening < 1) throw InputError("miq: stiffening must be ≥ 1");
  if (!(options.conformal_scale >= 0 && options.conformal_scale <= 1)) {
    throw InputError("miq: conformal_scale must be in [0, 1]");
  }
  progress.report(0.0, "miq: cut");
  const FieldCut cut = cut_graph(V, F, theta);
  const Eigen::Index n_edges = mesh.checked.incidence.n_edges();
  std::vector<char> released(n_edges, 0);
  // Feature constraints that the map cannot keep: where triangles stay flipped with the feature
  // iso-lines held, the feature edges within `radius` of them are released and the map solved
  // again, kept when it has fewer flips, else the radius grows by half a quad edge (at most
  // kReleaseRounds re-solves). On fandisk at 3,000 quads the flips left sit 1–2 quad edges from
  // a feature line, next to a −1 cone the field puts beside it. With the grid calibrated to
  // 3,000 quads (a 1.4% shorter quad edge) it took 8 re-solves (681 of 710 feature edges held,
  // on OpenBLAS's Haswell, SkylakeX and Sandybridge kernels alike); at 6 the pipeline fell back
  // to its third merge distance.
  //
  // The releases only help where the feature constraints cause the flips: before them the map is
  // solved once with every feature edge released, and when that keeps as many flips (the cones
  // fold the map, not the features) the rounds are skipped. pmp-bunny at sharp_angle=60 (139
  // "feature" edges from the scan's noise) ran all ten rounds in each of five merge distances that
  // folded anyway: 255 s.
  constexpr int kReleaseRounds = 10;
  MiqResult result = solve_map(mesh, F, options, progress.subrange(0.0, 1.0 / (1 + kReleaseRounds)), cut, released);
  const double unit = std::ldexp(result.target_edge_length, -mesh.frame.exponent);
  double radius = 1.0 * unit;
  int flipped_unconstrained = -1;
  if (result.flipped_after > 0 && result.feature_edges > 0) {
    flipped_unconstrained = solve_map(mesh, F, options, progress.subrange(0.0, 1.0 / (1 + kReleaseRounds)), cut,
                                      std::vector<char>(n_edges, 1)).flipped_after;
  }
  const bool releases_help = flipped_unconstrained < 0 || flipped_unconstrained < result.flipped_after;
  for (int round = 1; releases_help && round <= kReleaseRounds && result.flipped_after > 0 && result.feature_edges > 0;
       ++round) {
    std::vector<char> near(mesh.V.rows(), 0), flipped;
    detail::count_flipped(result.uv, &flipped);
    std::vector<Eigen::Vector3d> centres;  // the corners of the flipped triangles
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      if (flipped[f]) for (int k = 0; k < 3; ++k) centres.push_back(mesh.V.row(F(f, k)));
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
      for (const Eigen::Vector3d& c : centres) {
        if ((Eigen::Vector3d(mesh.V.row(v)) - c).norm() <= radius) {
          near[v] = 1;
          break;
        }
      }
    }
    std::vector<char> trial = released;
    const auto& edges = mesh.checked.incidence.edges;
    for (Eigen::Index e = 0; e < n_edges; ++e) trial[e] |= near[edges(e, 0)] || near[edges(e, 1)];
    MiqResult retry = solve_map(mesh, F, options,
                                progress.subrange(static_cast<double>(round) / (1 + kReleaseRounds),
                                                  static_cast<double>(round + 1) / (1 + kReleaseRounds)),
                                cut, trial);
    if (retry.flipped_after >= result.flipped_after) {
      radius += 0.5 * unit;
      continue;
    }
    released = std::move(trial);
    result = std::move(retry);
    result.release_rounds = round;
  }
  result.flipped_unconstrained = flipped_unconstrained;
  progress.report(1.0, "miq");
  return result;
}

}  // namespace meshsmith::quadrangulation
