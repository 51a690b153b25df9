// Cross fields in the power-4 representation (Knöppel et al. 2013): a cross {θ + kπ/2} is the
// complex number z = e^{4iθ}, so "the same cross after parallel transport" is the linear
// condition z_g = e^{4iκ_fg} z_f and the smoothness energy Σ w |z_g − e^{4iκ} z_f|² is a
// Hermitian quadratic form (each edge adds w to both diagonals and −w e^{4iκ} below them). Hard
// constraints are eliminated; the free block is positive definite once anything is fixed or
// softly pulled, and one complex CHOLMOD factorization solves it (one unknown per face: on a
// 100k-face mesh 1.9 s where its real 2×2-block form took 4.5–7.8 s, machine loaded).
// An unconstrained field is the smallest eigenvector of the generalized problem A z = λ M z
// (M the face areas), found by inverse iteration on A + εM with that one factorization reused.
// Period jumps and indices are read off the resulting angles; the index of a vertex is an
// integer up to round-off because the connection's holonomy around a vertex equals its angle
// defect mod 2π, so rounding it gives Poincaré–Hopf exactly.
//
// Rounding (options.rounding = resolve | greedy) works on the angle energy of MIQ (Bommes et
// al. 2009) with unreduced angles. The power-4 field is combed along a dual spanning forest
// rooted at the hard faces (BFS; one root, face 0, when nothing is hard), so the forest's jumps
// are 0: that is the gauge, and fixing them loses nothing. The plain real relaxation of the other
// jumps has the trivial zero-energy minimum of the forest's transported field; the power-4 field
// is a better one (Knöppel et al. 2013 §6), so it is the relaxed solution the rounding starts
// from. Greedy rounding (as CoMISo's multiple rounding): every free jump within kBatch of an
// integer is rounded at once and the angles relaxed by kGlobalSweeps Gauss–Seidel sweeps over
// all faces; then the jump closest to an integer is rounded, the faces within kRings dual rings
// of its edge get kLocalSweeps sweeps (the energy of an unrounded edge is zero: its real jump
// absorbs it, so a sweep sees the rounded and forest edges and the alignment only), the edges
// there are re-queued, and so on (a lazy heap: O(#E log #E) in all, no refactorization). Last,
// the angles are solved with every jump fixed — one real SPD factorization that also solves
// the resolve candidate (the power-4 jumps), so greedy can fall back to it.
#include "field_geometry.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/geometry/curvature.h>

#include <Eigen/CholmodSupport>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <mutex>
#include <queue>
#include <string>
#include <tuple>

namespace meshsmith::quadrangulation {

namespace detail {

FieldMesh::FieldMesh(const VertexRef& input_V, const FaceRef& F, const char* function) {
  auto normalized = parametrization::detail::normalized(input_V);
  V = std::move(normalized.V);
  frame = normalized.frame;
  checked = parametrization::detail::check_mesh(V, F, parametrization::detail::Requirement::any, function);
  const Eigen::Index m = F.rows();
  e1.resize(m, 3), e2.resize(m, 3), normal.resize(m, 3), area.resize(m);
  for (Eigen::Index f = 0; f < m; ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    area[f] = 0.5 * cross.norm();
    const Eigen::Vector3d n = cross.normalized(), x = (b - a).normalized();
    normal.row(f) = n, e1.row(f) = x, e2.row(f) = n.cross(x);
  }
  const auto& incidence = checked.incidence;
  const Eigen::Index n_edges = incidence.n_edges();
  edge_faces.setConstant(n_edges, 2, -1);
  connection.setZero(n_edges);
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    const int i = incidence.edges(e, 0), j = incidence.edges(e, 1);
    for (int k = incidence.edge_offsets[e]; k < incidence.edge_offsets[e + 1]; ++k) {
      edge_faces(e, k - incidence.edge_offsets[e]) = incidence.edge_sides[k] / 3;  // ≤ 2 sides (checked)
    }
    // Put the face whose side runs i → j first (the mesh is oriented: exactly one does).
    if (edge_faces(e, 1) >= 0) {
      const int f = edge_faces(e, 0);
      bool forward = false;
      for (int k = 0; k < 3; ++k) forward |= (F(f, k) == i && F(f, (k + 1) % 3) == j);
      if (!forward) std::swap(edge_faces(e, 0), edge_faces(e, 1));
      const Eigen::Vector3d d = V.row(j) - V.row(i);
      connection[e] = wrap_angle(angle_in_face(edge_faces(e, 1), d) - angle_in_face(edge_faces(e, 0), d));
    }
  }
}

namespace {

/// The state behind SharedFieldMesh: how many instances live, and the last mesh with its input.
struct FieldMeshCache {
  std::mutex mutex;
  int scopes = 0;
  VertexMatrix V;
  FaceMatrix F;
  std::shared_ptr<const FieldMesh> mesh;
};

FieldMeshCache& field_mesh_cache() {
  static FieldMeshCache cache;
  return cache;
}

}  // namespace

std::shared_ptr<const FieldMesh> field_mesh(const VertexRef& V, const FaceRef& F, const char* function) {
  FieldMeshCache& cache = field_mesh_cache();
  {
    const std::lock_guard<std::mutex> lock(cache.mutex);
    if (cache.scopes == 0) return std::make_shared<const FieldMesh>(V, F, function);
    if (cache.mesh && cache.V.rows() == V.rows() && cache.F.rows() == F.rows() && cache.V == V && cache.F == F)
      return cache.mesh;
  }
  auto mesh = std::make_shared<const FieldMesh>(V, F, function);  // (outside the lock: it takes a while)
  const std::lock_guard<std::mutex> lock(cache.mutex);
  if (cache.scopes > 0) cache.V = V, cache.F = F, cache.mesh = mesh;
  return mesh;
}

Eigen::VectorXi period_jumps(const FieldMesh& mesh, const Eigen::VectorXd& theta) {
  const Eigen::Index n_edges = mesh.edge_faces.rows();
  Eigen::VectorXi p = Eigen::VectorXi::Zero(n_edges);
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const double x = theta[g] - theta[f] - mesh.connection[e];
    int jump = static_cast<int>(std::lround((x - quarter_residual(x)) / kQuarter)) % 4;
    if (jump < -1) jump += 4;
    if (jump > 2) jump -= 4;
    p[e] = jump;
  }
  return p;
}

