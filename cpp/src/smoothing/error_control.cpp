// Error bounds of smoothing (error_control.h): projection onto the ε-ball or the error slab of
// every vertex, exact in the sense that the bound holds for the rounded stored positions.
//
// The projection aims at ε(1 − 4u) (u = 2⁻⁵³·2, the machine epsilon) rather than ε, so the few
// ulps that the subtraction p − p* and the norm lose in rounding do not push a vertex across;
// a row that still tests outside (a displacement much longer than ε in the slab's free
// directions makes the dot product's rounding larger than the margin) is corrected again, and
// after a few corrections pulled towards p* until it tests inside. Each test is written with the
// operations in the order numpy evaluates `np.linalg.norm(V - V0, axis=1)` and
// `((V - V0) * N).sum(axis=1)`, and the build does not contract them into FMAs (-std=c++17).
#include <meshsmith/smoothing/error_control.h>

#include <meshsmith/core/errors.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>

namespace meshsmith::smoothing {

namespace {

constexpr double kMargin = 1.0 - 4.0 * std::numeric_limits<double>::epsilon();

double dot(const double* a, const double* b) { return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]; }

/// The rounded displacement d = p − p* as stored positions give it.
void displacement(const double* p, const double* original, double* d) {
  for (int k = 0; k < 3; ++k) d[k] = p[k] - original[k];
}

bool inside_ball(const double* p, const double* original, double epsilon) {
  double d[3];
  displacement(p, original, d);
  return std::sqrt(dot(d, d)) <= epsilon;
}

/// The component that the slab bounds: along the axis (normal), or the length of the part
/// orthogonal to it (tangent).
double bounded_component(const double* d, const double* axis, SlabAxis meaning) {
  const double along = dot(d, axis);
  if (meaning == SlabAxis::normal) return std::abs(along);
  double across[3];
  for (int k = 0; k < 3; ++k) across[k] = d[k] - along * axis[k];
  return std::sqrt(dot(across, across));
}

bool inside_slab(const double* p, const double* original, const double* axis, SlabAxis meaning, double epsilon) {
  double d[3];
  displacement(p, original, d);
  return bounded_component(d, axis, meaning) <= epsilon;
}

/// Shrinks p towards p* (scaling the displacement) until test(p) holds; p* itself passes.
template <typename Test>
void pull_in(double* p, const double* original, Test&& test) {
  double factor = kMargin;
  for (int attempt = 0; attempt < 64 && !test(p); ++attempt) {
    for (int k = 0; k < 3; ++k) p[k] = original[k] + factor * (p[k] - original[k]);
    factor *= 0.5;
  }
  if (!test(p)) {
    for (int k = 0; k < 3; ++k) p[k] = original[k];
  }
}

void project_ball(double* p, const double* original, double epsilon) {
  if (inside_ball(p, original, epsilon)) return;
  double d[3];
  displacement(p, original, d);
  const double length = std::sqrt(dot(d, d));
  const double scale = kMargin * epsilon / length;
  for (int k = 0; k < 3; ++k) p[k] = original[k] + scale * d[k];
  pull_in(p, original, [&](const double* q) { return inside_ball(q, original, epsilon); });
}

void project_slab(double* p, const double* original, const double* axis, SlabAxis meaning, double epsilon) {
  if (inside_slab(p, original, axis, meaning, epsilon)) return;
  const double target = kMargin * epsilon;
  for (int attempt = 0; attempt < 4 && !inside_slab(p, original, axis, meaning, epsilon); ++attempt) {
    double d[3];
    displacement(p, original, d);
    const double along = dot(d, axis);
    if (meaning == SlabAxis::normal) {
      // Clamp the normal component to ±target, keep the tangential one.
      const double excess = along - std::copysign(target, along);
      for (int k = 0; k < 3; ++k) p[k] -= excess * axis[k];
    } else {
      // Scale the part orthogonal to the tangent down to length target, keep the tangential one.
      double across[3];
      for (int k = 0; k < 3; ++k) across[k] = d[k] - along * axis[k];
      const double length = std::sqrt(dot(across, across));
      const double scale = target / length;
      for (int k = 0; k < 3; ++k) p[k] = original[k] + along * axis[k] + scale * across[k];
    }
  }
  pull_in(p, original, [&](const double* q) { return inside_slab(q, original, axis, meaning, epsilon); });
}

}  // namespace

void validate_error_control(const ErrorControl& control, const char* function) {
  if (control.bound == ErrorBound::none) return;
  const char* name = control.bound == ErrorBound::epsilon_ball ? "epsilon_ball" : "error_slab";
  if (!(control.epsilon > 0.0) || !std::isfinite(control.epsilon)) {
    throw InputError(std::string(function) + ": " + name + " = " + number_text(control.epsilon) +
                     ": expected a finite distance > 0");
  }
}

void project_onto_error_bound(const VertexRef& original, const VertexRef& axes, SlabAxis axis_meaning,
                              const ErrorControl& control, VertexMatrix& V) {
  validate_error_control(control, "project_onto_error_bound");
  if (control.bound == ErrorBound::none) return;
  if (original.rows() != V.rows() || (control.bound == ErrorBound::error_slab && axes.rows() != V.rows())) {
    throw InputError("project_onto_error_bound: V has " + std::to_string(V.rows()) + " rows, the original positions " +
                     std::to_string(original.rows()) + " and the axes " + std::to_string(axes.rows()) +
                     ": expected the same number");
  }
  const double epsilon = control.epsilon;
  const bool slab = control.bound == ErrorBound::error_slab;
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, V.rows(), 4096), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index i = range.begin(); i != range.end(); ++i) {
      double* p = V.row(i).data();
      const double* o = original.row(i).data();
      if (slab) {
        const double* axis = axes.row(i).data();
        if (axis[0] != 0.0 || axis[1] != 0.0 || axis[2] != 0.0) {
          project_slab(p, o, axis, axis_meaning, epsilon);
          continue;
        }
      }
      project_ball(p, o, epsilon);
    }
  });
}

}  // namespace meshsmith::smoothing
