#pragma once
// Internal to the quadrangulation chapter (not installed): the pieces of a seamless map's solve
// that MIQ (miq.cpp) and the spectral chapter's coupled map (spectral.cpp) share.
#include <meshsmith/core/types.h>
#include <meshsmith/quadrangulation/miq.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <functional>
#include <vector>

namespace meshsmith::quadrangulation::detail {

/// The weighted energy Σ_f w_f A_f (‖∇u − u*‖² + ‖∇v − v*‖²) over per-corner-copy unknowns (Fc
/// indexes the copies, P their positions), as the interleaved (u_i at 2i, v_i at 2i + 1) matrix K
/// and right-hand side b (E = xᵀKx − 2bᵀx + c); u* = v* = 0 gives the Dirichlet energy (cotangent
/// weights). target_u, target_v: #F×3 per-face target gradients; weight: #F.
void assemble_energy(const VertexMatrix& P, const FaceMatrix& Fc, const VertexMatrix& target_u,
                     const VertexMatrix& target_v, const Eigen::VectorXd& weight, Eigen::Index n_variables,
                     Eigen::SparseMatrix<double>& K, Eigen::VectorXd& b);

/// Faces of a #F×6 corner map with det(B − A, C − A) ≤ 0 (flagged in `flipped` when given).
Eigen::Index count_flipped(const CornerUV& uv, std::vector<char>* flipped = nullptr);

/// Flip repair by stiffening (MIQ step 3; the spectral chapter's coupled map): each round
/// multiplies the weight of the flipped faces of the best map so far by `stiffening` and that of
/// the faces around their corners by its square root, and `resolve(weight)` re-solves the map; a
/// round with more flips is undone and the factor drops to its square root; at most `iterations`
/// rounds, ending after three without fewer flips. uv, flipped_count (and the flags `flipped` of
/// uv's flipped faces) start as the unstiffened map and end as the best one; `on_round(k)` is
/// called before round k. Returns the rounds run.
int repair_by_stiffening(const FaceRef& F, Eigen::Index n_vertices, int iterations, double stiffening,
                         Eigen::VectorXd weight, CornerUV& uv, Eigen::Index& flipped_count, std::vector<char> flipped,
                         const std::function<CornerUV(const Eigen::VectorXd&)>& resolve,
                         const std::function<void(int)>& on_round);

}  // namespace meshsmith::quadrangulation::detail
