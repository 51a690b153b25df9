// Horn's quaternion method for absolute orientation (§2.3.1). The inputs are centred in their own
// power-of-two normalized frames (core/normalization.h), so coordinates anywhere in the double
// range give the same rotation as at scale 1 and the cross-covariance never overflows; the scale
// and translation are mapped back to input units exactly at the end.
#include <meshsmith/registration/align.h>

#include "horn.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <string>

namespace meshsmith::registration {

namespace detail {

Eigen::Matrix3d horn_rotation(const Eigen::Matrix3d& H) {
  const double xx = H(0, 0), xy = H(0, 1), xz = H(0, 2);
  const double yx = H(1, 0), yy = H(1, 1), yz = H(1, 2);
  const double zx = H(2, 0), zy = H(2, 1), zz = H(2, 2);
  Eigen::Matrix4d N;
  N << xx + yy + zz, yz - zy, zx - xz, xy - yx,
       yz - zy, xx - yy - zz, xy + yx, zx + xz,
       zx - xz, xy + yx, -xx + yy - zz, yz + zy,
       xy - yx, zx + xz, yz + zy, -xx - yy + zz;
  // Scale N to unit size first so that the eigen solver's tolerances are relative to it.
  const double size = N.cwiseAbs().maxCoeff();
  if (!(size > 0.0)) return Eigen::Matrix3d::Identity();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> solver(N / size);
  const Eigen::Vector4d q = solver.eigenvectors().col(3);  // eigenvalues ascending: the largest
  return Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
}

Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& omega) {
  const double angle = omega.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
}

}  // namespace detail

namespace {

/// Weighted centroid and centred copy of X (normalized coordinates) with the spread of its
/// covariance; throws if the points are identical or collinear.
struct CentredSet {
  Eigen::Vector3d centroid;
  VertexMatrix centred;
  double spread = 0.0;  // Σ w ‖x − c‖²
};

CentredSet centre(const VertexMatrix& X, const Eigen::VectorXd& w, double total, const char* name) {
  CentredSet set;
  set.centroid = (X.transpose() * w) / total;
  set.centred = X.rowwise() - set.centroid.transpose();
  Eigen::Matrix3d covariance = set.centred.transpose() * w.asDiagonal() * set.centred;
  set.spread = covariance.trace();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d lambda = solver.eigenvalues().cwiseMax(0.0);  // ascending
  if (!(lambda(2) > 0.0))
    throw InputError(std::string("align: the points of ") + name +
                     " (with positive weight) are all identical: the rotation is not determined");
  // Collinear: the second principal extent is below 1e-9 of the first (round-off of a line).
  if (std::sqrt(lambda(1) / lambda(2)) < 1e-9)
    throw InputError(std::string("align: the points of ") + name +
                     " (with positive weight) are collinear: the rotation about their line is not determined");
  return set;
}

}  // namespace

Transform align(const VertexRef& A, const VertexRef& B, const Eigen::Ref<const Eigen::VectorXd>& weights,
                bool with_scale) {
  validate_vertices(A, "A");
  validate_vertices(B, "B");
  const Eigen::Index n = A.rows();
  if (B.rows() != n)
    throw InputError("align: A has " + std::to_string(n) + " points and B " + std::to_string(B.rows()) +
                     ": the rows of A and B must correspond one to one");
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  if (weights.size() != 0) {
    if (weights.size() != n)
      throw InputError("align: weights has " + std::to_string(weights.size()) + " entries for " +
                       std::to_string(n) + " points");
    for (Eigen::Index i = 0; i < n; ++i)
      if (!std::isfinite(weights(i)) || weights(i) < 0.0)
        throw InputError("align: weights[" + std::to_string(i) + "] = " + number_text(weights(i)) +
                         ": expected a finite number >= 0");
    w = weights;
    const double largest = w.maxCoeff();
    if (largest > 0.0) w /= largest;  // the weights' scale does not matter: keep sums in range
  }
  const Eigen::Index positive = (w.array() > 0.0).count();
  if (positive < 3)
    throw InputError("align: " + std::to_string(positive) +
                     " point(s) with positive weight: at least 3 are needed to fix a rotation");
  const double total = w.sum();

  const CoordinateFrame frame_a = normalizing_frame(A), frame_b = normalizing_frame(B);
  const CentredSet a = centre(frame_a.normalize_vertices(A), w, total, "A");
  const CentredSet b = centre(frame_b.normalize_vertices(B), w, total, "B");

  const Eigen::Matrix3d H = a.centred.transpose() * w.asDiagonal() * b.centred;
  const Eigen::Matrix3d R = detail::horn_rotation(H);
  // Scale from the spreads (Horn 1987, the symmetric form: align(B, A) is the inverse of
  // align(A, B)), in normalized units, then in input units (B's lengths over A's).
  double scale = 1.0;
  if (with_scale) {
    const double s = std::sqrt(b.spread / a.spread);
    scale = std::ldexp(s, frame_b.exponent - frame_a.exponent);
    if (!std::isfinite(scale) || scale == 0.0)
      throw InputError("align: the scale from A to B (" + number_text(s) + " × 2^" +
                       std::to_string(frame_b.exponent - frame_a.exponent) + ") leaves the double range");
  }
  const Eigen::Vector3d centroid_a = a.centroid * std::ldexp(1.0, frame_a.exponent);
  const Eigen::Vector3d centroid_b = b.centroid * std::ldexp(1.0, frame_b.exponent);
  Transform T = Transform::Identity();
  T.topLeftCorner<3, 3>() = scale * R;
  T.topRightCorner<3, 1>() = centroid_b - scale * (R * centroid_a);
  if (!T.allFinite()) throw InputError("align: the translation from A to B leaves the double range");
  return T;
}

Transform align(const VertexRef& A, const VertexRef& B, bool with_scale) {
  return align(A, B, Eigen::VectorXd(), with_scale);
}

double rotation_angle(const Transform& T) {
  Eigen::Matrix3d M = T.topLeftCorner<3, 3>();
  const double scale = std::cbrt(M.determinant());
  if (scale > 0.0) M /= scale;
  const double c = std::clamp((M.trace() - 1.0) / 2.0, -1.0, 1.0);
  // acos loses accuracy near 0; use atan2 of the skew part's norm for small angles.
  const Eigen::Vector3d skew(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1));
  return std::atan2(0.5 * skew.norm(), c);
}

}  // namespace meshsmith::registration