void check_angles(const Eigen::VectorXd& theta, Eigen::Index n_faces, const char* function) {
  if (theta.size() != n_faces) {
    throw InputError(std::string(function) + ": the field has " + std::to_string(theta.size()) +
                     " entries but the mesh has " + std::to_string(n_faces) + " faces");
  }
  for (Eigen::Index f = 0; f < n_faces; ++f) {
    if (!std::isfinite(theta[f])) {
      throw InputError(std::string(function) + ": the field is not finite at face " + std::to_string(f) +
                       " (NaN or Inf)");
    }
  }
}

std::vector<int> vertex_indices(const FieldMesh& mesh, const FaceRef& F, const Eigen::VectorXd& theta) {
  const auto& incidence = mesh.checked.incidence;
  const Eigen::Index n = mesh.V.rows(), m = F.rows();
  // Corner angles, the angle sums and, per vertex, one corner to start its fan from (the corner
  // whose side v → a is a boundary edge, on the boundary).
  std::vector<double> angle_sum(n, 0.0);
  std::vector<int> start(n, -1);
  std::vector<char> on_boundary(n, 0);
  for (Eigen::Index f = 0; f < m; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      const Eigen::Vector3d a = mesh.V.row(F(f, (k + 1) % 3)) - mesh.V.row(v);
      const Eigen::Vector3d b = mesh.V.row(F(f, (k + 2) % 3)) - mesh.V.row(v);
      angle_sum[v] += std::atan2(a.cross(b).norm(), a.dot(b));
      const int e = incidence.side_edge[3 * f + k];
      if (incidence.side_count(e) == 1) on_boundary[v] = 1, start[v] = static_cast<int>(3 * f + k);
      else if (start[v] < 0) start[v] = static_cast<int>(3 * f + k);
    }
  }
  std::vector<int> index(n, 0);
  for (Eigen::Index v = 0; v < n; ++v) {
    int corner = start[v];
    int f = corner / 3, k = corner % 3;
    double total = on_boundary[v] ? kPi - angle_sum[v] : 2 * kPi - angle_sum[v];
    if (on_boundary[v]) {  // from the first boundary edge v → a to the field
      const Eigen::Vector3d d = mesh.V.row(F(f, (k + 1) % 3)) - mesh.V.row(v);
      total += quarter_residual(theta[f] - mesh.angle_in_face(f, d));
    }
    for (Eigen::Index step = 0; step <= m; ++step) {
      // The next face counter-clockwise around v lies across side (k + 2) % 3 (b → v).
      const int e = incidence.side_edge[3 * f + (k + 2) % 3];
      if (incidence.side_count(e) == 1) {  // the last boundary edge, b → v, seen from v
        const Eigen::Vector3d d = mesh.V.row(F(f, (k + 2) % 3)) - mesh.V.row(v);
        total += quarter_residual(mesh.angle_in_face(f, d) - theta[f]);
        break;
      }
      const int g = mesh.other_face(e, f);
      total += quarter_residual(theta[g] - theta[f] - mesh.transport(e, f));
      f = g;
      k = 0;
      while (F(f, k) != v) ++k;
      if (3 * f + k == corner) break;
    }
    index[v] = static_cast<int>(std::lround(total / kQuarter));
  }
  return index;
}

}  // namespace detail

