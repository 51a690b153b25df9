// k-harmonic systems with fixed vertices, and handle-based deformation on them.
//
// The operator is assembled as libigl's igl::harmonic does (Q = −L, then Q ← Q M⁻¹ (−L) k−1
// times), so solutions agree with it to round-off. Only the free block Q_FF is factorized, as
// its lower triangle in CSC (CHOLMOD reads that), by CHOLMOD's supernodal LLᵀ (AMD, or METIS
// from 50k free vertices on, where its smaller factor pays for its ordering) through
// the core's MeshCholesky (its thread limits: ../core/mesh_cholesky.h), and solved by the core's
// SupernodalSolve (two threads, all right-hand-side columns in one pass over the factor:
// ../core/supernodal_solve.h); the coupling block Q_FC
// is kept to form right-hand sides −Q_FC X_C. A singular free block is ruled out before CHOLMOD
// sees it: every component of the Laplacian's graph (edges of non-zero weight; vertices on
// degenerate triangles only are isolated in it) must hold a constrained vertex.
//
// HarmonicDeformer solves for displacements (the response to the handle's move), not
// positions, which is what igl::harmonic(V, F, b, D_b, k) computes for D_b; its affine fast
// path precomputes the response to each of the handle's four control points (§3.1.1).
#include <meshsmith/deformation/harmonic_deformer.h>
#include <meshsmith/deformation/multiresolution.h>

#include "../core/mesh_cholesky.h"
#include "../core/supernodal_solve.h"
#include "vertex_sets.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/laplacian.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace meshsmith::deformation {

namespace {

/// Free blocks from this size on are ordered by METIS, smaller ones by AMD (mesh_cholesky.h).
constexpr Eigen::Index kMetisUnknowns = 50000;

void check_order(int order, const char* function) {
  if (order < 1 || order > 3) {
    throw InputError(std::string(function) + ": order = " + std::to_string(order) + ": expected 1, 2 or 3");
  }
}

/// Q = (−L M⁻¹)^(k−1) (−L) from the Laplacian and the vertex areas (0 areas: 0 inverse).
Eigen::SparseMatrix<double> order_k_operator(const Eigen::SparseMatrix<double>& L, const Eigen::VectorXd& areas,
                                             int order) {
  Eigen::SparseMatrix<double> Q = -L;
  if (order == 1) return Q;
  Eigen::VectorXd inverse_areas(areas.size());
  for (Eigen::Index i = 0; i < areas.size(); ++i) inverse_areas[i] = areas[i] > 0.0 ? 1.0 / areas[i] : 0.0;
  for (int p = 1; p < order; ++p) {
    const Eigen::SparseMatrix<double> scaled = Q * inverse_areas.asDiagonal();
    Q = scaled * (-L);
  }
  // Sorted row indices in every column (CHOLMOD's precondition) and no stored zeros.
  const Eigen::SparseMatrix<double> transposed = Q.transpose();
  Q = transposed.transpose();
  Q.makeCompressed();
  return Q;
}

}  // namespace

Eigen::SparseMatrix<double> k_harmonic_operator(const VertexRef& V, const FaceRef& F, int order) {
  check_order(order, "k_harmonic_operator");
  const Eigen::SparseMatrix<double> L = geometry::cotan_laplacian(V, F);
  const Eigen::VectorXd areas = order > 1 ? geometry::vertex_areas(V, F) : Eigen::VectorXd();
  return order_k_operator(L, areas, order);
}

struct KHarmonicSolver::Factorization {
  meshsmith::detail::MeshCholesky<double> cholesky;
  /// The substitutions on cholesky's factor: reentrant (no cholmod_common involved), so Python
  /// threads (the bindings release the GIL) may share a Deformer.
  meshsmith::detail::SupernodalSolve substitution;
  Eigen::SparseMatrix<double> coupling;  ///< Q_FC: #free×#constrained
};

KHarmonicSolver::~KHarmonicSolver() = default;
KHarmonicSolver::KHarmonicSolver(KHarmonicSolver&&) noexcept = default;
KHarmonicSolver& KHarmonicSolver::operator=(KHarmonicSolver&&) noexcept = default;

