#include <meshsmith/geometry/curvature.h>

#include <meshsmith/geometry/normals.h>

#include "triangle_corners.h"

#include <meshsmith/core/normalization.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace meshsmith::geometry {

namespace {

detail::CornerAreaRule area_rule(MassMatrixType type) {
  return type == MassMatrixType::barycentric ? detail::CornerAreaRule::barycentric
                                             : detail::CornerAreaRule::mixed_voronoi;
}

// true for vertices on an edge that only one face uses (counted over the corners around v).
std::vector<char> boundary_vertices(const FaceRef& F, const detail::VertexCorners& corners) {
  const Eigen::Index n = static_cast<Eigen::Index>(corners.offsets.size()) - 1;
  std::vector<char> boundary(n, 0);
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 1024),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    std::vector<int> neighbours;
    for (Eigen::Index v = range.begin(); v != range.end(); ++v) {
      neighbours.clear();
      for (auto k = corners.begin(v); k < corners.end(v); ++k) {
        const int f = corners.corners[k] / 3, c = corners.corners[k] % 3;
        neighbours.push_back(F(f, (c + 1) % 3));
        neighbours.push_back(F(f, (c + 2) % 3));
      }
      std::sort(neighbours.begin(), neighbours.end());
      for (std::size_t i = 0; i < neighbours.size();) {
        std::size_t j = i;
        while (j < neighbours.size() && neighbours[j] == neighbours[i]) ++j;
        if (j - i == 1 && neighbours[i] != v) {
          boundary[v] = 1;
          break;
        }
        i = j;
      }
    }
  });
  return boundary;
}

Eigen::VectorXd angle_defects(const VertexRef& V, const FaceRef& F, const GaussianCurvatureOptions& options) {
  // Per vertex: (Σθ, area) in one pass over the faces.
  const auto rule = area_rule(options.area);
  const bool with_area = options.pointwise;
  const detail::VertexSums<2> sums =
      detail::accumulate_at_vertices<2>(F, V.rows(), [&](Eigen::Index f, double (*out)[2]) {
        const detail::Triangle t = detail::triangle(V, F, f);
        double angles[3], areas[3] = {0.0, 0.0, 0.0};
        detail::triangle_angles(t, angles);
        if (with_area) detail::triangle_corner_areas(t, rule, areas);
        for (int c = 0; c < 3; ++c) {
          out[c][0] = angles[c];
          out[c][1] = areas[c];
        }
      });
  Eigen::VectorXd K = Eigen::VectorXd::Constant(V.rows(), 2.0 * M_PI) - sums.col(0);
  if (options.boundary == BoundaryAngle::half_turn) {
    const std::vector<char> boundary = boundary_vertices(F, detail::vertex_corners(F, V.rows()));
    for (Eigen::Index v = 0; v < V.rows(); ++v) {
      if (boundary[v]) K[v] -= M_PI;
    }
  }
  if (options.pointwise) {
    for (Eigen::Index v = 0; v < V.rows(); ++v) K[v] = sums(v, 1) > 0.0 ? K[v] / sums(v, 1) : 0.0;
  }
  return K;
}

MeanCurvature mean_curvature_of(const VertexRef& V, const FaceRef& F, MassMatrixType area) {
  // Per vertex: (½ L V, area) in one pass over the faces. Edge (c, next) of a face carries
  // ½ cot of the angle at prev, so corner c receives ½ cot_prev (p_next − p_c) + ½ cot_next (p_prev − p_c).
  const auto rule = area_rule(area);
  const detail::VertexSums<4> sums =
      detail::accumulate_at_vertices<4>(F, V.rows(), [&](Eigen::Index f, double (*out)[4]) {
        const detail::Triangle t = detail::triangle(V, F, f);
        double areas[3];
        detail::triangle_corner_areas(t, rule, areas);
        for (int c = 0; c < 3; ++c) {
          const int next = (c + 1) % 3, prev = (c + 2) % 3;
          Eigen::Vector3d half_laplacian = Eigen::Vector3d::Zero();
          if (!t.degenerate) {
            half_laplacian = (0.25 / t.double_area) *
                             (t.dot[prev] * (t.p[next] - t.p[c]) + t.dot[next] * (t.p[prev] - t.p[c]));
          }
          out[c][0] = half_laplacian[0];
          out[c][1] = half_laplacian[1];
          out[c][2] = half_laplacian[2];
          out[c][3] = areas[c];
        }
      });
  const VertexMatrix normals = vertex_normals(V, F, NormalWeighting::angle);
  MeanCurvature result;
  result.H.resize(V.rows());
  result.Hn.resize(V.rows(), 3);
  detail::parallel_for(V.rows(), [&](Eigen::Index v) {
    const double vertex_area = sums(v, 3);
    if (!(vertex_area > 0.0)) {
      result.H[v] = 0.0;
      result.Hn.row(v).setZero();
      return;
    }
    result.Hn.row(v) = -sums.row(v).head<3>() / vertex_area;
    const double magnitude = result.Hn.row(v).norm();
    result.H[v] = result.Hn.row(v).dot(normals.row(v)) < 0.0 ? -magnitude : magnitude;
  });
  return result;
}

