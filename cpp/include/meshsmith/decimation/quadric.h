#pragma once
/// \file quadric.h
/// Error quadrics (§4.1.1, §4.2.1; Garland & Heckbert 1997): the summed squared distance of a
/// point x to a set of planes, Q(x) = xᵀAx + 2bᵀx + c. Shared by vertex clustering (the
/// "quadric" representative) and incremental QEM decimation, so both place points the same way.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace meshsmith::decimation {

/// A symmetric quadric stored as its 10 distinct coefficients. Plain data: adding two quadrics
/// sums the plane sets they stand for.
struct Quadric {
  // A = [[a00 a01 a02] [a01 a11 a12] [a02 a12 a22]], b = (b0 b1 b2), c.
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0, b0 = 0, b1 = 0, b2 = 0, c = 0;

  /// The quadric of the plane through `point` with unit normal `normal`, scaled by `weight`
  /// (typically the triangle's area, so big triangles count more).
  static Quadric from_plane(const Eigen::Vector3d& normal, const Eigen::Vector3d& point, double weight = 1.0) {
    const double d = -normal.dot(point);
    Quadric q;
    q.a00 = weight * normal.x() * normal.x();
    q.a01 = weight * normal.x() * normal.y();
    q.a02 = weight * normal.x() * normal.z();
    q.a11 = weight * normal.y() * normal.y();
    q.a12 = weight * normal.y() * normal.z();
    q.a22 = weight * normal.z() * normal.z();
    q.b0 = weight * d * normal.x();
    q.b1 = weight * d * normal.y();
    q.b2 = weight * d * normal.z();
    q.c = weight * d * d;
    return q;
  }

  Quadric& operator+=(const Quadric& o) {
    a00 += o.a00; a01 += o.a01; a02 += o.a02; a11 += o.a11; a12 += o.a12; a22 += o.a22;
    b0 += o.b0; b1 += o.b1; b2 += o.b2; c += o.c;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }
  Quadric& operator*=(double s) {
    a00 *= s; a01 *= s; a02 *= s; a11 *= s; a12 *= s; a22 *= s; b0 *= s; b1 *= s; b2 *= s; c *= s;
    return *this;
  }

  Eigen::Matrix3d A() const {
    Eigen::Matrix3d m;
    m << a00, a01, a02, a01, a11, a12, a02, a12, a22;
    return m;
  }
  Eigen::Vector3d b() const { return {b0, b1, b2}; }

  /// Q(x) = xᵀAx + 2bᵀx + c: the (weighted) sum of squared plane distances. Clamped at 0 against
  /// round-off.
  double error(const Eigen::Vector3d& x) const {
    const double x0 = x.x(), x1 = x.y(), x2 = x.z();
    const double quadratic = a00 * x0 * x0 + a11 * x1 * x1 + a22 * x2 * x2 +
                             2.0 * (a01 * x0 * x1 + a02 * x0 * x2 + a12 * x1 * x2);
    const double value = quadratic + 2.0 * (b0 * x0 + b1 * x1 + b2 * x2) + c;
    return std::max(value, 0.0);
  }

  /// The minimiser of Q closest to `reference`: x = reference + A⁺(−b − A·reference), with A⁺ the
  /// pseudo-inverse that drops eigenvalues below `relative_tolerance`·λ_max (§4.1.1). When A is
  /// rank-deficient (all planes parallel: a flat region, or along a straight crease) the point
  /// stays at the reference along the unconstrained directions instead of flying off, so this is
  /// stable for every quadric; with A = 0 it returns `reference`.
  Eigen::Vector3d minimizer(const Eigen::Vector3d& reference, double relative_tolerance = 1e-3) const {
    const Eigen::Matrix3d a = A();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(a);
    const Eigen::Vector3d lambda = eigen.eigenvalues();
    const double lambda_max = std::max(std::abs(lambda(0)), std::abs(lambda(2)));
    if (!(lambda_max > 0.0) || !std::isfinite(lambda_max)) return reference;
    const Eigen::Matrix3d& U = eigen.eigenvectors();
    const Eigen::Vector3d residual = U.transpose() * (-b() - a * reference);
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    for (int i = 0; i < 3; ++i)
      if (lambda(i) > relative_tolerance * lambda_max) step += U.col(i) * (residual(i) / lambda(i));
    return reference + step;
  }
};

}  // namespace meshsmith::decimation