KHarmonicSolver::KHarmonicSolver(const VertexRef& V, const FaceRef& F, const std::vector<int>& constrained,
                                 int order)
    : order_(order), n_vertices_(V.rows()), constrained_(constrained) {
  static const char* function = "k-harmonic solve";
  validate_mesh(V, F);
  check_order(order, function);
  const Eigen::Index n = V.rows();
  detail::check_vertex_set(constrained, n, "the constrained vertex set", function);

  std::vector<char> used(static_cast<std::size_t>(n), 0), is_constrained(static_cast<std::size_t>(n), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) used[F(f, c)] = 1;
  for (int v : constrained) is_constrained[v] = 1;

  const Eigen::SparseMatrix<double> L = geometry::cotan_laplacian(V, F);
  const std::string system = "order-" + std::to_string(order) + " system";
  detail::check_every_component_constrained(L, used, is_constrained, system.c_str(), function);
  const Eigen::SparseMatrix<double> Q =
      order_k_operator(L, order > 1 ? geometry::vertex_areas(V, F) : Eigen::VectorXd(), order);

  // index[v]: position among the free vertices, or −1 − position among the constrained ones.
  std::vector<int> index(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < constrained.size(); ++k) index[constrained[k]] = -1 - static_cast<int>(k);
  for (Eigen::Index v = 0; v < n; ++v) {
    if (used[v] && !is_constrained[v]) {
      index[v] = static_cast<int>(free_.size());
      free_.push_back(static_cast<int>(v));
    }
  }
  factorization_ = std::make_unique<Factorization>();
  const Eigen::Index n_free = static_cast<Eigen::Index>(free_.size());
  if (n_free == 0) return;

  // The lower triangle of Q_FF column by column (free vertices increase with their position, so
  // the rows stay sorted) and Q_FC as triplets (Q is symmetric: entry (u, v) is entry (v, u)).
  Eigen::SparseMatrix<double> block(n_free, n_free);
  std::vector<Eigen::Triplet<double>> coupling;
  std::vector<int> outer(static_cast<std::size_t>(n_free) + 1, 0), rows;
  std::vector<double> values;
  rows.reserve(static_cast<std::size_t>(Q.nonZeros() / 2 + n_free));
  values.reserve(rows.capacity());
  for (Eigen::Index c = 0; c < n_free; ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, free_[c]); it; ++it) {
      const int j = index[it.row()];
      if (j >= c) {
        rows.push_back(j);
        values.push_back(it.value());
      } else if (j < 0 && is_constrained[it.row()]) {
        coupling.emplace_back(static_cast<int>(c), -1 - j, it.value());
      }
    }
    outer[c + 1] = static_cast<int>(rows.size());
  }
  block.resizeNonZeros(static_cast<Eigen::Index>(rows.size()));
  std::copy(outer.begin(), outer.end(), block.outerIndexPtr());
  std::copy(rows.begin(), rows.end(), block.innerIndexPtr());
  std::copy(values.begin(), values.end(), block.valuePtr());
  factorization_->coupling.resize(n_free, static_cast<Eigen::Index>(constrained.size()));
  factorization_->coupling.setFromTriplets(coupling.begin(), coupling.end());

  auto& cholesky = factorization_->cholesky;
  // Supernodal for every order, solved by SupernodalSolve on two threads; ordered by METIS from
  // kMetisUnknowns free vertices on (the smaller stored factor, which is what a solve streams;
  // below, METIS's ordering costs more than the solves save: mesh_cholesky.h), by AMD below.
  // Measured here on the 100k-vertex torus (80k free vertices, 3 right-hand sides, CPU time on a
  // loaded machine): order 2, 24 ms per thread (47 ms in all) against 38 ms for cholmod_solve on
  // the same factor; order 1 (ARAP's global step), 13 ms per thread against 23 ms, and 16 ms for
  // the simplicial AMD factor used before. Since SupernodalSolve's AVX2 loops and its skip of
  // zero supernodes (a handle's right-hand side): order 2, 9–10 ms per thread at load 14–18
  // (supernodal_solve.h). Ordering the free rows coupled to the handle last (so that the forward
  // pass touches almost nothing) stored 14.8M factor entries instead of 12.8M: no net gain.
  meshsmith::detail::configure_cholesky(cholesky, n_free >= kMetisUnknowns
                                                      ? meshsmith::detail::CholeskyKind::vertex_laplacian_solves
                                                      : meshsmith::detail::CholeskyKind::vertex_laplacian);
  cholesky.compute(block);
  if (cholesky.info() != Eigen::Success) {
    throw SolverError(std::string(function) + ": the " + system + " restricted to the " + std::to_string(n_free) +
                      " free vertices is not positive definite (negative cotangent weights of obtuse triangles "
                      "can make orders 1 and 3 indefinite; order 2 is always semi-definite)");
  }
  factorization_->substitution = meshsmith::detail::SupernodalSolve(*cholesky.factor());
}