namespace {

using detail::FieldMesh;
using detail::kPi;
using detail::kQuarter;
using Complex = std::complex<double>;

/// Hard constraints: per face, the power-4 number of the constrained direction (0: free).
struct HardConstraints {
  std::vector<Complex> value;
  std::vector<char> fixed;
  explicit HardConstraints(Eigen::Index m) : value(m, 0.0), fixed(m, 0) {}
  void set(int f, double angle) {
    if (fixed[f]) return;  // the first constraint on a face wins
    fixed[f] = 1;
    value[f] = std::polar(1.0, 4 * angle);
  }
  Eigen::Index count() const { return std::count(fixed.begin(), fixed.end(), 1); }
};

/// The soft curvature targets: per face, the weight (0: none) and the unit power-4 target.
void curvature_targets(const FieldMesh& mesh, const FaceRef& F, double weight, std::vector<double>& mu,
                       std::vector<Complex>& target) {
  const Eigen::Index m = F.rows();
  const auto curvature = geometry::principal_curvatures(mesh.V, F);
  const double mean_area = mesh.area.mean();
  mu.assign(m, 0.0);
  target.assign(m, 0.0);
  for (Eigen::Index f = 0; f < m; ++f) {
    Complex sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      const double k1 = curvature.k1[v], k2 = curvature.k2[v], scale = std::abs(k1) + std::abs(k2);
      if (!(scale > 0)) continue;
      const Eigen::Vector3d d = curvature.d1.row(v);
      const Eigen::Vector3d tangent = d - d.dot(mesh.normal.row(f)) * Eigen::Vector3d(mesh.normal.row(f));
      if (tangent.squaredNorm() < 1e-12) continue;
      sum += std::polar((k1 - k2) / scale, 4 * mesh.angle_in_face(static_cast<int>(f), tangent));
    }
    const double strength = std::abs(sum) / 3;
    if (strength < 0.1) continue;  // isotropic or disagreeing: leave the face to smoothness
    mu[f] = weight * strength * mesh.area[f] / mean_area;
    target[f] = sum / std::abs(sum);
  }
}

using Solver = meshsmith::detail::MeshCholesky<Complex>;

void factorize(Solver& solver, const Eigen::SparseMatrix<Complex>& A) {
  meshsmith::detail::configure_cholesky(solver, meshsmith::detail::CholeskyKind::vertex_laplacian);
  solver.compute(A);
  if (solver.info() != Eigen::Success) throw SolverError("cross_field: CHOLMOD failed to factorize the field system");
}


/// w_e = |e|² / (A_f + A_g) per interior edge (0 on the boundary): the smoothness weights.
std::vector<double> edge_weights(const FieldMesh& mesh) {
  const auto& incidence = mesh.checked.incidence;
  std::vector<double> w(incidence.n_edges(), 0.0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const double length2 = (mesh.V.row(incidence.edges(e, 1)) - mesh.V.row(incidence.edges(e, 0))).squaredNorm();
    w[e] = length2 / (mesh.area[f] + mesh.area[g]);
  }
  return w;
}

/// Faces whose crease pull |C_f| (below, before the weight) is smaller are left to smoothness.
constexpr double kCreaseFloor = 0.02;

/// Adds the crease alignment to the soft targets (mu, target: per face, the weight and the
/// power-4 target, as curvature_targets leaves them; w: the smoothness weights). Each interior
/// edge e pulls both of its faces towards its direction with c_e = w_e (1 − cos β_e), β_e the
/// dihedral angle: the extrinsic misfit of a cross across a fold (a direction at φ to the edge
/// is bent by the fold: |Δ|² = 2(1 − cos β) sin²φ, as in Instant Meshes' extrinsic smoothness),
/// so smooth parts (β ≈ κh: second order) are left to smoothness while CAD creases are followed.
/// Per face the pulls are summed, C_f = Σ c_e t_e (t_e: the edge's unit power-4 direction), and
/// kept where |C_f| ≥ kCreaseFloor: a face whose edges fold alike in every direction (an
/// icosphere's lattice) has pulls that cancel to a little noise, and that noise anchored the
/// whole solve (the icosphere's 8 cones became 32 at any weight ≥ 0.01). The face's
/// S = μ t + weight C_f then gives μ = |S| and target S/|S|: only the agreement pulls.
void crease_targets(const FieldMesh& mesh, const std::vector<double>& w, double weight, std::vector<double>& mu,
                    std::vector<Complex>& target) {
  const auto& incidence = mesh.checked.incidence;
  std::vector<Complex> crease(mu.size(), 0.0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const double c = w[e] * (1.0 - std::clamp(mesh.normal.row(f).dot(mesh.normal.row(g)), -1.0, 1.0));
    if (!(c > 0)) continue;
    const Eigen::Vector3d d = mesh.V.row(incidence.edges(e, 1)) - mesh.V.row(incidence.edges(e, 0));
    for (const int h : {f, g}) crease[h] += c * std::polar(1.0, 4 * mesh.angle_in_face(h, d));
  }
  for (std::size_t f = 0; f < mu.size(); ++f) {
    if (!(std::abs(crease[f]) >= kCreaseFloor)) continue;
    const Complex sum = mu[f] * target[f] + weight * crease[f];
    mu[f] = std::abs(sum);
    target[f] = mu[f] > 0 ? sum / mu[f] : Complex(0.0);
  }
}

/// The alignment of the angle energy: per face μ_f (0: none) and the target angle θ*_f.
struct Alignment {
  std::vector<double> mu;
  std::vector<double> angle;
};

/// E(θ) = Σ_e w_e r(θ_g − θ_f − κ_e)² + Σ_f μ_f r(θ_f − θ*_f)², r the residual mod π/2 (the
/// jumps and the alignment's quarter turns taken nearest).
double angle_energy(const FieldMesh& mesh, const std::vector<double>& w, const Alignment& alignment,
                    const Eigen::VectorXd& theta) {
  double energy = 0.0;
  for (Eigen::Index e = 0; e < mesh.edge_faces.rows(); ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const double r = detail::quarter_residual(theta[g] - theta[f] - mesh.connection[e]);
    energy += w[e] * r * r;
  }
  for (std::size_t f = 0; f < alignment.mu.size(); ++f) {
    if (alignment.mu[f] == 0) continue;
    const double r = detail::quarter_residual(theta[f] - alignment.angle[f]);
    energy += alignment.mu[f] * r * r;
  }
  return energy;
}