// An orthonormal tangent frame (u, w) of the unit normal n, with u × w = n.
void tangent_frame(const Eigen::Vector3d& n, Eigen::Vector3d& u, Eigen::Vector3d& w) {
  Eigen::Index axis;
  n.cwiseAbs().minCoeff(&axis);
  u = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
  w = n.cross(u);
}

// Rotates the tangent vector x of a plane with unit normal `from` by the smallest rotation
// that takes `from` to `to` (x ⟂ from).
Eigen::Vector3d rotate_tangent(const Eigen::Vector3d& x, const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const double cosine = from.dot(to);
  if (cosine <= -1.0 + 1e-12) return -x;
  const Eigen::Vector3d perpendicular = to - cosine * from;
  return x - (from + to) * (perpendicular.dot(x) / (1.0 + cosine));
}

// Principal curvatures from a least-squares height function z = a x² + b xy + c y² + d x + e y
// fitted, in the tangent frame (u, w, n) of vertex v, to the vertices of its 2-ring.
void quadric_fit_curvatures(const VertexRef& V, const FaceRef& F, const detail::VertexCorners& corners,
                            const VertexMatrix& normals, PrincipalCurvatures& result) {
  const Eigen::Index n = V.rows();
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 512),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    std::vector<int> ring, frontier, next_frontier;
    for (Eigen::Index v = range.begin(); v != range.end(); ++v) {
      result.k1[v] = result.k2[v] = 0.0;
      result.d1.row(v).setZero();
      result.d2.row(v).setZero();
      const Eigen::Vector3d normal = normals.row(v).transpose();
      if (normal.squaredNorm() == 0.0) continue;
      // Breadth-first neighbourhood: the 2-ring, grown to at most 4 rings until it holds at least
      // 8 neighbours (a 1-ring of 5 would interpolate the 5 coefficients, averaging nothing).
      ring.assign(1, static_cast<int>(v));
      frontier.assign(1, static_cast<int>(v));
      for (int depth = 0; depth < 4 && (depth < 2 || ring.size() < 9) && !frontier.empty(); ++depth) {
        next_frontier.clear();
        for (const int x : frontier) {
          for (auto k = corners.begin(x); k < corners.end(x); ++k) {
            const int f = corners.corners[k] / 3, c = corners.corners[k] % 3;
            for (const int y : {F(f, (c + 1) % 3), F(f, (c + 2) % 3)}) {
              if (std::find(ring.begin(), ring.end(), y) == ring.end()) {
                ring.push_back(y);
                next_frontier.push_back(y);
              }
            }
          }
        }
        frontier.swap(next_frontier);
      }
      if (ring.size() < 6) continue;  // fewer than 5 neighbours: the quadric is undetermined
      Eigen::Vector3d u, w;
      tangent_frame(normal, u, w);
      const Eigen::Vector3d p = V.row(v).transpose();
      Eigen::Matrix<double, 5, 5> normal_matrix = Eigen::Matrix<double, 5, 5>::Zero();
      Eigen::Matrix<double, 5, 1> rhs = Eigen::Matrix<double, 5, 1>::Zero();
      double scale = 0.0;
      for (std::size_t i = 1; i < ring.size(); ++i) scale += (V.row(ring[i]).transpose() - p).norm();
      scale /= static_cast<double>(ring.size() - 1);
      if (!(scale > 0.0)) continue;
      for (std::size_t i = 1; i < ring.size(); ++i) {
        const Eigen::Vector3d d = (V.row(ring[i]).transpose() - p) / scale;  // unit-free
        const double x = d.dot(u), y = d.dot(w), z = d.dot(normal);
        const Eigen::Matrix<double, 5, 1> row(x * x, x * y, y * y, x, y);
        normal_matrix += row * row.transpose();
        rhs += row * z;
      }
      const Eigen::Matrix<double, 5, 1> q = normal_matrix.ldlt().solve(rhs);
      if (!q.allFinite()) continue;
      // Graph (x, y, z(x, y)): first form I = [[1+d², de], [de, 1+e²]]; second form with
      // respect to the unit normal on n's side, negated so that a surface bending away from
      // n (a sphere seen from outside) has positive curvature: II = −Hessian / sqrt(1+d²+e²).
      const double gx = q[3], gy = q[4];
      const double root = std::sqrt(1.0 + gx * gx + gy * gy);
      Eigen::Matrix2d first, second;
      first << 1.0 + gx * gx, gx * gy, gx * gy, 1.0 + gy * gy;
      second << -2.0 * q[0] / root, -q[1] / root, -q[1] / root, -2.0 * q[2] / root;
      Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> eigen(second, first);
      if (eigen.info() != Eigen::Success) continue;
      result.k1[v] = eigen.eigenvalues()[1] / scale;
      result.k2[v] = eigen.eigenvalues()[0] / scale;
      const Eigen::Vector2d along = eigen.eigenvectors().col(1);
      Eigen::Vector3d direction = along[0] * (u + gx * normal) + along[1] * (w + gy * normal);
      direction -= direction.dot(normal) * normal;  // tangent to the vertex normal
      direction.normalize();
      result.d1.row(v) = direction.transpose();
      result.d2.row(v) = normal.cross(direction).transpose();
    }
  });
}

}  // namespace

