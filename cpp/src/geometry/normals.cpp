#include <meshsmith/geometry/normals.h>

#include "triangle_corners.h"

#include <meshsmith/core/normalization.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace meshsmith::geometry {

VertexMatrix face_normals(const VertexRef& V, const FaceRef& F) {
  detail::validate_surface(V, F);
  VertexMatrix N(F.rows(), 3);
  detail::parallel_for(F.rows(), [&](Eigen::Index f) {
    const detail::Triangle t = detail::triangle(V, F, f);
    if (t.degenerate) {
      N.row(f).setZero();
    } else {
      N.row(f) = (t.cross / t.double_area).transpose();
    }
  });
  return N;
}

VertexMatrix vertex_normals(const VertexRef& V, const FaceRef& F, NormalWeighting weighting) {
  detail::validate_surface(V, F);
  VertexMatrix N;
  if (weighting == NormalWeighting::area && std::abs(normalizing_frame(V).exponent) <= 200) {
    // Area weighting adds each face's cross product (2·area·unit normal) to its corners: no
    // angles, lengths or degeneracy test needed (a degenerate face's cross product is ~0).
    N = detail::accumulate_at_vertices<3>(F, V.rows(), [&](Eigen::Index f, double (*out)[3]) {
      const Eigen::Vector3d cross = detail::triangle_cross(V, F, f);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) out[c][k] = cross[k];
    });
  } else if (weighting == NormalWeighting::area) {
    // Coordinates beyond 2^±200: the cross products come scaled by 4^-exponent (triangle()), and
    // each vertex adds them relative to the largest face around it, 4^(exponent − largest), so
    // none overflows and a face fades only where it is negligible next to that largest one.
    std::vector<int> face_exponent(static_cast<std::size_t>(F.rows()));
    detail::parallel_for(F.rows(), [&](Eigen::Index f) { face_exponent[f] = detail::triangle(V, F, f).exponent; });
    std::vector<int> largest(static_cast<std::size_t>(V.rows()), std::numeric_limits<int>::min());
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int c = 0; c < 3; ++c) largest[F(f, c)] = std::max(largest[F(f, c)], face_exponent[f]);
    N = detail::accumulate_at_vertices<3>(F, V.rows(), [&](Eigen::Index f, double (*out)[3]) {
      const detail::Triangle t = detail::triangle(V, F, f);
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) out[c][k] = std::ldexp(t.cross[k], 2 * (t.exponent - largest[F(f, c)]));
    });
  } else {
    N = detail::accumulate_at_vertices<3>(F, V.rows(), [&](Eigen::Index f, double (*out)[3]) {
      const detail::Triangle t = detail::triangle(V, F, f);
      // Each corner receives weight · unit normal. Degenerate faces contribute nothing.
      double weights[3] = {0.0, 0.0, 0.0};
      Eigen::Vector3d direction = Eigen::Vector3d::Zero();
      if (!t.degenerate) {
        direction = t.cross / t.double_area;
        if (weighting == NormalWeighting::angle) {
          detail::triangle_angles(t, weights);
        } else {
          weights[0] = weights[1] = weights[2] = 1.0;
        }
      }
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) out[c][k] = weights[c] * direction[k];
    });
  }
  detail::parallel_for(V.rows(), [&](Eigen::Index v) {
    const double norm = N.row(v).norm();
    if (norm > 0.0) N.row(v) /= norm;
  });
  return N;
}

}  // namespace meshsmith::geometry