namespace {

void check_finite_values(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::vector<int>& vertices,
                         const char* what, const char* function) {
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) {
      if (!std::isfinite(values(r, c))) {
        throw InputError(std::string(function) + ": the " + what + " of vertex " + std::to_string(vertices[r]) +
                         " is " + number_text(values(r, c)) + " (column " + std::to_string(c) +
                         "); values must be finite");
      }
    }
  }
}

}  // namespace

Eigen::MatrixXd KHarmonicSolver::solve_free(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values) const {
  return solve_free_impl(constrained_values, nullptr);
}

Eigen::MatrixXd KHarmonicSolver::solve_free(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values,
                                            const Eigen::Ref<const Eigen::MatrixXd>& free_rhs) const {
  return solve_free_impl(constrained_values, &free_rhs);
}

Eigen::MatrixXd KHarmonicSolver::solve_free_impl(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values,
                                                 const Eigen::Ref<const Eigen::MatrixXd>* free_rhs) const {
  static const char* function = "k-harmonic solve";
  if (constrained_values.rows() != static_cast<Eigen::Index>(constrained_.size())) {
    throw InputError(std::string(function) + ": " + std::to_string(constrained_values.rows()) +
                     " constrained values for " + std::to_string(constrained_.size()) + " constrained vertices");
  }
  check_finite_values(constrained_values, constrained_, "value", function);
  const Eigen::Index n_free = static_cast<Eigen::Index>(free_.size()), columns = constrained_values.cols();
  if (free_rhs) {
    if (free_rhs->rows() != n_free || free_rhs->cols() != columns) {
      throw InputError(std::string(function) + ": the right-hand side is " + std::to_string(free_rhs->rows()) + "x" +
                       std::to_string(free_rhs->cols()) + ", expected " + std::to_string(n_free) + "x" +
                       std::to_string(columns));
    }
    check_finite_values(*free_rhs, free_, "right-hand side", function);
  }
  if (n_free == 0 || columns == 0) return Eigen::MatrixXd::Zero(n_free, columns);
  Eigen::MatrixXd rhs = -(factorization_->coupling * constrained_values);
  if (free_rhs) rhs += *free_rhs;
  const Eigen::MatrixXd solution = factorization_->substitution.solve(rhs);
  if (!solution.allFinite()) {
    throw SolverError(std::string(function) + ": the back-substitution produced non-finite values");
  }
  return solution;
}

Eigen::MatrixXd KHarmonicSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values) const {
  const Eigen::MatrixXd free_values = solve_free(constrained_values);
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n_vertices_, constrained_values.cols());
  for (std::size_t k = 0; k < constrained_.size(); ++k) X.row(constrained_[k]) = constrained_values.row(k);
  for (std::size_t r = 0; r < free_.size(); ++r) X.row(free_[r]) = free_values.row(r);
  return X;
}

Eigen::MatrixXd harmonic(const VertexRef& V, const FaceRef& F, const std::vector<int>& b, const Eigen::MatrixXd& bc,
                         int order) {
  if (bc.rows() != static_cast<Eigen::Index>(b.size())) {
    throw InputError("harmonic: bc has " + std::to_string(bc.rows()) + " rows for " + std::to_string(b.size()) +
                     " vertices in b");
  }
  return KHarmonicSolver(V, F, b, order).solve(bc);
}

namespace {

std::vector<int> concatenated(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> both(a);
  both.insert(both.end(), b.begin(), b.end());
  return both;
}

const std::vector<int>& checked_handle(const VertexRef& V, const FaceRef& F, const std::vector<int>& handle,
                                       const std::vector<int>& fixed) {
  static const char* function = "Deformer";
  validate_mesh(V, F);
  detail::check_vertex_set(handle, V.rows(), "handle", function);
  detail::check_vertex_set(fixed, V.rows(), "fixed", function, /*allow_empty=*/true);
  detail::check_disjoint(handle, fixed, V.rows(), "handle", "fixed", function);
  return handle;
}

}  // namespace

