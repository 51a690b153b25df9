// Lawson's edge-flip algorithm (curriculum §2.1.1: flip BD to AC when α + γ > 180°).
#include "edge_faces.h"
#include "planar_detail.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/tessellation/delaunay.h>

#include <string>
#include <vector>

namespace meshsmith::tessellation {

namespace {

/// Index (0..2) of the corner of triangle f that is neither p nor q.
int opposite_corner(const FaceMatrix& F, int f, int p, int q) {
  for (int c = 0; c < 3; ++c)
    if (F(f, c) != p && F(f, c) != q) return c;
  return -1;
}

void replace_face(detail::EdgeFaces& edges, int a, int b, int old_face, int new_face) {
  auto& sides = edges.at(detail::edge_key(a, b));
  for (int& side : sides)
    if (side == old_face) side = new_face;
}

}  // namespace

FlipResult flip_to_delaunay(const PointRef2& V, const FaceRef& F) {
  detail::require_finite(V, "V");
  auto at = [&](int i) { return V.data() + i * V.outerStride(); };
  const int n = static_cast<int>(V.rows());
  FlipResult result;
  result.F = F;
  FaceMatrix& T = result.F;
  for (Eigen::Index f = 0; f < T.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      if (T(f, c) < 0 || T(f, c) >= n)
        throw InputError("F: row " + std::to_string(f) + " holds index " + std::to_string(T(f, c)) +
                         ", outside [0, " + std::to_string(n) + ")");
    const int turn = detail::orientation(at(T(f, 0)), at(T(f, 1)), at(T(f, 2)));
    if (turn == 0)
      throw InputError("F: triangle " + std::to_string(f) + " is degenerate (zero area)");
    if (turn < 0) std::swap(T(f, 1), T(f, 2));
  }
  detail::EdgeFaces edges = detail::build_edge_faces(T);

  std::vector<std::pair<int, int>> pending;
  pending.reserve(edges.size());
  for (const auto& [key, sides] : edges)
    if (sides[1] >= 0) pending.emplace_back(static_cast<int>(key >> 32), static_cast<int>(key & 0xffffffffu));
  // Lawson flips reach the Delaunay triangulation after at most n(n-1)/2 flips.
  const long flip_limit = static_cast<long>(n) * (n - 1) / 2 + 1;

  while (!pending.empty()) {
    auto [p, q] = pending.back();
    pending.pop_back();
    auto found = edges.find(detail::edge_key(p, q));
    if (found == edges.end() || found->second[1] < 0) continue;  // flipped away meanwhile
    int f1 = found->second[0], f2 = found->second[1];
    int i = opposite_corner(T, f1, p, q);
    // Orient so that f1 = (a, p, q) and f2 = (d, q, p), both counter-clockwise.
    p = T(f1, (i + 1) % 3);
    q = T(f1, (i + 2) % 3);
    const int a = T(f1, i);
    const int d = T(f2, opposite_corner(T, f2, p, q));
    const double* A = at(a);
    const double* P = at(p);
    const double* Q = at(q);
    const double* D = at(d);
    if (detail::side_of_circle(A, P, Q, D) <= 0) continue;  // locally Delaunay
    // d strictly inside the circumcircle of (a, p, q) makes the quad a-p-d-q convex in a valid
    // triangulation; check anyway so that overlapping input cannot produce inverted triangles.
    if (detail::orientation(A, P, D) <= 0 || detail::orientation(A, D, Q) <= 0) continue;
    if (++result.flip_count > flip_limit)
      throw SolverError("flip_to_delaunay: more than n(n-1)/2 flips; is (V, F) a planar triangulation?");
    T.row(f1) << a, p, d;
    T.row(f2) << a, d, q;
    edges.erase(detail::edge_key(p, q));
    edges[detail::edge_key(a, d)] = {f1, f2};
    replace_face(edges, p, d, f2, f1);
    replace_face(edges, q, a, f1, f2);
    pending.insert(pending.end(), {{a, p}, {p, d}, {d, q}, {q, a}});
  }
  return result;
}

}  // namespace meshsmith::tessellation
