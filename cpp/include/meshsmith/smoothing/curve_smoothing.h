#pragma once
/// \file curve_smoothing.h
/// Smoothing of polylines (§3.0.1, "Smoothing (2D)"): the update Δp_i = ½(p_(i+1) − p_i) +
/// ½(p_(i−1) − p_i), i.e. [p] ← (I + λU)[p] with U the polygon's second-difference matrix, and
/// Taubin's λ|μ filter (I + μU)(I + λU) on the same U (laplacian_smoothing.h documents its
/// transfer function; for a closed polygon of n points the eigenvalues of −U are
/// k_j = 1 − cos(2πj/n), the frequencies of its Fourier modes).
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/progress.h>
#include <meshsmith/smoothing/error_control.h>

#include <vector>

namespace meshsmith::smoothing {

struct CurveSmoothingOptions {
  double lambda = 0.5;       ///< λ > 0
  double mu = 0.0;           ///< 0: Laplacian steps only; μ < 0: Taubin λ|μ pairs
  int iterations = 10;       ///< ≥ 0 steps (Taubin: pairs)
  bool closed = false;       ///< a segment joins the last point to the first
  std::vector<int> fixed;    ///< points held in place (an open curve's two ends always are)
  ErrorControl error_control;  ///< error_slab bounds the displacement orthogonal to the original tangent
  PointMatrix tangents;        ///< n×d unit tangents of P, for an error slab only (rows of zeros: ε-ball)
};

/// Smooths the polyline P (n×d, d = 2 or 3; do not repeat the first point at the end of a closed
/// curve). Returns the smoothed n×d points. An error slab needs the original unit tangents in
/// options.tangents (the Python wrapper passes meshsmith.curves.tangents(P)).
/// \pre n ≥ 2 (open) or n ≥ 3 (closed); P finite; λ > 0, μ ≤ 0 finite; iterations ≥ 0; fixed
///      indices in [0, n); tangents n×d when the bound is error_slab.
/// \throw InputError if a precondition fails; Cancelled through `progress`.
/// Complexity: O(n·iterations).
PointMatrix smooth_curve(const PointRef& P, const CurveSmoothingOptions& options, const Progress& progress = {});

}  // namespace meshsmith::smoothing
