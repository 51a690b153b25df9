#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/measures.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

namespace meshsmith::geometry {

namespace {

/// Σ_f term(f) over all faces with a fixed split of the range (simple_partitioner with a fixed
/// grain), so the floating-point result does not depend on the thread count or scheduling.
template <typename Term>
double deterministic_face_sum(Eigen::Index n_faces, const Term& term) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Eigen::Index>(0, n_faces, 8192), 0.0,
      [&](const tbb::blocked_range<Eigen::Index>& range, double sum) {
        for (Eigen::Index f = range.begin(); f < range.end(); ++f) sum += term(f);
        return sum;
      },
      std::plus<double>());
}

/// Area of face f, computed on its edge vectors scaled into (−1, 1) (core/normalization.h):
/// no overflow or underflow in the cross product, whatever the coordinates.
/// \throw InputError if the area itself exceeds the double range (a triangle of size 1e155).
double triangle_area(const VertexRef& V, const FaceRef& F, Eigen::Index f) {
  // Fast path: with every edge-vector component in [2^-250, 2^250] (or 0) the cross product can
  // neither overflow nor underflow, and scaling by a power of two commutes with each rounding,
  // so this gives the scaled computation's value bit for bit (a subnormal coordinate aside, where
  // it is the more accurate of the two) without its frexp/ldexp calls.
  const double* a = V.row(F(f, 0)).data();
  const double* b = V.row(F(f, 1)).data();
  const double* c = V.row(F(f, 2)).data();
  const Eigen::Vector3d u(b[0] - a[0], b[1] - a[1], b[2] - a[2]), w(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
  const double largest = std::max(u.cwiseAbs().maxCoeff(), w.cwiseAbs().maxCoeff());
  constexpr double kHigh = 0x1p250, kLow = 0x1p-250;
  if (largest <= kHigh) {
    const double smallest_nonzero = [&] {
      double m = kHigh;
      for (int j = 0; j < 3; ++j) {
        if (u(j) != 0.0) m = std::min(m, std::abs(u(j)));
        if (w(j) != 0.0) m = std::min(m, std::abs(w(j)));
      }
      return m;
    }();
    if (smallest_nonzero >= kLow) return 0.5 * u.cross(w).norm();
  }
  Eigen::Vector3d ab, ac;
  const CoordinateFrame frame = triangle_edge_vectors(V.row(F(f, 0)).data(), V.row(F(f, 1)).data(),
                                                      V.row(F(f, 2)).data(), ab, ac);
  const double area = std::ldexp(0.5 * ab.cross(ac).norm(), 2 * frame.exponent);
  if (!std::isfinite(area))
    throw InputError("the area of face " + std::to_string(f) + " exceeds the double range (about 1.8e308): its "
                     "edges are up to 2^" + std::to_string(frame.exponent) + " long; scale the mesh down");
  return area;
}

}  // namespace

Eigen::VectorXd face_areas(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  Eigen::VectorXd areas(F.rows());
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, F.rows(), 8192),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index f = range.begin(); f < range.end(); ++f) areas[f] = triangle_area(V, F, f);
                    });
  return areas;
}

double surface_area(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  const double total = deterministic_face_sum(F.rows(), [&](Eigen::Index f) { return triangle_area(V, F, f); });
  if (!std::isfinite(total))
    throw InputError("surface_area: the total area exceeds the double range (about 1.8e308); scale the mesh down");
  return total;
}

double volume(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  // A sum of degree-3 terms: on normalized coordinates (core/normalization.h), then scaled back.
  const CoordinateFrame frame = normalizing_frame(V);
  const VertexMatrix W = frame.normalize_vertices(V);
  const double normalized = deterministic_face_sum(F.rows(), [&](Eigen::Index f) {
                              const Eigen::RowVector3d a = W.row(F(f, 0)), b = W.row(F(f, 1)), c = W.row(F(f, 2));
                              return a.dot(b.cross(c));
                            }) / 6.0;
  return frame.to_input(normalized, 3, "volume: the enclosed volume");
}

}  // namespace meshsmith::geometry
