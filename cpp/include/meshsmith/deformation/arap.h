#pragma once
/// \file arap.h
/// As-rigid-as-possible surface deformation (§3.1.2 "Poisson Editing", ‖ΔQ − RΔP‖² with local
/// rotations; Sorkine & Alexa 2007), with libigl's default "spokes and rims" energy (Chao et
/// al. 2010): every vertex i has a rotation R_i that acts on the edges of all triangles around
/// it,
///     E(U) = Σ_i min_{R_i ∈ SO(3)} Σ_{t ∋ i} Σ_{(j,k) ∈ t} c_jk^t ‖(u_j − u_k) − R_i (v_j − v_k)‖²,
/// c_jk^t = ½ cot of the angle of t opposite edge jk (libigl's cotmatrix_entries). Minimized by
/// alternating the local step (each R_i by a 3×3 polar decomposition, in parallel) and the global
/// step (a Poisson system in the cotan Laplacian −L with the handles held, factorized once).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/deformation/harmonic_deformer.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::deformation {

/// The spokes-and-rims ARAP energy E(U) above of the deformed positions U (#V×3) of the rest
/// mesh (V, F) (the optimal rotations are fitted). E(V) = 0; E is invariant to rigid motions of U.
/// \throw InputError for invalid V, F or a U of another shape or with NaN/Inf.
double arap_energy(const VertexRef& V, const FaceRef& F, const VertexRef& U);

/// The precomputed ARAP solver for interactive use: the cotan weights, the constant parts of the
/// right-hand side and the factorization of −L_FF (free = not a handle) are computed once;
/// solve() costs per iteration one parallel pass of rotation fits and one back-substitution.
class ArapDeformer {
 public:
  /// V: #V×3 rest positions, F: #F×3, handles: #H distinct vertex indices.
  /// \pre every connected component holds a handle (otherwise it could drift freely).
  /// \throw InputError for invalid V, F, empty, out-of-range or repeated handles, or a component
  ///        without a handle; SolverError if −L_FF is not positive definite (negative cotangent
  ///        weights on badly shaped meshes).
  ArapDeformer(const VertexRef& V, const FaceRef& F, const std::vector<int>& handles);

  /// `iterations` local/global steps from `initial` (#V×3; nullptr: the rest mesh with the
  /// handles' displacement spread harmonically, which costs one back-substitution), with the
  /// handles at `positions` (#H×3, in the order of `handles`). iterations = 0 returns the initial
  /// guess with the handles placed. Vertices used by no face keep their initial positions.
  /// \throw InputError for wrong shapes, NaN/Inf or iterations < 0; Cancelled from `progress`.
  VertexMatrix solve(const VertexRef& positions, int iterations, const VertexRef* initial = nullptr,
                     const Progress& progress = {}) const;

  /// The energy E(U) of deformed positions U (as arap_energy, with the precomputed weights).
  double energy(const VertexRef& U) const;

  const std::vector<int>& handles() const { return solver_.constrained(); }

 private:
  /// Reused per solve() call: per-face 3×3 blocks and per-vertex rotations.
  struct Workspace;
  /// The optimal rotation R_i of every vertex for the deformed positions U (into work.rotations).
  void fit_rotations(const VertexMatrix& U, Workspace& work) const;

  VertexMatrix V_;
  FaceMatrix F_;
  KHarmonicSolver solver_;                      ///< order 1: −L_FF and −L_FC
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> weights_;  ///< #F×3: c of the edge opposite each corner
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> weighted_edges_;  ///< #F×9: c_k (v_{k+1} − v_{k+2}) per corner k
  std::vector<int> vertex_face_offsets_, vertex_faces_;                 ///< faces around each vertex (CSR)
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> corner_gradients_;  ///< #F×9: per corner j, Σ_k c_jk (v_j − v_k)
};

/// One call: ArapDeformer(V, F, handles).solve(positions, iterations, initial, progress).
VertexMatrix arap(const VertexRef& V, const FaceRef& F, const std::vector<int>& handles, const VertexRef& positions,
                  int iterations, const VertexRef* initial = nullptr, const Progress& progress = {});

}  // namespace meshsmith::deformation
