#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/measures.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

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
