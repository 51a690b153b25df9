#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/geometry/distortion.h>

#include <Eigen/Geometry>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <string>

namespace meshsmith::geometry {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

void validate_parameters(const VertexRef& V, const ParameterRef& UV) {
  if (UV.rows() != V.rows()) {
    throw InputError("UV has " + std::to_string(UV.rows()) + " rows but V has " + std::to_string(V.rows()) +
                     ": expected one parameter position per vertex");
  }
  for (Eigen::Index i = 0; i < UV.rows(); ++i)
    for (Eigen::Index c = 0; c < 2; ++c)
      if (!std::isfinite(UV(i, c)))
        throw InputError("UV[" + std::to_string(i) + ", " + std::to_string(c) + "] is not finite");
}

/// Singular values σ1 ≥ σ2 ≥ 0 of the 2×2 matrix [[a, b], [c, d]] in closed form: J is the sum
/// of a similarity (E, H) and an anti-similarity (F, G), σ = |(E, H)| ± |(F, G)|. σ2 comes from
/// |det J| / σ1, which keeps its relative accuracy when J is nearly singular.
Eigen::Vector2d singular_values_2x2(double a, double b, double c, double d) {
  const double similarity = std::hypot(0.5 * (a + d), 0.5 * (c - b));
  const double anti_similarity = std::hypot(0.5 * (a - d), 0.5 * (c + b));
  const double sigma1 = similarity + anti_similarity;
  const double sigma2 = sigma1 > 0.0 ? std::abs(a * d - b * c) / sigma1 : 0.0;
  return {sigma1, std::min(sigma2, sigma1)};
}

/// v times the power of two that brings its largest |component| into [0.5, 1) (exact): the cross
/// product of a thin triangle's edges (1 and 2^-997 long in the triangle's frame) has normal
/// components whose squares underflow.
Eigen::Vector3d scaled_to_unit(const Eigen::Vector3d& v, int* exponent = nullptr) {
  int e = 0;
  const double largest = v.cwiseAbs().maxCoeff();
  if (largest > 0.0) std::frexp(largest, &e);
  if (exponent) *exponent = e;
  return Eigen::Vector3d(std::ldexp(v[0], -e), std::ldexp(v[1], -e), std::ldexp(v[2], -e));
}

/// The 3D triangle's edges e1 = v1 − v0, e2 = v2 − v0 in an orthonormal frame of its plane
/// (columns of the returned matrix). Counter-clockwise (det > 0) for a non-degenerate triangle.
Eigen::Matrix2d edges_in_triangle_frame(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  const Eigen::Vector3d e3 = e2 - e1;
  Eigen::Vector3d x = e1;
  if (x.squaredNorm() == 0.0) x = e2;
  if (x.squaredNorm() == 0.0) return Eigen::Matrix2d::Zero();  // all corners coincide
  Eigen::Vector3d normal = scaled_to_unit(e1.cross(e2));  // a thin face's squared norm underflows
  if (normal.squaredNorm() == 0.0) {
    // Collinear corners: x along the longest edge; y is then orthogonal to every edge.
    if (e2.squaredNorm() > x.squaredNorm()) x = e2;
    if (e3.squaredNorm() > x.squaredNorm()) x = e3;
    x.normalize();
    Eigen::Vector3d y = x.unitOrthogonal();
    Eigen::Matrix2d D;
    D << e1.dot(x), e2.dot(x), e1.dot(y), e2.dot(y);
    return D;
  }
  x.normalize();
  const Eigen::Vector3d y = normal.normalized().cross(x);
  Eigen::Matrix2d D;
  D << e1.dot(x), e2.dot(x), e1.dot(y), e2.dot(y);
  return D;
}

/// Area-weighted per-vertex average of a per-face measure (NaN where the total weight is 0).
/// Face f weighs weights[f] · 2^exponents[f] (its area in its own frame, core/normalization.h's
/// triangle_edge_vectors): each vertex sums its faces relative to the largest of them, so the small
/// faces around a vertex keep their weights when another vertex of the mesh is at 1e300.
Eigen::VectorXd vertex_average(const FaceRef& F, Eigen::Index n_vertices, const Eigen::VectorXd& weights,
                               const Eigen::VectorXi& exponents, const Eigen::VectorXd& measure) {
  Eigen::VectorXi largest = Eigen::VectorXi::Constant(n_vertices, std::numeric_limits<int>::min());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (weights[f] > 0.0)
      for (int k = 0; k < 3; ++k) largest[F(f, k)] = std::max(largest[F(f, k)], exponents[f]);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n_vertices), total = Eigen::VectorXd::Zero(n_vertices);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!(weights[f] > 0.0)) continue;
    for (int k = 0; k < 3; ++k) {
      const double weight = std::ldexp(weights[f], exponents[f] - largest[F(f, k)]);
      sum[F(f, k)] += weight * measure[f];
      total[F(f, k)] += weight;
    }
  }
  Eigen::VectorXd average(n_vertices);
  for (Eigen::Index i = 0; i < n_vertices; ++i)
    average[i] = total[i] > 0.0 ? sum[i] / total[i] : std::numeric_limits<double>::quiet_NaN();
  return average;
}

}  // namespace

