#include <meshsmith/geometry/laplacian.h>

#include <meshsmith/core/errors.h>

#include "triangle_corners.h"

#include <sstream>

namespace meshsmith::geometry {

Eigen::SparseMatrix<double> cotan_laplacian(const VertexRef& V, const FaceRef& F) {
  detail::validate_surface(V, F);
  // The edge opposite corner c gets ½ cot of the angle at c, in both directions.
  detail::CornerMatrix half_cotangents(F.rows(), 3);
  detail::parallel_for(F.rows(), [&](Eigen::Index f) {
    const detail::Triangle t = detail::triangle(V, F, f);
    for (int c = 0; c < 3; ++c) half_cotangents(f, c) = t.degenerate ? 0.0 : 0.5 * t.dot[c] / t.double_area;
  });
  detail::LaplacianWeights weights;
  weights.symmetric = &half_cotangents;
  return detail::assemble_laplacian(F, detail::vertex_corners(F, V.rows()), weights);
}

Eigen::SparseMatrix<double> uniform_laplacian(const FaceRef& F, Eigen::Index n, bool normalized) {
  if (F.rows() == 0) throw InputError("F is empty: expected at least one triangle");
  if (n < 1) throw InputError("n = " + std::to_string(n) + ": expected at least one vertex");
  if (6.0 * static_cast<double>(F.rows()) + static_cast<double>(n) >= 2147483647.0) {
    throw InputError("mesh too large for 32-bit sparse matrix indices");
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (F(f, c) < 0 || F(f, c) >= n) {
        std::ostringstream message;
        message << "F[" << f << "] = (" << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2)
                << ") indexes vertex " << F(f, c) << ", outside [0, " << n << ")";
        throw InputError(message.str());
      }
    }
  }
  Eigen::SparseMatrix<double> L = detail::assemble_laplacian(F, detail::vertex_corners(F, n), {});
  if (normalized) {
    // The pattern is symmetric, so the degree of vertex i is the entry count of column i − 1.
    Eigen::VectorXd inverse_degree(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const int degree = L.outerIndexPtr()[i + 1] - L.outerIndexPtr()[i] - 1;
      inverse_degree[i] = degree > 0 ? 1.0 / degree : 0.0;
    }
    const int* inner = L.innerIndexPtr();
    double* values = L.valuePtr();
    detail::parallel_for(n, [&](Eigen::Index j) {
      for (int k = L.outerIndexPtr()[j]; k < L.outerIndexPtr()[j + 1]; ++k) values[k] *= inverse_degree[inner[k]];
    });
  }
  return L;
}

Eigen::SparseMatrix<double> mean_value_laplacian(const VertexRef& V, const FaceRef& F) {
  detail::validate_surface(V, F);
  // Corner c weighs its two neighbours in this face by tan(θ_c/2) / |edge|, with
  // tan(θ/2) = |u × v| / (|u||v| + u·v) for the edge vectors u, v leaving the corner.
  detail::DirectedWeights W(F.rows(), 6);
  detail::parallel_for(F.rows(), [&](Eigen::Index f) {
    const detail::Triangle t = detail::triangle(V, F, f);
    for (int c = 0; c < 3; ++c) {
      const int next = (c + 1) % 3, prev = (c + 2) % 3;
      const double to_next = std::sqrt(t.squared_edge[prev]);  // edge (c, next) is opposite prev
      const double to_prev = std::sqrt(t.squared_edge[next]);
      const double denominator = to_next * to_prev + t.dot[c];
      if (t.degenerate || !(denominator > 0.0)) {
        W(f, 2 * c) = W(f, 2 * c + 1) = 0.0;
        continue;
      }
      const double half_angle_tangent = t.double_area / denominator;
      // Lengths in input units: 2^exponent times the scaled ones.
      W(f, 2 * c) = std::ldexp(half_angle_tangent / to_next, -t.exponent);
      W(f, 2 * c + 1) = std::ldexp(half_angle_tangent / to_prev, -t.exponent);
    }
  });
  detail::LaplacianWeights weights;
  weights.directed = &W;
  return detail::assemble_laplacian(F, detail::vertex_corners(F, V.rows()), weights);
}

Eigen::VectorXd vertex_areas(const VertexRef& V, const FaceRef& F, MassMatrixType type) {
  detail::validate_surface(V, F);
  const auto rule = type == MassMatrixType::barycentric ? detail::CornerAreaRule::barycentric
                                                        : detail::CornerAreaRule::mixed_voronoi;
  Eigen::VectorXd areas = detail::accumulate_at_vertices<1>(F, V.rows(), [&](Eigen::Index f, double (*out)[1]) {
    double corner[3];
    detail::triangle_corner_areas(detail::triangle(V, F, f), rule, corner);
    for (int c = 0; c < 3; ++c) out[c][0] = corner[c];
  });
  for (Eigen::Index v = 0; v < areas.size(); ++v)
    if (!std::isfinite(areas[v]))
      throw InputError("vertex_areas: the area of vertex " + std::to_string(v) +
                       " exceeds the double range (about 1.8e308): its faces are too large; scale the mesh down");
  return areas;
}

Eigen::SparseMatrix<double> mass_matrix(const VertexRef& V, const FaceRef& F, MassMatrixType type) {
  const Eigen::VectorXd areas = vertex_areas(V, F, type);
  const Eigen::Index n = areas.size();
  Eigen::SparseMatrix<double> M(n, n);
  M.resizeNonZeros(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    M.outerIndexPtr()[i] = static_cast<int>(i);
    M.innerIndexPtr()[i] = static_cast<int>(i);
    M.valuePtr()[i] = areas[i];
  }
  M.outerIndexPtr()[n] = static_cast<int>(n);
  return M;
}

}  // namespace meshsmith::geometry