Eigen::VectorXd gaussian_curvature(const VertexRef& V, const FaceRef& F,
                                   const GaussianCurvatureOptions& options) {
  detail::validate_surface(V, F);
  return angle_defects(V, F, options);
}

MeanCurvature mean_curvature(const VertexRef& V, const FaceRef& F, MassMatrixType area) {
  detail::validate_surface(V, F);
  // Coordinates beyond 2^±200: on normalized coordinates (the vertex areas of a 1e-300 mesh
  // underflow to 0 in input units), H and Hn mapped back as length^-1.
  const CoordinateFrame frame = normalizing_frame(V);
  if (std::abs(frame.exponent) <= 200) return mean_curvature_of(V, F, area);
  MeanCurvature result = mean_curvature_of(frame.normalize_vertices(V), F, area);
  frame.to_input(result.H.data(), result.H.size(), -1, "mean_curvature: H at vertex");
  frame.to_input(result.Hn.data(), result.Hn.size(), -1, "mean_curvature: Hn entry");
  return result;
}

PrincipalCurvatures principal_curvatures(const VertexRef& input_V, const FaceRef& F,
                                         PrincipalCurvatureMethod method) {
  detail::validate_surface(input_V, F);
  // Coordinates beyond 2^±200: on normalized coordinates (core/normalization.h; the fitted
  // tensors are products of up to four coordinates), curvatures mapped back as length^-1.
  const CoordinateFrame frame = normalizing_frame(input_V);
  const bool rescale = std::abs(frame.exponent) > 200;
  const VertexMatrix normalized = rescale ? frame.normalize_vertices(input_V) : VertexMatrix();
  const VertexRef V = rescale ? VertexRef(normalized) : input_V;
  const Eigen::Index n = V.rows(), m = F.rows();
  const detail::VertexCorners corners = detail::vertex_corners(F, n);
  const VertexMatrix normals = vertex_normals(V, F, NormalWeighting::angle);
  VertexMatrix frame_u(n, 3), frame_w(n, 3);
  detail::parallel_for(n, [&](Eigen::Index v) {
    Eigen::Vector3d u = Eigen::Vector3d::Zero(), w = Eigen::Vector3d::Zero();
    if (normals.row(v).squaredNorm() > 0.0) tangent_frame(normals.row(v).transpose(), u, w);
    frame_u.row(v) = u.transpose();
    frame_w.row(v) = w.transpose();
  });
  if (method == PrincipalCurvatureMethod::quadric_fit) {
    PrincipalCurvatures fitted;
    fitted.k1.resize(n);
    fitted.k2.resize(n);
    fitted.d1.resize(n, 3);
    fitted.d2.resize(n, 3);
    quadric_fit_curvatures(V, F, corners, normals, fitted);
    if (rescale) {
      frame.to_input(fitted.k1.data(), fitted.k1.size(), -1, "principal_curvatures: k1 at vertex");
      frame.to_input(fitted.k2.data(), fitted.k2.size(), -1, "principal_curvatures: k2 at vertex");
    }
    return fitted;
  }
  const detail::CornerMatrix weights = detail::corner_areas(V, F, detail::CornerAreaRule::mixed_voronoi);

  // Per face: the second fundamental form [[e, f], [f, g]] in the face frame (t, b) that best
  // explains the change of vertex normals along the three edges, II·(edge·t, edge·b) =
  // (Δn·t, Δn·b) in the least-squares sense; then expressed in each corner's vertex frame,
  // weighted by the corner's mixed Voronoi area. Stored per corner as (uu, uw, ww, weight);
  // degenerate faces and vertices without a normal store zeros.
  Eigen::Matrix<double, Eigen::Dynamic, 12, Eigen::RowMajor> corner_tensors(m, 12);
  detail::parallel_for(m, [&](Eigen::Index f) {
    const detail::Triangle tri = detail::triangle(V, F, f);
    corner_tensors.row(f).setZero();
    if (tri.degenerate) return;
    const Eigen::Vector3d face_normal = tri.cross / tri.double_area;
    const Eigen::Vector3d t = (tri.p[2] - tri.p[1]).normalized();
    const Eigen::Vector3d b = face_normal.cross(t);
    Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) {
      const int from = (c + 1) % 3, to = (c + 2) % 3;  // the edge opposite corner c
      const Eigen::Vector3d edge = tri.p[to] - tri.p[from];
      const Eigen::Vector3d dn = (normals.row(F(f, to)) - normals.row(F(f, from))).transpose();
      const double et = edge.dot(t), eb = edge.dot(b);
      const double dnt = dn.dot(t), dnb = dn.dot(b);
      // rows (et, eb, 0)·(e, f, g) = dnt and (0, et, eb)·(e, f, g) = dnb
      Eigen::Vector3d r1(et, eb, 0.0), r2(0.0, et, eb);
      normal_matrix += r1 * r1.transpose() + r2 * r2.transpose();
      rhs += r1 * dnt + r2 * dnb;
    }
    const Eigen::Vector3d efg = normal_matrix.ldlt().solve(rhs);
    if (!efg.allFinite()) return;
    const Eigen::Matrix2d second_form = (Eigen::Matrix2d() << efg[0], efg[1], efg[1], efg[2]).finished();
    for (int c = 0; c < 3; ++c) {
      const int v = F(f, c);
      const Eigen::Vector3d vertex_normal = normals.row(v).transpose();
      if (vertex_normal.squaredNorm() == 0.0) continue;
      const Eigen::Vector3d u = rotate_tangent(frame_u.row(v).transpose(), vertex_normal, face_normal);
      const Eigen::Vector3d w = rotate_tangent(frame_w.row(v).transpose(), vertex_normal, face_normal);
      const Eigen::Vector2d u2(u.dot(t), u.dot(b)), w2(w.dot(t), w.dot(b));
      const double weight = weights(f, c);
      corner_tensors(f, 4 * c + 0) = weight * u2.dot(second_form * u2);
      corner_tensors(f, 4 * c + 1) = weight * u2.dot(second_form * w2);
      corner_tensors(f, 4 * c + 2) = weight * w2.dot(second_form * w2);
      corner_tensors(f, 4 * c + 3) = weight;
    }
  });

  PrincipalCurvatures result;
  result.k1.resize(n);
  result.k2.resize(n);
  result.d1.resize(n, 3);
  result.d2.resize(n, 3);
  detail::parallel_for(n, [&](Eigen::Index v) {
    double uu = 0.0, uw = 0.0, ww = 0.0, total = 0.0;
    for (auto k = corners.begin(v); k < corners.end(v); ++k) {
      const int f = corners.corners[k] / 3, c = corners.corners[k] % 3;
      uu += corner_tensors(f, 4 * c);
      uw += corner_tensors(f, 4 * c + 1);
      ww += corner_tensors(f, 4 * c + 2);
      total += corner_tensors(f, 4 * c + 3);
    }
    if (!(total > 0.0) || normals.row(v).squaredNorm() == 0.0) {
      result.k1[v] = result.k2[v] = 0.0;
      result.d1.row(v).setZero();
      result.d2.row(v).setZero();
      return;
    }
    uu /= total, uw /= total, ww /= total;
    const double mean = 0.5 * (uu + ww);
    const double radius = std::hypot(0.5 * (uu - ww), uw);
    result.k1[v] = mean + radius;
    result.k2[v] = mean - radius;
    const double phi = 0.5 * std::atan2(2.0 * uw, uu - ww);
    result.d1.row(v) = std::cos(phi) * frame_u.row(v) + std::sin(phi) * frame_w.row(v);
    result.d2.row(v) = normals.row(v).cross(result.d1.row(v));
  });

  if (method == PrincipalCurvatureMethod::mean_gaussian) {
    GaussianCurvatureOptions pointwise;
    pointwise.pointwise = true;
    const Eigen::VectorXd K = angle_defects(V, F, pointwise);
    const MeanCurvature mean = mean_curvature_of(V, F, MassMatrixType::voronoi);
    for (Eigen::Index v = 0; v < n; ++v) {
      const double spread = std::sqrt(std::max(mean.H[v] * mean.H[v] - K[v], 0.0));
      result.k1[v] = mean.H[v] + spread;
      result.k2[v] = mean.H[v] - spread;
    }
  }
  if (rescale) {
    frame.to_input(result.k1.data(), result.k1.size(), -1, "principal_curvatures: k1 at vertex");
    frame.to_input(result.k2.data(), result.k2.size(), -1, "principal_curvatures: k2 at vertex");
  }
  return result;
}

}  // namespace meshsmith::geometry
