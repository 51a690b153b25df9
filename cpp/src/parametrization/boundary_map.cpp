#include <meshsmith/parametrization/boundary_map.h>

#include <meshsmith/core/errors.h>

#include "input_checks.h"

#include <cmath>
#include <string>

namespace meshsmith::parametrization {

namespace {

constexpr double pi = 3.14159265358979323846;

/// Arc length from loop[0] to loop[i] (entry i), and the total length in entry #b.
std::vector<double> arc_lengths(const VertexRef& V, const std::vector<int>& loop) {
  const std::size_t b = loop.size();
  std::vector<double> length(b + 1, 0.0);
  for (std::size_t i = 1; i <= b; ++i) {
    const double step = (V.row(loop[i % b]) - V.row(loop[i - 1])).norm();
    if (!(step > 0.0)) {
      throw InputError("map_boundary: boundary vertices " + std::to_string(loop[i - 1]) + " and " +
                       std::to_string(loop[i % b]) + " are at the same position");
    }
    length[i] = length[i - 1] + step;
  }
  return length;
}

/// Point at arc-length fraction t ∈ [0, 1] of the segment from corner k to corner k+1 of [0, 1]².
Eigen::RowVector2d on_square_side(int k, double t) {
  static const double corners[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  return {(1 - t) * corners[k][0] + t * corners[k + 1][0], (1 - t) * corners[k][1] + t * corners[k + 1][1]};
}

}  // namespace

BoundaryMap map_boundary_loop(const VertexRef& input_V, const std::vector<int>& loop, BoundaryShape shape) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const std::size_t b = loop.size();
  const std::size_t minimum = shape == BoundaryShape::square ? 4 : 3;
  if (b < minimum) {
    throw InputError("map_boundary: the boundary loop has " + std::to_string(b) + " vertices; at least " +
                     std::to_string(minimum) + " are needed");
  }
  BoundaryMap map;
  map.indices = loop;
  map.uv.resize(static_cast<Eigen::Index>(b), 2);
  detail::check_constrained_vertices(loop, Eigen::MatrixX2d::Zero(static_cast<Eigen::Index>(b), 2), V.rows(),
                                     "boundary", "map_boundary");
  const std::vector<double> length = arc_lengths(V, loop);
  const double total = length[b];
  if (shape == BoundaryShape::circle) {
    for (std::size_t i = 0; i < b; ++i) {
      const double angle = length[i] * 2.0 * pi / total;
      map.uv.row(i) << std::cos(angle), std::sin(angle);
    }
    return map;
  }
  // Square: corner k at the loop vertex nearest k/4 of the arc length, kept strictly increasing.
  std::size_t corner[5];
  corner[0] = 0;
  corner[4] = b;
  for (int k = 1; k < 4; ++k) {
    std::size_t best = corner[k - 1] + 1;
    for (std::size_t i = best; i + (4 - k) <= b; ++i) {
      if (std::abs(length[i] - k * total / 4) < std::abs(length[best] - k * total / 4)) best = i;
    }
    corner[k] = std::min(best, b - (4 - k));
  }
  for (int k = 0; k < 4; ++k) {
    const double start = length[corner[k]], span = length[corner[k + 1]] - start;
    for (std::size_t i = corner[k]; i < corner[k + 1]; ++i) map.uv.row(i) = on_square_side(k, (length[i] - start) / span);
  }
  return map;
}

BoundaryMap map_boundary(const VertexRef& input_V, const FaceRef& F, BoundaryShape shape) {
  const auto normalized = detail::normalized(input_V);
  const VertexRef V(normalized.V);
  const auto mesh = detail::check_mesh(V, F, detail::Requirement::has_boundary, "map_boundary");
  return map_boundary_loop(V, mesh.boundary_loops.front(), shape);
}

}  // namespace meshsmith::parametrization