/// A choice of integer jumps (combed gauge, per edge) and the angles they were found with.
struct JumpCandidate {
  std::vector<int> jumps;
  Eigen::VectorXd theta;
};

/// For each candidate, the angles minimizing Σ_e w_e (θ_g − θ_f − κ_e − π/2·p_e)² +
/// Σ_f μ_f (θ_f − a_f)² with its jumps fixed (a_f: the target θ*_f turned nearest to the
/// candidate's angle) and the `held` faces kept at the candidate's angles — one factorization.
std::vector<Eigen::VectorXd> solve_angles(const FieldMesh& mesh, const std::vector<double>& w, const Alignment& alignment,
                                          const std::vector<char>& held, const std::vector<JumpCandidate>& candidates) {
  const Eigen::Index m = mesh.n_faces(), n_edges = mesh.edge_faces.rows();
  std::vector<int> number(m, -1);
  int n_free = 0;
  for (Eigen::Index f = 0; f < m; ++f) {
    if (!held[f]) number[f] = n_free++;
  }
  std::vector<Eigen::VectorXd> solved;
  for (const auto& candidate : candidates) solved.push_back(candidate.theta);
  if (n_free == 0) return solved;
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(n_edges + m);
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n_free);
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const int a = number[f], b = number[g];
    if (a >= 0) diagonal[a] += w[e];
    if (b >= 0) diagonal[b] += w[e];
    if (a >= 0 && b >= 0) triplets.emplace_back(std::max(a, b), std::min(a, b), -w[e]);
  }
  for (Eigen::Index f = 0; f < m; ++f) {
    if (number[f] >= 0) diagonal[number[f]] += alignment.mu[f];
  }
  for (int i = 0; i < n_free; ++i) triplets.emplace_back(i, i, diagonal[i]);
  Eigen::SparseMatrix<double> A(n_free, n_free);
  A.setFromTriplets(triplets.begin(), triplets.end());
  detail::Cholesky solver;
  detail::configure_cholmod(solver);
  solver.compute(A);
  if (solver.info() != Eigen::Success) throw SolverError("cross_field: CHOLMOD failed to factorize the angle system");
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    const Eigen::VectorXd& theta = candidates[c].theta;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_free);
    for (Eigen::Index e = 0; e < n_edges; ++e) {
      const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
      if (g < 0) continue;
      const double shift = w[e] * (mesh.connection[e] + kQuarter * candidates[c].jumps[e]);
      const int a = number[f], b = number[g];
      if (a >= 0) rhs[a] -= shift;
      if (b >= 0) rhs[b] += shift;
      if (a >= 0 && b < 0) rhs[a] += w[e] * theta[g];
      if (b >= 0 && a < 0) rhs[b] += w[e] * theta[f];
    }
    for (Eigen::Index f = 0; f < m; ++f) {
      const double mu = alignment.mu[f];
      if (number[f] < 0 || mu == 0) continue;
      const double target = theta[f] - detail::quarter_residual(theta[f] - alignment.angle[f]);
      rhs[number[f]] += mu * target;
    }
    const Eigen::VectorXd x = solver.solve(rhs);
    if (!x.allFinite()) throw SolverError("cross_field: the angle solve did not give finite values");
    for (Eigen::Index f = 0; f < m; ++f) {
      if (number[f] >= 0) solved[c][f] = x[number[f]];
    }
  }
  return solved;
}

constexpr double kBatch = 0.1;     // jumps this close to an integer are rounded together, first
constexpr int kGlobalSweeps = 3;   // Gauss–Seidel sweeps over all faces after that batch
constexpr int kRings = 2;          // a single rounding relaxes the faces this many dual rings around its edge
constexpr int kLocalSweeps = 4;    // with this many sweeps

