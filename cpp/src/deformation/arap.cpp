// ARAP (Sorkine & Alexa 2007) with the spokes-and-rims energy, as local/global alternation.
//
// Precomputed: c_jk^t for every face (½ cot of each corner, the weight of the opposite edge; a
// degenerate face gets 0 as in geometry::cotan_laplacian), the faces around each vertex, and per
// corner j of face t the constant g_tj = Σ_{k ∈ t, k ≠ j} c_jk (v_j − v_k). The global step's
// normal equations are (−L U)_j = ⅓ Σ_{t ∋ j} (R_a + R_b + R_c) g_tj (each triangle edge is
// seen by the three rotations of its triangle; with every R = I the right-hand side is −L V),
// solved by the order-1 KHarmonicSolver (−L_FF factorized once, handles as its constrained
// vertices). The local step fits each R_i to M_i = Σ_{t ∋ i} Σ_{(j,k) ∈ t} c_jk (u_j − u_k)(v_j − v_k)ᵀ
// (per-face sums first, then gathered per vertex: both passes parallel and deterministic).
//
// Rotation fit: rotation_fit.h.
#include <meshsmith/deformation/arap.h>

#include "rotation_fit.h"
#include "vertex_sets.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>

namespace meshsmith::deformation {

namespace {

using FaceBlocks = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;
using RowMatrix3d = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;


const std::vector<int>& checked_handles(const VertexRef& V, const FaceRef& F, const std::vector<int>& handles) {
  validate_mesh(V, F);
  detail::check_vertex_set(handles, V.rows(), "handles", "arap");
  return handles;
}

}  // namespace

ArapDeformer::ArapDeformer(const VertexRef& V, const FaceRef& F, const std::vector<int>& handles)
    : V_(V), F_(F), solver_(V, F, checked_handles(V, F, handles), 1) {
  const Eigen::Index n = V_.rows(), m = F_.rows();
  weights_.resize(m, 3);
  weighted_edges_.resize(m, 9);
  corner_gradients_.resize(m, 9);
  tbb::parallel_for(Eigen::Index(0), m, [&](Eigen::Index f) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = V_.row(F_(f, k)).transpose();
    double longest = 0.0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, (p[(k + 1) % 3] - p[k]).squaredNorm());
    const double twice_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    const bool degenerate = !(twice_area > 8.0 * std::numeric_limits<double>::epsilon() * longest);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      weights_(f, k) = degenerate ? 0.0 : 0.5 * a.dot(b) / twice_area;
    }
    for (int k = 0; k < 3; ++k) {
      weighted_edges_.block<1, 3>(f, 3 * k) = (weights_(f, k) * (p[(k + 1) % 3] - p[(k + 2) % 3])).transpose();
    }
    for (int k = 0; k < 3; ++k) {
      const int q = (k + 1) % 3, r = (k + 2) % 3;  // edge (k, q) is opposite corner r, (k, r) opposite q
      const Eigen::Vector3d g = weights_(f, r) * (p[k] - p[q]) + weights_(f, q) * (p[k] - p[r]);
      corner_gradients_.block<1, 3>(f, 3 * k) = g.transpose();
    }
  });
  vertex_face_offsets_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) ++vertex_face_offsets_[F_(f, k) + 1];
  for (Eigen::Index v = 0; v < n; ++v) vertex_face_offsets_[v + 1] += vertex_face_offsets_[v];
  vertex_faces_.resize(static_cast<std::size_t>(3 * m));
  std::vector<int> fill(vertex_face_offsets_.begin(), vertex_face_offsets_.end() - 1);
  // Corner ids 3f + k, so a vertex's repeated use of one face (a degenerate face) stays distinct.
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) vertex_faces_[fill[F_(f, k)]++] = static_cast<int>(3 * f + k);
}

struct ArapDeformer::Workspace {
  FaceBlocks face_blocks;                 ///< #F×9: covariances, then the corners' right-hand sides
  std::vector<Eigen::Matrix3d> rotations;  ///< #V
};

void ArapDeformer::fit_rotations(const VertexMatrix& U, Workspace& work) const {
  const Eigen::Index n = V_.rows(), m = F_.rows();
  work.face_blocks.resize(m, 9);
  work.rotations.resize(static_cast<std::size_t>(n));
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 512), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index f = range.begin(); f < range.end(); ++f) {
      const Eigen::RowVector3d u0 = U.row(F_(f, 0)), u1 = U.row(F_(f, 1)), u2 = U.row(F_(f, 2));
      RowMatrix3d C = (u1 - u2).transpose() * weighted_edges_.block<1, 3>(f, 0);
      C.noalias() += (u2 - u0).transpose() * weighted_edges_.block<1, 3>(f, 3);
      C.noalias() += (u0 - u1).transpose() * weighted_edges_.block<1, 3>(f, 6);
      Eigen::Map<RowMatrix3d>(&work.face_blocks(f, 0)) = C;
    }
  });
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 256), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index v = range.begin(); v < range.end(); ++v) {
      RowMatrix3d M = RowMatrix3d::Zero();
      for (int at = vertex_face_offsets_[v]; at < vertex_face_offsets_[v + 1]; ++at) {
        M += Eigen::Map<const RowMatrix3d>(&work.face_blocks(vertex_faces_[at] / 3, 0));
      }
      work.rotations[v] = detail::best_rotation(M);
    }
  });
}

