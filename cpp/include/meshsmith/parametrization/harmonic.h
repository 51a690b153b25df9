#pragma once
/// \file harmonic.h
/// Harmonic parametrization with a fixed convex boundary (§5.1.1): every interior vertex is in
/// spring equilibrium with its neighbours, Σ_j w_ij (u_j − u_i) = 0, i.e. ΔF = 0 with the
/// boundary fixed. With uniform weights this is Tutte's embedding (Tutte 1963), with mean-value
/// weights Floater's (2003), with cotangent weights the discrete harmonic map (Pinkall &
/// Polthier 1993, Eck et al. 1995). Positive weights and a convex boundary guarantee a
/// bijective map (Tutte, Floater): uniform and mean-value weights are always positive,
/// cotangent weights are not (obtuse triangles), so the cotangent map may fold.
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>
#include <meshsmith/parametrization/boundary_map.h>

#include <Eigen/SparseCore>

namespace meshsmith::parametrization {

/// The spring weights w_ij of §5.1.1 (the Laplacians of geometry/laplacian.h).
enum class HarmonicWeights {
  uniform,     ///< w_ij = 1: Tutte's embedding (symmetric, solved by CHOLMOD)
  cotan,       ///< ½ (cot α_ij + cot β_ij): libigl's harmonic(…, k = 1) (symmetric, CHOLMOD)
  mean_value,  ///< (tan(α/2) + tan(β/2)) / |p_j − p_i| (not symmetric: sparse LU)
};

struct HarmonicOptions {
  HarmonicWeights weights = HarmonicWeights::uniform;
  BoundaryShape shape = BoundaryShape::circle;  ///< used when no boundary map is given
};

/// The #V×#V Laplacian (libigl's sign: L_ij = w_ij ≥ 0 off the diagonal, rows sum to zero) with
/// the chosen weights. V: #V×3, F: #F×3.
/// \throw InputError as geometry::cotan_laplacian.
Eigen::SparseMatrix<double> weight_laplacian(const VertexRef& V, const FaceRef& F, HarmonicWeights weights);

/// Solves Σ_j L_ij (x_j − x_i) = 0 at every vertex not in `boundary`, the boundary fixed at its
/// positions: the harmonic map of the Laplacian L (row i holds vertex i's weights; L need not be
/// symmetric). `symmetric` selects CHOLMOD (L symmetric, −L positive semi-definite) or sparse LU.
/// L: #V×#V. Returns #V×2 parameter positions.
/// \throw InputError for a bad boundary; SolverError if the system is singular (a part of the
///        mesh with no fixed vertex).
geometry::ParameterMatrix harmonic_from_laplacian(const Eigen::SparseMatrix<double>& L, const BoundaryMap& boundary,
                                                  bool symmetric);

/// Harmonic map of (V, F) with `boundary` fixed. V: #V×3, F: #F×3. Returns #V×2.
/// \pre (V, F) is a clean, connected, oriented 2-manifold (any topology: every vertex not in the
///      boundary is free).
/// \throw InputError naming the problem; SolverError as harmonic_from_laplacian.
geometry::ParameterMatrix harmonic(const VertexRef& V, const FaceRef& F, const BoundaryMap& boundary,
                                   HarmonicWeights weights = HarmonicWeights::uniform);

/// Harmonic map of a topological disk with its boundary loop mapped by map_boundary(V, F, shape).
/// \pre (V, F) is a topological disk (cut other meshes with cut_to_disk first).
/// \throw InputError naming the problem otherwise.
geometry::ParameterMatrix harmonic(const VertexRef& V, const FaceRef& F, const HarmonicOptions& options = {});

}  // namespace meshsmith::parametrization