/// The rounded field (FieldRounding::resolve or greedy) from the power-4 angles theta0; see the
/// top comment. hard: the hard faces (kept exactly). changed: set to the interior edges whose
/// jump, in the gauge of theta0 combed along the forest, differs from theta0's.
Eigen::VectorXd round_jumps(const FieldMesh& mesh, FieldRounding rounding, const std::vector<double>& w,
                            const Alignment& alignment, const std::vector<char>& hard, const Eigen::VectorXd& theta0,
                            const Progress& progress, Eigen::Index& changed) {
  const auto& incidence = mesh.checked.incidence;
  const Eigen::Index m = mesh.n_faces(), n_edges = mesh.edge_faces.rows();
  // The forest and the combed angles (forest jumps 0).
  std::vector<char> held(hard.begin(), hard.end());
  std::vector<int> queue;
  queue.reserve(m);
  for (Eigen::Index f = 0; f < m; ++f) {
    if (hard[f]) queue.push_back(static_cast<int>(f));
  }
  const bool anchored = !queue.empty() || std::any_of(alignment.mu.begin(), alignment.mu.end(), [](double x) { return x > 0; });
  if (queue.empty()) {
    queue.push_back(0);
    if (!anchored) held[0] = 1;  // E is invariant under a global turn: pinning one face loses nothing
  }
  std::vector<char> reached(m, 0), fixed(n_edges, 0);
  for (const int f : queue) reached[f] = 1;
  Eigen::VectorXd theta = theta0;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int f = queue[head];
    for (int k = 0; k < 3; ++k) {
      const int e = incidence.side_edge[3 * f + k];
      const int g = mesh.other_face(e, f);
      if (g < 0 || reached[g]) continue;
      reached[g] = 1, fixed[e] = 1;
      const double t = mesh.transport(e, f);
      theta[g] = theta[f] + t + detail::quarter_residual(theta0[g] - theta[f] - t);
      queue.push_back(g);
    }
  }
  auto relaxed_jump = [&](int e) {
    return (theta[mesh.edge_faces(e, 1)] - theta[mesh.edge_faces(e, 0)] - mesh.connection[e]) / kQuarter;
  };
  auto interior = [&](int e) { return mesh.edge_faces(e, 1) >= 0; };
  JumpCandidate resolve{std::vector<int>(n_edges, 0), theta};
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    if (interior(static_cast<int>(e))) resolve.jumps[e] = static_cast<int>(std::lround(relaxed_jump(static_cast<int>(e))));
  }
  std::vector<JumpCandidate> candidates{resolve};
  if (rounding == FieldRounding::greedy) {
    std::vector<int> jump(n_edges, 0);
    std::vector<double> aligned(m, 0.0);  // the alignment targets turned nearest to the start
    for (Eigen::Index f = 0; f < m; ++f) {
      if (alignment.mu[f] > 0) aligned[f] = theta[f] - detail::quarter_residual(theta[f] - alignment.angle[f]);
    }
    auto sweep = [&](int f) {  // θ_f minimizing its rounded/forest edges' and alignment terms
      if (held[f]) return;
      double numerator = alignment.mu[f] * aligned[f], denominator = alignment.mu[f];
      for (int k = 0; k < 3; ++k) {
        const int e = incidence.side_edge[3 * f + k];
        const int g = mesh.other_face(e, f);
        if (g < 0 || !fixed[e]) continue;
        const double shift = mesh.connection[e] + kQuarter * jump[e];  // θ_f1 ≈ θ_f0 + shift
        numerator += w[e] * (mesh.edge_faces(e, 0) == f ? theta[g] - shift : theta[g] + shift);
        denominator += w[e];
      }
      if (denominator > 0) theta[f] = numerator / denominator;
    };
    auto distance = [&](int e) {
      const double x = relaxed_jump(e);
      return std::abs(x - std::round(x));
    };
    for (Eigen::Index e = 0; e < n_edges; ++e) {
      if (interior(static_cast<int>(e)) && !fixed[e] && distance(static_cast<int>(e)) < kBatch) {
        jump[e] = static_cast<int>(std::lround(relaxed_jump(static_cast<int>(e))));
        fixed[e] = 1;
      }
    }
    for (int s = 0; s < kGlobalSweeps; ++s) {
      for (Eigen::Index f = 0; f < m; ++f) sweep(static_cast<int>(f));
    }
    progress.report(0.93, "cross field");
    using Entry = std::tuple<double, int, int>;  // (distance, edge, stamp)
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    std::vector<int> stamp(n_edges, 0);
    for (Eigen::Index e = 0; e < n_edges; ++e) {
      if (interior(static_cast<int>(e)) && !fixed[e]) heap.emplace(distance(static_cast<int>(e)), static_cast<int>(e), 0);
    }
    std::vector<int> seen(m, -1), region;
    int step = 0;
    while (!heap.empty()) {
      const auto [d, e, version] = heap.top();
      heap.pop();
      if (fixed[e] || version != stamp[e]) continue;
      jump[e] = static_cast<int>(std::lround(relaxed_jump(e)));
      fixed[e] = 1;
      ++step;
      region.assign({mesh.edge_faces(e, 0), mesh.edge_faces(e, 1)});
      seen[region[0]] = seen[region[1]] = step;
      for (std::size_t begin = 0, ring = 0; ring < static_cast<std::size_t>(kRings); ++ring) {
        const std::size_t end = region.size();
        for (std::size_t i = begin; i < end; ++i) {
          for (int k = 0; k < 3; ++k) {
            const int g = mesh.other_face(incidence.side_edge[3 * region[i] + k], region[i]);
            if (g >= 0 && seen[g] != step) seen[g] = step, region.push_back(g);
          }
        }
        begin = end;
      }
      for (int s = 0; s < kLocalSweeps; ++s) {
        for (const int f : region) sweep(f);
      }
      for (const int f : region) {
        for (int k = 0; k < 3; ++k) {
          const int a = incidence.side_edge[3 * f + k];
          if (!interior(a) || fixed[a]) continue;
          heap.emplace(distance(a), a, ++stamp[a]);
        }
      }
    }
    candidates.push_back({jump, theta});
  }
  progress.report(0.96, "cross field");
  const auto solved = solve_angles(mesh, w, alignment, held, candidates);
  // greedy: its own result unless the resolve candidate's energy is lower
  std::size_t best = solved.size() - 1;
  if (angle_energy(mesh, w, alignment, solved[0]) < angle_energy(mesh, w, alignment, solved[best])) best = 0;
  theta = solved[best];
  changed = 0;
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    if (interior(static_cast<int>(e))) changed += std::lround(relaxed_jump(static_cast<int>(e))) != resolve.jumps[e];
  }
  return theta;
}

}  // namespace

