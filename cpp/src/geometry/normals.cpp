#include <meshsmith/geometry/normals.h>

#include "triangle_corners.h"

namespace meshsmith::geometry {

namespace {

VertexMatrix unit_face_normals(const VertexRef& V, const FaceRef& F, detail::CornerMatrix* weights,
                               NormalWeighting weighting) {
  VertexMatrix N(F.rows(), 3);
  detail::parallel_for(F.rows(), [&](Eigen::Index f) {
    const detail::Triangle t = detail::triangle(V, F, f);
    if (t.degenerate) {
      N.row(f).setZero();
      if (weights) weights->row(f).setZero();
      return;
    }
    N.row(f) = (t.cross / t.double_area).transpose();
    if (!weights) return;
    for (int c = 0; c < 3; ++c) {
      switch (weighting) {
        case NormalWeighting::uniform: (*weights)(f, c) = 1.0; break;
        case NormalWeighting::area: (*weights)(f, c) = t.double_area; break;
        case NormalWeighting::angle: (*weights)(f, c) = detail::corner_angle(t, c); break;
      }
    }
  });
  return N;
}

}  // namespace

VertexMatrix face_normals(const VertexRef& V, const FaceRef& F) {
  detail::validate_surface(V, F);
  return unit_face_normals(V, F, nullptr, NormalWeighting::uniform);
}

VertexMatrix vertex_normals(const VertexRef& V, const FaceRef& F, NormalWeighting weighting) {
  detail::validate_surface(V, F);
  detail::CornerMatrix weights(F.rows(), 3);
  const VertexMatrix face = unit_face_normals(V, F, &weights, weighting);
  const detail::VertexCorners corners = detail::vertex_corners(F, V.rows());
  VertexMatrix N(V.rows(), 3);
  detail::parallel_for(V.rows(), [&](Eigen::Index v) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (auto k = corners.begin(v); k < corners.end(v); ++k) {
      const int corner = corners.corners[k];
      sum += weights(corner / 3, corner % 3) * face.row(corner / 3);
    }
    const double norm = sum.norm();
    N.row(v) = norm > 0.0 ? (sum / norm).eval() : sum;
  });
  return N;
}

}  // namespace meshsmith::geometry