VertexMatrix ArapDeformer::solve(const VertexRef& positions, int iterations, const VertexRef* initial,
                                 const Progress& progress) const {
  static const char* function = "arap";
  const std::vector<int>& handles = solver_.constrained();
  const std::vector<int>& free = solver_.free_vertices();
  const Eigen::Index n = V_.rows(), n_free = static_cast<Eigen::Index>(free.size());
  detail::check_positions(positions, static_cast<Eigen::Index>(handles.size()), "positions", function);
  if (iterations < 0) {
    throw InputError(std::string(function) + ": iterations = " + std::to_string(iterations) + ": expected >= 0");
  }
  const Eigen::MatrixXd held = positions;
  VertexMatrix U;
  if (initial) {
    detail::check_positions(*initial, n, "initial", function);
    U = *initial;
  } else {  // the handles' displacement spread harmonically (the order-1 system is the same −L_FF)
    Eigen::MatrixXd moves(held.rows(), 3);
    for (std::size_t k = 0; k < handles.size(); ++k) {
      moves.row(static_cast<Eigen::Index>(k)) = held.row(static_cast<Eigen::Index>(k)) - V_.row(handles[k]);
    }
    const Eigen::MatrixXd displacement = solver_.solve_free(moves);
    U = V_;
    for (Eigen::Index r = 0; r < n_free; ++r) U.row(free[r]) += displacement.row(r);
  }
  for (std::size_t k = 0; k < handles.size(); ++k) U.row(handles[k]) = held.row(static_cast<Eigen::Index>(k));

  Workspace work;
  Eigen::MatrixXd rhs(n_free, 3);
  const Eigen::Index m = F_.rows();
  for (int iteration = 0; iteration < iterations; ++iteration) {
    progress.report(static_cast<double>(iteration) / iterations, "arap iterations");
    fit_rotations(U, work);
    // Per face: ⅓ (R_a + R_b + R_c) g_tk for its three corners k; then summed per free vertex.
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 512), [&](const tbb::blocked_range<Eigen::Index>& range) {
      for (Eigen::Index f = range.begin(); f < range.end(); ++f) {
        const Eigen::Matrix3d S =
            (work.rotations[F_(f, 0)] + work.rotations[F_(f, 1)] + work.rotations[F_(f, 2)]) / 3.0;
        for (int k = 0; k < 3; ++k) {
          work.face_blocks.block<1, 3>(f, 3 * k) = (S * corner_gradients_.block<1, 3>(f, 3 * k).transpose()).transpose();
        }
      }
    });
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n_free, 256), [&](const tbb::blocked_range<Eigen::Index>& range) {
      for (Eigen::Index r = range.begin(); r < range.end(); ++r) {
        const int v = free[r];
        Eigen::RowVector3d b = Eigen::RowVector3d::Zero();
        for (int at = vertex_face_offsets_[v]; at < vertex_face_offsets_[v + 1]; ++at) {
          b += work.face_blocks.block<1, 3>(vertex_faces_[at] / 3, 3 * (vertex_faces_[at] % 3));
        }
        rhs.row(r) = b;
      }
    });
    const Eigen::MatrixXd solution = solver_.solve_free(held, rhs);
    for (Eigen::Index r = 0; r < n_free; ++r) U.row(free[r]) = solution.row(r);
  }
  progress.report(1.0, "arap iterations");
  return U;
}

double ArapDeformer::energy(const VertexRef& U_in) const {
  detail::check_positions(U_in, V_.rows(), "U", "arap_energy");
  const VertexMatrix U = U_in;
  Workspace work;
  fit_rotations(U, work);
  const std::vector<Eigen::Matrix3d>& rotations = work.rotations;
  const Eigen::Index n = V_.rows();
  Eigen::VectorXd per_vertex(n);
  tbb::parallel_for(Eigen::Index(0), n, [&](Eigen::Index v) {
    double sum = 0.0;
    for (int at = vertex_face_offsets_[v]; at < vertex_face_offsets_[v + 1]; ++at) {
      const int f = vertex_faces_[at] / 3;
      for (int k = 0; k < 3; ++k) {
        const int a = F_(f, (k + 1) % 3), b = F_(f, (k + 2) % 3);
        const Eigen::Vector3d residual =
            (U.row(a) - U.row(b)).transpose() - rotations[v] * (V_.row(a) - V_.row(b)).transpose();
        sum += weights_(f, k) * residual.squaredNorm();
      }
    }
    per_vertex[v] = sum;
  });
  return per_vertex.sum();
}

double arap_energy(const VertexRef& V, const FaceRef& F, const VertexRef& U) {
  validate_mesh(V, F);
  detail::check_positions(U, V.rows(), "U", "arap_energy");
  // The energy needs only the weights and adjacency; every vertex is a "handle" so that no
  // system is factorized (there are no free vertices).
  std::vector<int> all(static_cast<std::size_t>(V.rows()));
  for (Eigen::Index v = 0; v < V.rows(); ++v) all[v] = static_cast<int>(v);
  return ArapDeformer(V, F, all).energy(U);
}

VertexMatrix arap(const VertexRef& V, const FaceRef& F, const std::vector<int>& handles, const VertexRef& positions,
                  int iterations, const VertexRef* initial, const Progress& progress) {
  return ArapDeformer(V, F, handles).solve(positions, iterations, initial, progress);
}

}  // namespace meshsmith::deformation
