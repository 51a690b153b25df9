#pragma once
/// \file normalization.h
/// Normalized coordinates for scale-invariant algorithms (DESIGN.md, "Errors"): coordinates
/// anywhere in the double range (1e-300 to 1e308, denormals aside) are brought into (-1, 1) by
/// one scaling by a power of two, which is exact. An algorithm runs on the normalized points and
/// maps its outputs back with CoordinateFrame::to_input (a length^p quantity is multiplied by
/// 2^(p·exponent), exactly).
///
/// Two inputs that differ by a factor 2^k give bit-identical normalized points, so the answers
/// differ exactly by 2^(p·k); and an input already near 1 computes exactly what it computed
/// unnormalized (every operation commutes with an exact power-of-two scaling). The frame does
/// not move the origin to the centre of the points: the scaling alone is exact both ways, so
/// positions map back bit for bit (kept vertices of a decimation, collapse records), which a
/// subtraction of the centre would round. Quantities that do not fit a double once mapped back
/// (the area of a triangle of size 1e200) raise an InputError naming the quantity instead of
/// turning into inf.
#include <meshsmith/core/types.h>

#include <Eigen/Core>

namespace meshsmith {

/// Row-major points of any dimension (n×d, d = 2 or 3 in practice).
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using PointRef = Eigen::Ref<const PointMatrix>;

/// The scaling W = 2^-exponent · X that normalizes a point set.
struct CoordinateFrame {
  int exponent = 0;  ///< input lengths are 2^exponent normalized lengths

  /// Normalized copy of X (n×d): 2^-exponent X, exact (a coordinate that was denormal to begin
  /// with may lose bits when exponent > 0; nothing else rounds).
  PointMatrix normalize(const PointRef& X) const;
  VertexMatrix normalize_vertices(const VertexRef& X) const;  ///< the same for n×3 vertices
  /// One point of `dimension` coordinates into `out` (may alias `in`).
  void normalize_point(const double* in, double* out, int dimension = 3) const;

  /// Normalized positions (n×d) back to input coordinates: 2^exponent W.
  /// \throw InputError naming `what` and its row if a coordinate overflows the double range
  /// (a constructed point, such as an optimal placement, outside the input's range).
  PointMatrix positions_to_input(const PointRef& W, const char* what) const;
  VertexMatrix vertices_to_input(const VertexRef& W, const char* what) const;  ///< n×3 version

  /// A normalized quantity of unit length^power (1: a distance, 2: an area, −1: a curvature)
  /// in input units: value · 2^(power·exponent), exact unless it leaves the range.
  /// \throw InputError naming `what` if a finite value overflows to ±inf (a result that
  /// underflows is rounded, to 0 at worst, as IEEE arithmetic does).
  double to_input(double value, int power, const char* what) const;
  /// In place on `count` values (same rules; the message names `what` and the index).
  void to_input(double* values, Eigen::Index count, int power, const char* what) const;
  /// An input quantity of unit length^power in normalized units (saturates to 0 or ±inf;
  /// option values such as a radius or an error bound go through it).
  double to_normalized(double value, int power) const;
};

/// Per-element normalization for local quantities of a triangle (area, normal, angles): its
/// edge vectors b − a and c − a scaled into (−1, 1) by one power of two, exactly (computed as
/// halves, so corners near ±1.8e308 do not overflow the subtraction). A quantity of unit
/// length^p computed from them maps back with the returned frame; this keeps the small faces of
/// a mesh that also holds a vertex at 1e300, which one frame for the whole mesh would flush to 0.
/// All corners equal: both vectors 0 and exponent 0.
CoordinateFrame triangle_edge_vectors(const double* a, const double* b, const double* c, Eigen::Vector3d& ab,
                                      Eigen::Vector3d& ac);

/// The frame that maps X into (-1, 1)^d: the smallest exponent with every |x| < 2^exponent
/// (0 when every coordinate is 0).
/// \pre X is finite (validate_vertices); an empty X gives exponent 0.
CoordinateFrame normalizing_frame(const PointRef& X);

}  // namespace meshsmith
