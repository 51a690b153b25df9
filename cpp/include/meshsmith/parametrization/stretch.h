#pragma once
/// \file stretch.h
/// Stretch-minimizing parametrization (§5.1.1 "Stretch Minimizing Parametrization"; Yoshizawa,
/// Belyaev & Seidel, "A fast and simple stretch-minimizing mesh parameterization", SMI 2004):
/// start from a harmonic map, measure the stretch s_i at every vertex (the area-weighted average
/// of Sander et al.'s triangle stretch s_Δ = sqrt((σ1² + σ2²)/2), geometry::triangle_distortion),
/// divide every spring weight by the mean stretch of its ends, w_ij ← w_ij / ((s_i + s_j)/2), and
/// solve again, so regions that were compressed in the plane spread out.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>
#include <meshsmith/parametrization/harmonic.h>

#include <vector>

namespace meshsmith::parametrization {

struct StretchOptions {
  int iterations = 10;                                    ///< reweighting steps at most (≥ 0)
  HarmonicWeights weights = HarmonicWeights::mean_value;  ///< weights of the starting harmonic map
  BoundaryShape shape = BoundaryShape::circle;            ///< the fixed convex boundary
};

struct StretchResult {
  geometry::ParameterMatrix uv;  ///< #V×2, the map of lowest stretch met
  /// Sander et al.'s scale-invariant L2 stretch (normalized_global_stretch_l2, 1 for an isometry
  /// up to scale) of the harmonic start (entry 0) and after every reweighting step.
  std::vector<double> stretch;
  int best_iteration = 0;        ///< index into `stretch` of the returned map
};

/// Stretch-minimizing map of a topological disk. Iterates until `iterations` steps are done or
/// the stretch stops decreasing (Yoshizawa et al.'s stopping rule), and returns the best map.
/// Every step solves a harmonic map with positive weights on the same convex boundary, so with
/// positive starting weights (uniform, mean-value) every map stays bijective.
/// V: #V×3, F: #F×3. Reports progress per step (cancellable).
/// \pre (V, F) is a topological disk (see harmonic). \throw InputError naming the problem,
///      InputError for iterations < 0; SolverError as harmonic; Cancelled.
StretchResult stretch_minimizing(const VertexRef& V, const FaceRef& F, const StretchOptions& options = {},
                                 const Progress& progress = {});

}  // namespace meshsmith::parametrization