SharedFieldMesh::SharedFieldMesh() {
  detail::FieldMeshCache& cache = detail::field_mesh_cache();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  ++cache.scopes;
}

SharedFieldMesh::~SharedFieldMesh() {
  detail::FieldMeshCache& cache = detail::field_mesh_cache();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  if (--cache.scopes == 0) cache.mesh.reset(), cache.V.resize(0, 3), cache.F.resize(0, 3);
}

FieldEdges field_edges(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta) {
  const auto shared_mesh = detail::field_mesh(V, F, "field_edges");
  const FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "field_edges");
  FieldEdges out;
  out.edges = mesh.checked.incidence.edges;
  out.faces = mesh.edge_faces;
  out.connection = mesh.connection;
  out.period_jumps = detail::period_jumps(mesh, theta);
  return out;
}

ResolvedAngles resolve_angles(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta,
                              const std::vector<int>& jumps, const std::vector<char>& held) {
  const auto shared_mesh = detail::field_mesh(V, F, "resolve_angles");
  const FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "resolve_angles");
  const Eigen::Index n_edges = mesh.edge_faces.rows();
  if (static_cast<Eigen::Index>(jumps.size()) != n_edges) {
    throw InputError("resolve_angles: " + std::to_string(jumps.size()) + " jumps for " + std::to_string(n_edges) + " edges");
  }
  if (static_cast<Eigen::Index>(held.size()) != F.rows()) {
    throw InputError("resolve_angles: held has " + std::to_string(held.size()) + " entries for " +
                     std::to_string(F.rows()) + " faces");
  }
  const std::vector<double> w = edge_weights(mesh);
  double total = 0;
  Eigen::Index interior = 0;
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    if (mesh.edge_faces(e, 1) >= 0) total += w[e], ++interior;
  }
  Alignment pull;
  pull.mu.assign(F.rows(), interior > 0 ? 1e-9 * total / static_cast<double>(interior) : 1e-9);
  pull.angle.assign(theta.data(), theta.data() + theta.size());
  ResolvedAngles out;
  out.theta = solve_angles(mesh, w, pull, held, {JumpCandidate{jumps, theta}}).front();
  for (Eigen::Index f = 0; f < out.theta.size(); ++f) {
    out.theta[f] -= detail::kQuarter * std::floor(out.theta[f] / detail::kQuarter);
    if (!(out.theta[f] < detail::kQuarter)) out.theta[f] = 0;  // a tiny negative angle rounded up to π/2
  }
  out.period_jumps = detail::period_jumps(mesh, out.theta);
  const auto index = detail::vertex_indices(mesh, F, out.theta);
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] != 0) out.singularities.vertices.push_back(static_cast<int>(v)), out.singularities.indices.push_back(index[v]);
  }
  return out;
}

Eigen::VectorXd field_angles(const VertexRef& V, const FaceRef& F, const VertexRef& directions) {
  const auto shared_mesh = detail::field_mesh(V, F, "field_angles");
  const FieldMesh& mesh = *shared_mesh;
  if (directions.rows() != F.rows()) {
    throw InputError("field_angles: the field has " + std::to_string(directions.rows()) + " rows but the mesh has " +
                     std::to_string(F.rows()) + " faces");
  }
  Eigen::VectorXd theta(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d d = directions.row(f);
    if (!d.allFinite()) throw InputError("field_angles: the field is not finite at face " + std::to_string(f) + " (NaN or Inf)");
    const double x = d.dot(mesh.e1.row(f)), y = d.dot(mesh.e2.row(f));
    if (std::hypot(x, y) <= 1e-9 * d.norm() || d.norm() == 0) {
      throw InputError("field_angles: the direction of face " + std::to_string(f) + " is zero or normal to the face");
    }
    const double angle = std::atan2(y, x);
    theta[f] = angle - kQuarter * std::floor(angle / kQuarter);
  }
  return theta;
}

VertexMatrix field_directions(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta) {
  const auto shared_mesh = detail::field_mesh(V, F, "field_directions");
  const FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "field_directions");
  VertexMatrix directions(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    directions.row(f) = std::cos(theta[f]) * mesh.e1.row(f) + std::sin(theta[f]) * mesh.e2.row(f);
  }
  return directions;
}

Singularities singularities(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta) {
  const auto shared_mesh = detail::field_mesh(V, F, "singularities");
  const FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "singularities");
  const auto index = detail::vertex_indices(mesh, F, theta);
  Singularities out;
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] != 0) out.vertices.push_back(static_cast<int>(v)), out.indices.push_back(index[v]);
  }
  return out;
}

