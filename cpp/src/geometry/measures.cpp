#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/measures.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <functional>

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

double triangle_area(const VertexRef& V, const FaceRef& F, Eigen::Index f) {
  const Eigen::RowVector3d a = V.row(F(f, 0));
  return 0.5 * (V.row(F(f, 1)) - a).cross(V.row(F(f, 2)) - a).norm();
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
  return deterministic_face_sum(F.rows(), [&](Eigen::Index f) { return triangle_area(V, F, f); });
}

double volume(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  return deterministic_face_sum(F.rows(), [&](Eigen::Index f) {
           const Eigen::RowVector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
           return a.dot(b.cross(c));
         }) / 6.0;
}

}  // namespace meshsmith::geometry
