#pragma once
/// \file laplacian_smoothing.h
/// Laplacian and Taubin smoothing of triangle meshes (§3.0.1–3.0.2): the umbrella operator
/// U = D⁻¹L (L a Laplacian of geometry/laplacian.h with libigl's signs, D = diag(−L_ii) the sum
/// of each vertex's weights), so (U p)_i = Σ_j w_ij (p_j − p_i) / Σ_j w_ij moves p_i towards
/// the weighted centre of its one-ring.
///
/// The weights are computed once, on the input mesh, so k iterations apply the linear filter
/// (I + λU)^k of §3.0.1 to the positions, and an implicit solve needs one factorization. The
/// direction projection (normal, tangential) uses the vertex normals of the current positions at
/// every step. Error bounds (error_control.h) and fixed vertices hold at every step.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/smoothing/error_control.h>

#include <vector>

namespace meshsmith::smoothing {

/// The edge weights w_ij of the umbrella operator (§3.0.2).
enum class SmoothingWeights {
  uniform,         ///< w_ij = 1 (geometry::uniform_laplacian): locality, symmetric, positive
  cotan,           ///< cot α_ij + cot β_ij (geometry::cotan_laplacian): linear precision, may be negative
  cotan_delaunay,  ///< cot weights of the intrinsic Delaunay triangulation
                   ///< (geometry::intrinsic_delaunay_cotan_laplacian): linear precision, ≥ 0 everywhere
  mean_value,      ///< Floater's mean-value weights (geometry::mean_value_laplacian): positive,
                   ///< linear precision, not symmetric
};

/// Which part of each step's displacement Δp_i is applied (§3.0.1).
enum class SmoothingDirection {
  full,        ///< Δp_i
  normal,      ///< (n_iᵀ Δp_i) n_i: removes noise, keeps the vertex distribution
  tangential,  ///< Δp_i − (n_iᵀ Δp_i) n_i: redistributes vertices, keeps the shape
};

/// Options shared by laplacian_smoothing and taubin_smoothing.
struct SmoothingOptions {
  SmoothingWeights weights = SmoothingWeights::uniform;
  SmoothingDirection direction = SmoothingDirection::full;
  int iterations = 10;           ///< ≥ 0 (Taubin: λ|μ pairs)
  std::vector<int> fixed;        ///< vertices held at their input position (any order, repeats allowed)
  ErrorControl error_control;    ///< bound on each vertex's distance from its input position
};

/// Options of laplacian_smoothing.
struct LaplacianSmoothingOptions : SmoothingOptions {
  double lambda = 0.5;     ///< step size λ > 0; explicit steps are stable for λ ≤ 1 with weights ≥ 0
  bool implicit = false;   ///< backward Euler: solve (I − λU) p' = p (stable for every λ > 0)
};

/// Laplacian smoothing (§3.0.2): `iterations` steps p ← p + λ U p (explicit) or
/// p ← (I − λU)⁻¹ p (implicit, Desbrun et al. 1999: (D − λL) p' = D p, factorized once by
/// CHOLMOD, or by sparse LU for the non-symmetric mean-value weights), each followed by the
/// direction projection and the error bound.
/// V: #V×3 positions, F: #F×3 triangles. Returns the smoothed #V×3 positions. Vertices whose
/// weights sum to zero (used by no face, or surrounded by degenerate faces) do not move.
/// \pre λ > 0 finite, iterations ≥ 0, fixed indices in [0, #V); for cotan_delaunay an
///      edge-manifold, consistently oriented mesh.
/// \throw InputError for bad (V, F) or options; SolverError if the factorization fails;
///        Cancelled through `progress`.
/// Complexity: O(iterations·#F) explicit; one sparse factorization + iterations solves implicit.
VertexMatrix laplacian_smoothing(const VertexRef& V, const FaceRef& F, const LaplacianSmoothingOptions& options,
                                 const Progress& progress = {});

/// Options of taubin_smoothing.
struct TaubinOptions : SmoothingOptions {
  double lambda = 0.5;   ///< shrinking step, λ > 0
  double mu = -0.53;     ///< inflating step, μ < 0 (μ < −λ gives a pass band: see taubin_smoothing)
};

/// Taubin's λ|μ smoothing (§3.0.1 "Design a smoothing operator"; Taubin 1995): `iterations`
/// times p ← (I + μU)(I + λU) p, with the direction projection and the error bound after each
/// of the two steps. For an eigenvector of −U with eigenvalue k ∈ [0, 2] (the frequency; k ≤ 2
/// for weights ≥ 0), N iterations scale its coefficient by the transfer function
/// f(k) = ((1 − λk)(1 − μk))^N: f(0) = 1, f ≈ 1 below the pass-band frequency
/// k_PB = 1/λ + 1/μ (0.113 for λ = 0.5, μ = −0.53), and f → 0 above it, so low frequencies (the
/// shape, its volume) are kept while noise is removed. μ = −λ gives §3.0.1's (I − λU)(I + λU)
/// = I − λ²U², f(k) = (1 − λ²k²)^N.
/// V: #V×3, F: #F×3. Returns #V×3.
/// \pre λ > 0, μ < 0, both finite; otherwise as laplacian_smoothing.
/// \throw as laplacian_smoothing.
VertexMatrix taubin_smoothing(const VertexRef& V, const FaceRef& F, const TaubinOptions& options,
                              const Progress& progress = {});

}  // namespace meshsmith::smoothing
