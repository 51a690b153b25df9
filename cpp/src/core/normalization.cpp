// Normalized coordinates (core/normalization.h). Everything here is a power-of-two scaling
// (std::ldexp, exact) and one subtraction per coordinate, done after the scaling so that
// nothing overflows: the centre is the bounding-box midpoint lo/2 + hi/2, the half extent
// hi/2 − lo/2, both within the double range for any finite input. Scaling the input by 2^k
// scales the centre and the half extent by exactly 2^k (outside the denormal range), so the
// exponent moves by k and the normalized points are bit-identical.
#include <meshsmith/core/normalization.h>

#include <meshsmith/core/errors.h>

#include <cmath>
#include <string>

namespace meshsmith {

namespace {

std::string overflow_message(const char* what, double value, int power, int exponent) {
  int mantissa_exponent = 0;
  std::frexp(value, &mantissa_exponent);
  return std::string(what) + ": the value is about 2^" + std::to_string(mantissa_exponent + power * exponent) +
         ", beyond the double range (about 2^1024): the input coordinates (lengths up to 2^" +
         std::to_string(exponent) + ") are too large for a quantity of unit length^" + std::to_string(power) +
         "; scale the input down";
}

}  // namespace

CoordinateFrame normalizing_frame(const PointRef& X) {
  CoordinateFrame frame;
  const Eigen::Index d = X.cols();
  frame.centre.resize(d);
  double half_extent = 0.0, largest_centre = 0.0;
  for (Eigen::Index j = 0; j < d; ++j) {
    const double lo = X.col(j).minCoeff(), hi = X.col(j).maxCoeff();
    frame.centre(j) = 0.5 * lo + 0.5 * hi;
    half_extent = std::max(half_extent, 0.5 * hi - 0.5 * lo);
    largest_centre = std::max(largest_centre, std::abs(frame.centre(j)));
  }
  // |x − centre| <= half_extent (plus half an ulp of the centre) < 2^(q+1) with half_extent in
  // [2^(q−1), 2^q): the normalized coordinates lie in (−1, 1), away from both ends.
  const double reference = half_extent > 0.0 ? half_extent : largest_centre;
  if (reference > 0.0) {
    int q = 0;
    std::frexp(reference, &q);
    frame.exponent = q + 1;
  }
  return frame;
}

PointMatrix CoordinateFrame::normalize(const PointRef& X) const {
  PointMatrix W(X.rows(), X.cols());
  for (Eigen::Index j = 0; j < X.cols(); ++j) {
    const double c = std::ldexp(centre(j), -exponent);
    for (Eigen::Index i = 0; i < X.rows(); ++i) W(i, j) = std::ldexp(X(i, j), -exponent) - c;
  }
  return W;
}

VertexMatrix CoordinateFrame::normalize_vertices(const VertexRef& X) const {
  VertexMatrix W(X.rows(), 3);
  const double c[3] = {std::ldexp(centre(0), -exponent), std::ldexp(centre(1), -exponent),
                       std::ldexp(centre(2), -exponent)};
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (int j = 0; j < 3; ++j) W(i, j) = std::ldexp(X(i, j), -exponent) - c[j];
  return W;
}

void CoordinateFrame::normalize_point(const double* in, double* out) const {
  for (Eigen::Index j = 0; j < centre.size(); ++j)
    out[j] = std::ldexp(in[j], -exponent) - std::ldexp(centre(j), -exponent);
}

PointMatrix CoordinateFrame::positions_to_input(const PointRef& W, const char* what) const {
  PointMatrix X(W.rows(), W.cols());
  for (Eigen::Index i = 0; i < W.rows(); ++i)
    for (Eigen::Index j = 0; j < W.cols(); ++j) {
      X(i, j) = centre(j) + std::ldexp(W(i, j), exponent);
      if (std::isfinite(W(i, j)) && !std::isfinite(X(i, j)))
        throw InputError(std::string(what) + " row " + std::to_string(i) + ", coordinate " + std::to_string(j) +
                         " lies beyond the double range once mapped back to the input's coordinates "
                         "(lengths up to 2^" + std::to_string(exponent) + "); scale the input down");
    }
  return X;
}

VertexMatrix CoordinateFrame::vertices_to_input(const VertexRef& W, const char* what) const {
  return positions_to_input(W, what);
}

double CoordinateFrame::to_input(double value, int power, const char* what) const {
  const double result = std::ldexp(value, power * exponent);
  if (std::isfinite(value) && !std::isfinite(result)) throw InputError(overflow_message(what, value, power, exponent));
  return result;
}

void CoordinateFrame::to_input(double* values, Eigen::Index count, int power, const char* what) const {
  for (Eigen::Index i = 0; i < count; ++i) {
    const double result = std::ldexp(values[i], power * exponent);
    if (std::isfinite(values[i]) && !std::isfinite(result))
      throw InputError(overflow_message((std::string(what) + " " + std::to_string(i)).c_str(), values[i], power,
                                        exponent));
    values[i] = result;
  }
}

double CoordinateFrame::to_normalized(double value, int power) const { return std::ldexp(value, -power * exponent); }

}  // namespace meshsmith
