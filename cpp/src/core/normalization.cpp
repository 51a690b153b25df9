// Normalized coordinates (core/normalization.h): every operation here is a power-of-two
// scaling (std::ldexp), exact in both directions outside the denormal range.
#include <meshsmith/core/normalization.h>

#include <meshsmith/core/errors.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace meshsmith {

namespace {

std::string overflow_message(const std::string& what, double value, int power, int exponent) {
  int value_exponent = 0;
  std::frexp(value, &value_exponent);
  return what + " is about 2^" + std::to_string(value_exponent + power * exponent) +
         ", beyond the double range (2^1024): with coordinates up to 2^" + std::to_string(exponent) +
         " a quantity of unit length^" + std::to_string(power) + " does not fit; scale the input down";
}

}  // namespace

CoordinateFrame normalizing_frame(const PointRef& X) {
  CoordinateFrame frame;
  const double largest = X.size() > 0 ? X.cwiseAbs().maxCoeff() : 0.0;
  if (largest > 0.0) std::frexp(largest, &frame.exponent);  // largest in [2^(e-1), 2^e)
  return frame;
}

CoordinateFrame triangle_edge_vectors(const double* a, const double* b, const double* c, Eigen::Vector3d& ab,
                                      Eigen::Vector3d& ac) {
  for (int j = 0; j < 3; ++j) {
    ab(j) = 0.5 * b[j] - 0.5 * a[j];
    ac(j) = 0.5 * c[j] - 0.5 * a[j];
  }
  CoordinateFrame frame;
  const double largest = std::max(ab.cwiseAbs().maxCoeff(), ac.cwiseAbs().maxCoeff());
  if (largest > 0.0) std::frexp(largest, &frame.exponent);
  if (frame.exponent >= -1021 && frame.exponent <= 1022) {
    // 2^-exponent is a normal double: a product with it is rounded once, to exactly what ldexp
    // returns, at a fraction of ldexp's cost (six calls per triangle were most of face_areas).
    const double scale = std::ldexp(1.0, -frame.exponent);
    ab *= scale;
    ac *= scale;
  } else {
    ab = ab.unaryExpr([&](double x) { return std::ldexp(x, -frame.exponent); });
    ac = ac.unaryExpr([&](double x) { return std::ldexp(x, -frame.exponent); });
  }
  ++frame.exponent;  // the halves
  return frame;
}

PointMatrix CoordinateFrame::normalize(const PointRef& X) const {
  PointMatrix W(X.rows(), X.cols());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index j = 0; j < X.cols(); ++j) W(i, j) = std::ldexp(X(i, j), -exponent);
  return W;
}

VertexMatrix CoordinateFrame::normalize_vertices(const VertexRef& X) const {
  VertexMatrix W(X.rows(), 3);
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (int j = 0; j < 3; ++j) W(i, j) = std::ldexp(X(i, j), -exponent);
  return W;
}

void CoordinateFrame::normalize_point(const double* in, double* out, int dimension) const {
  for (int j = 0; j < dimension; ++j) out[j] = std::ldexp(in[j], -exponent);
}

PointMatrix CoordinateFrame::positions_to_input(const PointRef& W, const char* what) const {
  PointMatrix X(W.rows(), W.cols());
  for (Eigen::Index i = 0; i < W.rows(); ++i)
    for (Eigen::Index j = 0; j < W.cols(); ++j) {
      X(i, j) = std::ldexp(W(i, j), exponent);
      if (std::isfinite(W(i, j)) && !std::isfinite(X(i, j)))
        throw InputError(overflow_message(std::string(what) + " " + std::to_string(i) + ", coordinate " +
                                              std::to_string(j),
                                          W(i, j), 1, exponent));
    }
  return X;
}

VertexMatrix CoordinateFrame::vertices_to_input(const VertexRef& W, const char* what) const {
  return positions_to_input(W, what);
}

namespace {

/// value · 2^e: a multiplication by the exact power of two where 2^e is a normal double (the
/// same correctly rounded result as std::ldexp, without the library call), ldexp elsewhere.
inline double times_power_of_two(double value, int e) {
  if (e == 0) return value;
  return e >= -1000 && e <= 1000 ? value * std::ldexp(1.0, e) : std::ldexp(value, e);
}

}  // namespace

double CoordinateFrame::to_input(double value, int power, const char* what) const {
  const double result = times_power_of_two(value, power * exponent);
  if (std::isfinite(value) && !std::isfinite(result)) throw InputError(overflow_message(what, value, power, exponent));
  return result;
}

void CoordinateFrame::to_input(double* values, Eigen::Index count, int power, const char* what) const {
  const int e = power * exponent;
  if (e == 0) return;
  for (Eigen::Index i = 0; i < count; ++i) {
    const double result = times_power_of_two(values[i], e);
    if (std::isfinite(values[i]) && !std::isfinite(result))
      throw InputError(overflow_message(std::string(what) + " " + std::to_string(i), values[i], power, exponent));
    values[i] = result;
  }
}

double CoordinateFrame::to_normalized(double value, int power) const { return std::ldexp(value, -power * exponent); }

}  // namespace meshsmith
