// Polyline smoothing (curve_smoothing.h): the polygon's uniform graph Laplacian turned into the
// same umbrella operator and step loop as meshes (umbrella.h), on the points padded to three
// coordinates (a planar curve's third coordinate stays exactly 0) and normalized.
#include <meshsmith/smoothing/curve_smoothing.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include "umbrella.h"

#include <cmath>
#include <string>

namespace meshsmith::smoothing {

namespace {

constexpr const char* kFunction = "smooth_curve";

VertexMatrix padded(const PointRef& P) {
  VertexMatrix Q = VertexMatrix::Zero(P.rows(), 3);
  Q.leftCols(P.cols()) = P;
  return Q;
}

/// The polygon's graph Laplacian: weight 1 on each segment (i, i+1), and (n−1, 0) if closed.
Eigen::SparseMatrix<double> polygon_laplacian(Eigen::Index n, bool closed) {
  std::vector<Eigen::Triplet<double>> entries;
  const Eigen::Index segments = closed ? n : n - 1;
  for (Eigen::Index i = 0; i < segments; ++i) {
    const int a = static_cast<int>(i), b = static_cast<int>((i + 1) % n);
    entries.emplace_back(a, b, 1.0);
    entries.emplace_back(b, a, 1.0);
    entries.emplace_back(a, a, -1.0);
    entries.emplace_back(b, b, -1.0);
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(entries.begin(), entries.end());
  return L;
}

}  // namespace

PointMatrix smooth_curve(const PointRef& P, const CurveSmoothingOptions& options, const Progress& progress) {
  const Eigen::Index n = P.rows(), d = P.cols();
  if (d != 2 && d != 3) throw InputError("smooth_curve: P has " + std::to_string(d) + " columns: expected 2 or 3");
  const Eigen::Index minimum = options.closed ? 3 : 2;
  if (n < minimum) {
    throw InputError("smooth_curve: P has " + std::to_string(n) + " points: an " +
                     std::string(options.closed ? "closed" : "open") + " curve needs at least " + std::to_string(minimum));
  }
  const VertexMatrix Q = padded(P);
  validate_vertices(Q, "P");
  if (!std::isfinite(options.lambda) || !(options.lambda > 0.0)) {
    throw InputError("smooth_curve: lam = " + number_text(options.lambda) + ": expected a finite number > 0");
  }
  if (!std::isfinite(options.mu) || options.mu > 0.0) {
    throw InputError("smooth_curve: mu = " + number_text(options.mu) + ": expected a finite number <= 0 (0: no Taubin step)");
  }
  if (options.iterations < 0) {
    throw InputError("smooth_curve: iterations = " + std::to_string(options.iterations) + ": expected an integer >= 0");
  }
  validate_error_control(options.error_control, kFunction);
  detail::validate_fixed(options.fixed, n, kFunction);
  const CoordinateFrame frame = normalizing_frame(Q);
  const VertexMatrix start = frame.normalize_vertices(Q);

  std::vector<int> fixed = options.fixed;
  if (!options.closed) {
    fixed.push_back(0);
    fixed.push_back(static_cast<int>(n - 1));
  }
  const detail::Umbrella U = detail::umbrella_operator(polygon_laplacian(n, options.closed), fixed, kFunction);

  detail::Bound bound;
  bound.control = options.error_control;
  bound.original = &start;
  bound.meaning = SlabAxis::tangent;
  if (options.error_control.bound != ErrorBound::none) {
    bound.control.epsilon = frame.to_normalized(options.error_control.epsilon, 1);
    if (!(bound.control.epsilon > 0.0)) {
      throw InputError("smooth_curve: the error bound " + number_text(options.error_control.epsilon) +
                       " is too small for coordinates of size 2^" + std::to_string(frame.exponent));
    }
  }
  if (options.error_control.bound == ErrorBound::error_slab) {
    if (options.tangents.rows() != n || options.tangents.cols() != d) {
      throw InputError("smooth_curve: the tangents are " + std::to_string(options.tangents.rows()) + "x" +
                       std::to_string(options.tangents.cols()) + ": expected one unit tangent per point, " +
                       std::to_string(n) + "x" + std::to_string(d));
    }
    bound.axes = padded(options.tangents);
    validate_vertices(bound.axes, "tangents");
  }
  if (options.iterations == 0) return P;

  std::vector<detail::Step> steps;
  const detail::Umbrella* umbrella = &U;
  for (const double factor : {options.lambda, options.mu}) {
    if (factor == 0.0) continue;
    steps.emplace_back([umbrella, factor](const VertexMatrix& before, VertexMatrix& after) {
      detail::explicit_step(*umbrella, factor, before, after);
    });
  }
  const VertexMatrix result = detail::run_steps(start, options.iterations, steps, {}, bound, progress, "smoothing");
  return frame.vertices_to_input(result, "a smoothed point").leftCols(d);
}

}  // namespace meshsmith::smoothing