TriangleDistortion triangle_distortion(const VertexRef& input_V, const FaceRef& F, const ParameterRef& input_UV) {
  validate_mesh(input_V, F);
  validate_parameters(input_V, input_UV);
  // The parameter domain on normalized coordinates and each surface triangle in its own frame
  // (core/normalization.h): areas and determinants are products of two coordinates, which under-
  // or overflow from 1e±154, and one frame for the whole surface would flush the small faces next
  // to a vertex at 1e150 to zero area (NaN per-vertex figures). The Jacobian maps parameter
  // lengths to surface lengths, so it and the stretches scale by 2^(face exponent − parameter
  // exponent); areas by 4^exponent of their own frame. The global figures use the whole
  // surface's frame (surface_frame), where such small faces weigh (next to) nothing.
  const CoordinateFrame surface_frame = normalizing_frame(input_V);
  const CoordinateFrame parameter_frame = normalizing_frame(input_UV);
  const ParameterMatrix UV = parameter_frame.normalize(input_UV);
  const int jacobian_exponent = surface_frame.exponent - parameter_frame.exponent;
  Eigen::VectorXd own_areas(F.rows());          // each face's area in its own frame
  Eigen::VectorXi own_area_exponents(F.rows());  // that frame's area exponent: 2 · face exponent
  const Eigen::Index m = F.rows();
  TriangleDistortion out;
  out.jacobians.resize(m, 4);
  out.singular_values.resize(m, 2);
  out.isometric.resize(m);
  out.conformal.resize(m);
  out.area.resize(m);
  out.stretch_l2.resize(m);
  out.stretch_linf.resize(m);
  out.flipped.resize(m);
  out.surface_areas.resize(m);
  out.parameter_areas.resize(m);

  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, m, 4096), [&](const tbb::blocked_range<Eigen::Index>& range) {
    for (Eigen::Index f = range.begin(); f < range.end(); ++f) {
      Eigen::Vector3d e1, e2;
      const CoordinateFrame face = triangle_edge_vectors(input_V.row(F(f, 0)).data(), input_V.row(F(f, 1)).data(),
                                                         input_V.row(F(f, 2)).data(), e1, e2);
      const int face_jacobian_exponent = face.exponent - parameter_frame.exponent;
      const auto to_jacobian_units = [&](double x) { return std::ldexp(x, face_jacobian_exponent); };
      const Eigen::Vector2d q0 = UV.row(F(f, 0)).transpose();
      Eigen::Matrix2d parameter_edges;
      parameter_edges.col(0) = UV.row(F(f, 1)).transpose() - q0;
      parameter_edges.col(1) = UV.row(F(f, 2)).transpose() - q0;
      const double parameter_det = parameter_edges.determinant();
      int normal_exponent = 0;
      const Eigen::Vector3d unit_normal = scaled_to_unit(e1.cross(e2), &normal_exponent);
      const double surface_area = std::ldexp(0.5 * unit_normal.norm(), normal_exponent);  // in the face's frame
      own_areas[f] = surface_area;
      own_area_exponents[f] = 2 * face.exponent;
      out.surface_areas[f] = std::ldexp(surface_area, 2 * (face.exponent - surface_frame.exponent));
      out.parameter_areas[f] = 0.5 * parameter_det;
      out.flipped[f] = surface_area > 0.0 && parameter_det < 0.0;

      if (parameter_det == 0.0) {
        // No affine map from a flat UV triangle: infinite distortion (0 for a point-like 3D
        // triangle would be as arbitrary; a zero-area 3D triangle has weight 0 anyway).
        out.jacobians.row(f).setConstant(infinity);
        out.singular_values.row(f).setConstant(infinity);
        out.isometric[f] = out.conformal[f] = out.area[f] = infinity;
        out.stretch_l2[f] = out.stretch_linf[f] = infinity;
        continue;
      }
      // J maps parameter edges onto surface edges: J · parameter_edges = surface_edges.
      const Eigen::Matrix2d J = edges_in_triangle_frame(e1, e2) * parameter_edges.inverse();
      const Eigen::Vector2d sigma = singular_values_2x2(J(0, 0), J(0, 1), J(1, 0), J(1, 1));
      out.jacobians.row(f) << to_jacobian_units(J(0, 0)), to_jacobian_units(J(0, 1)), to_jacobian_units(J(1, 0)),
          to_jacobian_units(J(1, 1));
      const double s1 = to_jacobian_units(sigma[0]), s2 = to_jacobian_units(sigma[1]);
      out.singular_values.row(f) << s1, s2;
      out.conformal[f] = sigma[1] > 0.0 ? sigma[0] / sigma[1] : infinity;
      out.isometric[f] = s2 > 0.0 ? (s1 * s1 + s2 * s2 + 1.0 / (s1 * s1) + 1.0 / (s2 * s2)) / 4.0 : infinity;
      out.area[f] = std::ldexp(sigma[0] * sigma[1], 2 * face_jacobian_exponent);
      out.stretch_l2[f] = to_jacobian_units(std::sqrt((sigma[0] * sigma[0] + sigma[1] * sigma[1]) / 2.0));
      out.stretch_linf[f] = s1;
    }
  });

  // Fixed-order (serial) sums: the result does not depend on the thread count. Weights and
  // stretches in normalized units here; the global figures are mapped back at the end.
  double weighted_stretch = 0.0, total_surface = 0.0, total_parameter = 0.0, max_stretch = 0.0;
  for (Eigen::Index f = 0; f < m; ++f) {
    const double weight = out.surface_areas[f];  // 0 for a small face next to a far vertex: it weighs nothing
    if (own_areas[f] > 0.0) {
      if (out.flipped[f]) out.flipped_faces.push_back(static_cast<int>(f));
      if (out.parameter_areas[f] == 0.0) out.degenerate_parameter_faces.push_back(static_cast<int>(f));
      const double stretch = std::ldexp(out.stretch_l2[f], -jacobian_exponent);
      weighted_stretch += weight * stretch * stretch;
      total_surface += weight;
      total_parameter += std::abs(out.parameter_areas[f]);
      max_stretch = std::max(max_stretch, out.stretch_linf[f]);
    } else {
      out.degenerate_surface_faces.push_back(static_cast<int>(f));
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double global_l2 = total_surface > 0.0 ? std::sqrt(weighted_stretch / total_surface) : nan;
  out.global_stretch_l2 = std::ldexp(global_l2, jacobian_exponent);
  // Scale-invariant: the same in normalized and input units. A map whose UV triangles all have
  // zero area cannot be scaled to the surface's area: its stretch is infinite at every scale
  // (not inf * 0 = NaN).
  const double inf = std::numeric_limits<double>::infinity();
  out.normalized_global_stretch_l2 =
      !(total_surface > 0.0) ? nan
      : total_parameter > 0.0 ? global_l2 * std::sqrt(total_parameter / total_surface) : inf;
  out.global_stretch_linf = total_surface > 0.0 ? max_stretch : nan;

  const Eigen::Index n = input_V.rows();
  out.vertex_isometric = vertex_average(F, n, own_areas, own_area_exponents, out.isometric);
  out.vertex_conformal = vertex_average(F, n, own_areas, own_area_exponents, out.conformal);
  out.vertex_area = vertex_average(F, n, own_areas, own_area_exponents, out.area);
  out.vertex_stretch_l2 = vertex_average(F, n, own_areas, own_area_exponents, out.stretch_l2);
  out.vertex_stretch_linf = vertex_average(F, n, own_areas, own_area_exponents, out.stretch_linf);
  for (Eigen::Index f = 0; f < m; ++f) {  // each face's area from its own frame: the small ones stay
    out.surface_areas[f] = std::ldexp(own_areas[f], own_area_exponents[f]);
    if (!std::isfinite(out.surface_areas[f]))
      throw InputError("triangle_distortion: the surface area of face " + std::to_string(f) +
                       " exceeds the double range (about 1.8e308); scale the mesh down");
  }
  parameter_frame.to_input(out.parameter_areas.data(), out.parameter_areas.size(), 2,
                           "triangle_distortion: the parameter area of face");
  return out;
}

}  // namespace meshsmith::geometry
