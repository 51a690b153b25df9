#pragma once
/// \file normalization.h
/// Normalized coordinates for scale-invariant algorithms (DESIGN.md, "Errors"): coordinates
/// anywhere in the double range (1e-300 to 1e308, denormals) are brought into (-1, 1) by
/// subtracting the centre of the bounding box and scaling by a power of two, which is exact.
/// An algorithm runs on the normalized points and maps its outputs back with
/// CoordinateFrame::to_input (a length^p quantity is multiplied by 2^(p·exponent), exactly).
///
/// Because the centre is computed covariantly and the scaling is exact, two inputs that differ
/// by a power-of-two factor 2^k give bit-identical normalized points (outside the denormal
/// range), so the algorithm's answers differ exactly by 2^(p·k). Outputs that do not fit a double
/// once mapped back (the area of a triangle of size 1e200) raise an InputError naming the
/// quantity instead of turning into inf.
#include <meshsmith/core/types.h>

#include <Eigen/Core>

namespace meshsmith {

/// Row-major points of any dimension (n×d, d = 2 or 3 in practice).
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using PointRef = Eigen::Ref<const PointMatrix>;

/// The similarity W = 2^-exponent · (X − centre) that normalizes a point set.
struct CoordinateFrame {
  Eigen::RowVectorXd centre;  ///< 1×d, in input coordinates (the bounding box centre)
  int exponent = 0;           ///< input lengths are 2^exponent normalized lengths

  /// Normalized copy of X (n×d, d = centre.size()): 2^-exponent X − 2^-exponent centre, each
  /// term exact (no overflow even for coordinates near ±1.8e308).
  PointMatrix normalize(const PointRef& X) const;
  VertexMatrix normalize_vertices(const VertexRef& X) const;  ///< the same for n×3 vertices
  /// One point of d coordinates, in place of `out` (may alias `in`).
  void normalize_point(const double* in, double* out) const;

  /// Normalized positions (n×d) back to input coordinates: centre + 2^exponent W.
  /// \throw InputError naming `what` and its row if a coordinate overflows the double range.
  PointMatrix positions_to_input(const PointRef& W, const char* what) const;
  VertexMatrix vertices_to_input(const VertexRef& W, const char* what) const;  ///< n×3 version

  /// A normalized quantity of unit length^power (power 1: a distance, 2: an area, -1: a
  /// curvature) in input units: value · 2^(power·exponent), exact unless it leaves the range.
  /// \throw InputError naming `what` if a finite value overflows to ±inf (a result that
  /// underflows is rounded, to 0 at worst, as IEEE arithmetic does).
  double to_input(double value, int power, const char* what) const;
  /// In place on an array of `count` values (same rules as to_input).
  void to_input(double* values, Eigen::Index count, int power, const char* what) const;
  /// An input quantity of unit length^power in normalized units (saturates to 0 or ±inf;
  /// callers pass option values such as a radius or an error bound through it).
  double to_normalized(double value, int power) const;
};

/// The frame that maps X into (-1, 1)^d: centre = midpoint of the bounding box, exponent the
/// smallest power of two with every |x − centre| < 2^exponent (for coincident points, the
/// exponent of the common coordinate, or 0 at the origin).
/// \pre X is non-empty and finite (validate_vertices).
CoordinateFrame normalizing_frame(const PointRef& X);

}  // namespace meshsmith