HarmonicDeformer::HarmonicDeformer(const VertexRef& V, const FaceRef& F, const std::vector<int>& handle,
                                   const std::vector<int>& fixed, int order, bool details)
    : V_(V),
      F_(F),
      handle_(checked_handle(V, F, handle, fixed)),
      fixed_(fixed),
      solver_(V, F, concatenated(handle, fixed), order),
      details_(details) {
  const Eigen::Index n_handle = static_cast<Eigen::Index>(handle_.size());
  const Eigen::Index n_constrained = n_handle + static_cast<Eigen::Index>(fixed_.size());

  // The four control points a, a + s e_x, a + s e_y, a + s e_z and the handle's affine
  // coordinates in them: h = a + s w = (1 − Σw) a + w_x b + w_y c + w_z d.
  Eigen::RowVector3d lo = V_.row(handle_[0]), hi = lo, centroid = Eigen::RowVector3d::Zero();
  for (int h : handle_) {
    lo = lo.cwiseMin(V_.row(h));
    hi = hi.cwiseMax(V_.row(h));
    centroid += V_.row(h);
  }
  centroid /= static_cast<double>(n_handle);
  double scale = (hi - lo).maxCoeff();
  if (!(scale > 0.0)) scale = (V_.colwise().maxCoeff() - V_.colwise().minCoeff()).maxCoeff();
  if (!(scale > 0.0)) scale = 1.0;
  control_points_.row(0) = centroid;
  for (int axis = 0; axis < 3; ++axis) {
    control_points_.row(1 + axis) = centroid;
    control_points_(1 + axis, axis) += scale;
  }
  handle_coordinates_.resize(n_handle, 4);
  for (Eigen::Index k = 0; k < n_handle; ++k) {
    const Eigen::RowVector3d w = (V_.row(handle_[k]) - centroid) / scale;
    handle_coordinates_(k, 0) = 1.0 - w.sum();
    handle_coordinates_.block<1, 3>(k, 1) = w;
  }
  Eigen::MatrixXd unit_moves = Eigen::MatrixXd::Zero(n_constrained, 4);
  unit_moves.topRows(n_handle) = handle_coordinates_;
  control_response_ = solver_.solve_free(unit_moves);

  if (!details_) return;
  // The smooth base: the same system solved for positions, with the handle and fixed held.
  const std::vector<int>& constrained = solver_.constrained();
  Eigen::MatrixXd held(n_constrained, 3);
  for (Eigen::Index k = 0; k < n_constrained; ++k) held.row(k) = V_.row(constrained[k]);
  const Eigen::MatrixXd faired = solver_.solve_free(held);
  base_ = V_;
  const std::vector<int>& free = solver_.free_vertices();
  for (std::size_t r = 0; r < free.size(); ++r) base_.row(free[r]) = faired.row(r);

  std::vector<char> with_detail(static_cast<std::size_t>(V_.rows()), 0);
  for (int v : free) with_detail[v] = 1;
  details_frames_ = encode_details(V_, base_, F_, with_detail);
}

VertexMatrix HarmonicDeformer::finish(const Eigen::MatrixXd& free_displacement, const VertexRef* handle_positions,
                                      const Eigen::Matrix4d* T) const {
  VertexMatrix out = details_ ? base_ : V_;
  const std::vector<int>& free = solver_.free_vertices();
  for (std::size_t r = 0; r < free.size(); ++r) out.row(free[r]) += free_displacement.row(r);
  for (std::size_t k = 0; k < handle_.size(); ++k) {
    const int h = handle_[k];
    if (handle_positions) {
      out.row(h) = handle_positions->row(static_cast<Eigen::Index>(k));
    } else {
      out.row(h) = (T->topLeftCorner<3, 3>() * V_.row(h).transpose() + T->topRightCorner<3, 1>()).transpose();
    }
  }
  if (!details_) return out;
  return decode_details(out, F_, details_frames_);  // the details, in the frames of the moved base
}

VertexMatrix HarmonicDeformer::deform(const VertexRef& handle_positions) const {
  if (handle_positions.rows() != static_cast<Eigen::Index>(handle_.size())) {
    throw InputError("Deformer.deform: handle_positions has " + std::to_string(handle_positions.rows()) +
                     " rows for " + std::to_string(handle_.size()) + " handle vertices");
  }
  validate_vertices(handle_positions, "handle_positions");
  Eigen::MatrixXd moves = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(solver_.constrained().size()), 3);
  for (std::size_t k = 0; k < handle_.size(); ++k) {
    moves.row(static_cast<Eigen::Index>(k)) = handle_positions.row(static_cast<Eigen::Index>(k)) - V_.row(handle_[k]);
  }
  return finish(solver_.solve_free(moves), &handle_positions, nullptr);
}

VertexMatrix HarmonicDeformer::transform(const Eigen::Matrix4d& T) const {
  detail::check_affine(T, "Deformer.transform");
  Eigen::Matrix<double, 4, 3> moves;
  for (int j = 0; j < 4; ++j) {
    const Eigen::Vector3d p = control_points_.row(j).transpose();
    moves.row(j) = (T.topLeftCorner<3, 3>() * p + T.topRightCorner<3, 1>() - p).transpose();
  }
  return finish(control_response_ * moves, nullptr, &T);
}

}  // namespace meshsmith::deformation