CrossField cross_field(const VertexRef& V, const FaceRef& F, const CrossFieldOptions& options, const Progress& progress) {
  const auto shared_mesh = detail::field_mesh(V, F, "cross_field");
  const FieldMesh& mesh = *shared_mesh;
  const auto& incidence = mesh.checked.incidence;
  const Eigen::Index m = F.rows(), n_edges = incidence.n_edges();
  progress.report(0.0, "cross field");

  // Hard constraints: user directions first, then features, then the boundary.
  HardConstraints hard(m);
  if (static_cast<Eigen::Index>(options.constraint_faces.size()) != options.constraint_directions.rows()) {
    throw InputError("cross_field: " + std::to_string(options.constraint_faces.size()) + " constraint faces but " +
                     std::to_string(options.constraint_directions.rows()) + " constraint directions");
  }
  for (std::size_t k = 0; k < options.constraint_faces.size(); ++k) {
    const int f = options.constraint_faces[k];
    if (f < 0 || f >= m) {
      throw InputError("cross_field: constraint " + std::to_string(k) + " names face " + std::to_string(f) +
                       ", outside [0, " + std::to_string(m) + ")");
    }
    const Eigen::Vector3d d = options.constraint_directions.row(static_cast<Eigen::Index>(k));
    const Eigen::Vector3d tangent = d - d.dot(mesh.normal.row(f)) * Eigen::Vector3d(mesh.normal.row(f));
    if (!d.allFinite() || !(tangent.norm() > 1e-9 * d.norm())) {
      throw InputError("cross_field: constraint direction " + std::to_string(k) + " (face " + std::to_string(f) +
                       ") is not finite, zero or normal to the face");
    }
    hard.set(f, mesh.angle_in_face(f, tangent));
  }
  if (!std::isfinite(options.sharp_angle_degrees)) throw InputError("cross_field: sharp_angle is not finite");
  const double cos_sharp = std::cos(options.sharp_angle_degrees * kPi / 180.0);
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    const Eigen::Vector3d d = mesh.V.row(incidence.edges(e, 1)) - mesh.V.row(incidence.edges(e, 0));
    const bool feature = g >= 0 && options.sharp_angle_degrees > 0 && mesh.normal.row(f).dot(mesh.normal.row(g)) < cos_sharp;
    const bool border = g < 0 && options.align != FieldAlignment::smooth;
    if (feature) hard.set(g, mesh.angle_in_face(g, d));
    if (feature || border) hard.set(f, mesh.angle_in_face(f, d));
  }
  const std::vector<double> weight = edge_weights(mesh);
  std::vector<double> mu(m, 0.0);
  std::vector<Complex> target(m, 0.0);
  if (options.align == FieldAlignment::curvature) {
    if (!(options.curvature_weight >= 0) || !std::isfinite(options.curvature_weight)) {
      throw InputError("cross_field: curvature_weight must be a finite number ≥ 0");
    }
    if (!(options.crease_weight >= 0) || !std::isfinite(options.crease_weight)) {
      throw InputError("cross_field: crease_weight must be a finite number ≥ 0");
    }
    curvature_targets(mesh, F, options.curvature_weight, mu, target);
    if (options.crease_weight > 0) crease_targets(mesh, weight, options.crease_weight, mu, target);
    for (Eigen::Index f = 0; f < m; ++f) {
      if (hard.fixed[f]) mu[f] = 0.0;  // a hard face's alignment is constant
    }
  }
  progress.report(0.2, "cross field");

  // Free faces are numbered; the system has the blocks of the free faces only.
  std::vector<int> free_index(m, -1);
  int n_free = 0;
  for (Eigen::Index f = 0; f < m; ++f) {
    if (!hard.fixed[f]) free_index[f] = n_free++;
  }
  std::vector<Eigen::Triplet<Complex>> triplets;
  triplets.reserve(n_edges + m);
  Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(n_free);
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n_free);
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    const int f = mesh.edge_faces(e, 0), g = mesh.edge_faces(e, 1);
    if (g < 0) continue;
    const double w = weight[e];
    const Complex r = std::polar(1.0, 4 * mesh.connection[e]);  // z_g ≈ r z_f
    const int a = free_index[f], b = free_index[g];
    if (a >= 0) diagonal[a] += w;
    if (b >= 0) diagonal[b] += w;
    if (a >= 0 && b >= 0) {  // the lower triangle of the Hermitian matrix: H_gf = −w r, H_fg = −w r̄
      if (b > a) triplets.emplace_back(b, a, -w * r);
      else triplets.emplace_back(a, b, -w * std::conj(r));
    } else if (a >= 0) {  // g fixed: its term moves to the right-hand side
      rhs[a] += w * std::conj(r) * hard.value[g];
    } else if (b >= 0) {
      rhs[b] += w * r * hard.value[f];
    }
  }
  bool anchored = hard.count() > 0;
  for (Eigen::Index f = 0; f < m; ++f) {
    const int a = free_index[f];
    if (a < 0 || mu[f] == 0) continue;
    anchored = true;
    diagonal[a] += mu[f];
    rhs[a] += mu[f] * target[f];
  }
  Eigen::VectorXd mass(n_free);
  const double mean_area = mesh.area.mean();  // once: inside the loop it made this O(m²) (1.3 s of pmp-bunny's 1.5)
  for (Eigen::Index f = 0; f < m; ++f) {
    if (free_index[f] >= 0) mass[free_index[f]] = mesh.area[f] / mean_area;
  }
  const double shift = anchored ? 0.0 : 1e-8 * (n_free > 0 ? diagonal.mean() : 0.0);
  for (int i = 0; i < n_free; ++i) triplets.emplace_back(i, i, Complex(diagonal[i] + shift * mass[i], 0.0));

  Eigen::VectorXcd z(n_free);
  if (n_free > 0) {
    Eigen::SparseMatrix<Complex> A(n_free, n_free);
    A.setFromTriplets(triplets.begin(), triplets.end());
    Solver solver;
    factorize(solver, A);
    progress.report(0.5, "cross field");
    auto m_norm = [&](const Eigen::VectorXcd& x) { return std::sqrt((mass.array() * x.array().abs2()).sum()); };
    if (anchored) {
      z = solver.solve(rhs);
    } else {
      // Inverse iteration for the smallest eigenvector of A z = λ M z (M-normalized). Plain
      // inverse iteration converges as λ1/λ2, close to 1 on a fine smooth mesh (it ran into its
      // 300-iteration cap: 37 s of a 40 s field on the 40k-face bumpy cube, machine loaded).
      // So: after a few steps the matrix is refactorized shifted by σ = 0.99, 0.9 or 0.5 × the
      // Rayleigh quotient (an upper bound of λ1; the first σ whose LLᵀ exists is below λ1), for
      // the rate (λ1 − σ)/(λ2 − σ); and the iteration also stops once the Rayleigh quotient is
      // stationary to 1e-10 (nearly equal λ1, λ2: any field of that energy is as smooth).
      for (int i = 0; i < n_free; ++i) z[i] = std::polar(1.0, 0.7 * i);
      z /= m_norm(z);
      auto rayleigh = [&](const Eigen::VectorXcd& x) {
        const Eigen::VectorXcd Ax = A.selfadjointView<Eigen::Lower>() * x;
        return x.dot(Ax).real() / (mass.array() * x.array().abs2()).sum();
      };
      double quotient = rayleigh(z);
      for (int iteration = 0; iteration < 300; ++iteration) {
        Eigen::VectorXcd next = solver.solve((mass.array() * z.array()).matrix());
        next /= m_norm(next);
        // |⟨next, z⟩_M|: the eigenspace is invariant under z → e^{iφ} z.
        const double overlap = std::abs((mass.array() * next.array().conjugate() * z.array()).sum());
        z = next;
        const double previous = quotient;
        quotient = rayleigh(z);
        if (1.0 - overlap < 1e-13 || std::abs(previous - quotient) <= 1e-10 * std::abs(quotient)) break;
        if (iteration == 4) {
          const int print_level = solver.cholmod().print;
          solver.cholmod().print = 0;  // a σ above λ1 is expected to fail: no "not positive definite" warning
          for (const double fraction : {0.99, 0.9, 0.5}) {
            std::vector<Eigen::Triplet<Complex>> shifted = triplets;
            for (int i = 0; i < n_free; ++i) shifted.emplace_back(i, i, Complex(-fraction * quotient * mass[i], 0.0));
            Eigen::SparseMatrix<Complex> B(n_free, n_free);
            B.setFromTriplets(shifted.begin(), shifted.end());
            solver.factorize(B);
            if (solver.info() == Eigen::Success) break;
          }
          solver.cholmod().print = print_level;
          if (solver.info() != Eigen::Success) factorize(solver, A);  // no shift below λ1 found: unshifted
        }
        progress.report(0.5 + 0.4 * iteration / 300.0, "cross field");
      }
    }
    if (!z.allFinite()) throw SolverError("cross_field: the field solve did not give finite values");
  }

  CrossField out;
  out.theta.resize(m);
  for (Eigen::Index f = 0; f < m; ++f) {
    const Complex value = hard.fixed[f] ? hard.value[f] : z[free_index[f]];
    double angle = std::arg(value) / 4;
    out.theta[f] = angle - kQuarter * std::floor(angle / kQuarter);
  }
  Alignment alignment{mu, std::vector<double>(m, 0.0)};
  for (Eigen::Index f = 0; f < m; ++f) {
    if (mu[f] > 0) alignment.angle[f] = std::arg(target[f]) / 4;
  }
  out.initial_energy = out.energy = angle_energy(mesh, weight, alignment, out.theta);
  if (options.rounding != FieldRounding::none) {
    const Eigen::VectorXd rounded =
        round_jumps(mesh, options.rounding, weight, alignment, hard.fixed, out.theta, progress, out.changed_jumps);
    // (the hard faces are forest roots: their angles come back as the power-4 field had them)
    for (Eigen::Index f = 0; f < m; ++f) out.theta[f] = rounded[f] - kQuarter * std::floor(rounded[f] / kQuarter);
    out.energy = angle_energy(mesh, weight, alignment, out.theta);
  }
  out.directions.resize(m, 3);
  for (Eigen::Index f = 0; f < m; ++f) {
    out.directions.row(f) = std::cos(out.theta[f]) * mesh.e1.row(f) + std::sin(out.theta[f]) * mesh.e2.row(f);
  }
  out.edges.edges = incidence.edges;
  out.edges.faces = mesh.edge_faces;
  out.edges.connection = mesh.connection;
  out.edges.period_jumps = detail::period_jumps(mesh, out.theta);
  out.constrained_faces = hard.count();
  progress.report(1.0, "cross field");
  return out;
}

}  // namespace meshsmith::quadrangulation
