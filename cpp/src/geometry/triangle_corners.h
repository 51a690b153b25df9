#pragma once
// Internal to the geometry chapter (not installed API): per-triangle corner quantities and the
// vertex → corner incidence shared by normals, Laplacians, mass matrices and curvatures.
//
// Per-face quantities are computed in parallel (TBB). Per-vertex sums are taken either by
// accumulate_at_vertices (fixed face chunks, each summed in face order into its own buffer) or
// as a parallel gather over the corners around each vertex (in face order). Neither depends on
// the thread count, so results are bitwise deterministic on any machine.
#include <meshsmith/core/types.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace meshsmith::geometry::detail {

/// Per-face values for the three corners, row f = (corner 0, corner 1, corner 2).
using CornerMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// Per-face directed edge weights: column 2c is the weight of corner c's vertex towards the
/// next vertex of the face (c+1 mod 3), column 2c+1 towards the previous one (c+2 mod 3).
using DirectedWeights = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

/// Runs body(i) for i in [0, n), in parallel chunks of `grain`.
template <typename Body>
void parallel_for(Eigen::Index n, Body&& body, Eigen::Index grain = 2048) {
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, grain),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
                      for (Eigen::Index i = range.begin(); i != range.end(); ++i) body(i);
                    });
}

/// The corners (3·face + corner) around every vertex, in increasing face order:
/// corners[offsets[v] .. offsets[v+1]) are the corners c with F(c / 3, c % 3) == v.
struct VertexCorners {
  std::vector<std::int64_t> offsets;  // #V + 1
  std::vector<int> corners;           // 3·#F
  std::int64_t begin(Eigen::Index v) const { return offsets[v]; }
  std::int64_t end(Eigen::Index v) const { return offsets[v + 1]; }
};
/// \pre every index of F is in [0, n).
VertexCorners vertex_corners(const FaceRef& F, Eigen::Index n);

/// The geometry of one triangle that every quantity here derives from. cross, double_area, dot
/// and squared_edge are those of the triangle scaled by 2^-exponent: exponent is 0 unless the
/// longest edge is outside [2^-250, 2^250], where products of four coordinates would underflow
/// or overflow; then the corners are scaled into (−1, 1) (core/normalization.h, exact).
/// Ratios (cotangents, angles, unit normals) need nothing; an area is 4^exponent times its
/// scaled value, a length 2^exponent times.
struct Triangle {
  Eigen::Vector3d p[3];     // corner positions (input coordinates)
  Eigen::Vector3d cross;    // (p1 − p0) × (p2 − p0) = 2·area·unit normal
  double double_area;       // |cross|
  double dot[3];            // (p_next − p_c) · (p_prev − p_c) at corner c
  double squared_edge[3];   // |p_prev − p_next|², the edge opposite corner c
  bool degenerate;          // double_area ≤ 8·ε·(longest edge)²: cotangents would blow up
  int exponent = 0;         // the scaling above
};
Triangle triangle(const VertexRef& V, const FaceRef& F, Eigen::Index f);
/// Just (p1 − p0) × (p2 − p0) of face f, with the same prefetching as triangle().
Eigen::Vector3d triangle_cross(const VertexRef& V, const FaceRef& F, Eigen::Index f);

/// Interior angle at corner c, atan2(|cross|, dot) (a fast, ~2-ulp implementation): accurate for
/// small and large angles alike, finite for degenerate triangles (0 at a repeated vertex).
double corner_angle(const Triangle& t, int c);
/// The three interior angles: the two at the ends of the longest edge by corner_angle, the
/// largest as π minus the other two (all three by corner_angle on degenerate triangles).
void triangle_angles(const Triangle& t, double angles[3]);

/// The part of each triangle's area that goes to each corner: a third (barycentric) or the
/// mixed Voronoi area (Meyer et al. 2003, libigl's rule for obtuse triangles). #F×3.
enum class CornerAreaRule { barycentric, mixed_voronoi };
void triangle_corner_areas(const Triangle& t, CornerAreaRule rule, double areas[3]);
CornerMatrix corner_areas(const VertexRef& V, const FaceRef& F, CornerAreaRule rule);


/// Per-vertex sums of per-corner contributions, computed and accumulated in one parallel pass
/// over the faces, deterministically: the faces are cut into a fixed number of chunks (it
/// depends on #F only, never on the thread count); each chunk is summed in face order into its
/// own buffer, and the buffers are added in chunk order. `per_face(f, out)` writes face f's
/// contribution to its corner c's vertex into out[c][0 .. Width).
/// Returns #V×Width sums (zero rows for vertices used by no face).
template <int Width>
using VertexSums = Eigen::Matrix<double, Eigen::Dynamic, Width, Width == 1 ? Eigen::ColMajor : Eigen::RowMajor>;
template <int Width, typename PerFace>
VertexSums<Width> accumulate_at_vertices(const FaceRef& F, Eigen::Index n, PerFace&& per_face) {
  using Sums = VertexSums<Width>;
  const Eigen::Index m = F.rows();
  // One chunk per 2^19 faces (at least 2, at most 8), one buffer of #V×Width per chunk.
  const int chunks = m < 65536 ? 1 : static_cast<int>(std::clamp<Eigen::Index>(m >> 19, 2, 8));
  std::vector<Sums> partial(chunks);
  tbb::parallel_for(0, chunks, [&](int chunk) {
    Sums& sums = partial[chunk];
    sums.setZero(n, Width);  // here, so that each buffer is zeroed (and first touched) in parallel
    const Eigen::Index begin = m * chunk / chunks, end = m * (chunk + 1) / chunks;
    double out[3][Width];
    for (Eigen::Index f = begin; f < end; ++f) {
      if (f + 12 < end) {  // the rows this loop adds to a few faces ahead (see triangle())
        for (int c = 0; c < 3; ++c) __builtin_prefetch(sums.data() + static_cast<Eigen::Index>(F(f + 12, c)) * Width, 1);
      }
      per_face(f, out);
      for (int c = 0; c < 3; ++c) {
        double* row = sums.data() + static_cast<Eigen::Index>(F(f, c)) * Width;
        for (int w = 0; w < Width; ++w) row[w] += out[c][w];
      }
    }
  });
  if (chunks > 1) {
    parallel_for(n, [&](Eigen::Index v) {
      for (int chunk = 1; chunk < chunks; ++chunk) partial[0].row(v) += partial[chunk].row(v);
    }, 8192);
  }
  return std::move(partial[0]);
}

/// The edge weights a Laplacian is assembled from, per face. Exactly one of:
/// `symmetric` (#F×3): the weight of the edge opposite corner k, the same in both directions;
/// `directed` (#F×6, see DirectedWeights); neither: every edge has weight 1, whatever the number
/// of faces sharing it (the graph Laplacian).
struct LaplacianWeights {
  const CornerMatrix* symmetric = nullptr;
  const DirectedWeights* directed = nullptr;
};

/// Laplacian-shaped #V×#V CSC matrix: L(i, j) is the sum over the faces with edge ij of the
/// weight of i towards j, L(i, i) = −Σ_j L(i, j). Every column holds its diagonal entry (0 for
/// vertices used by no face); rows are sorted; columns are assembled in parallel.
Eigen::SparseMatrix<double> assemble_laplacian(const FaceRef& F, const VertexCorners& corners,
                                               const LaplacianWeights& weights);

/// \throw InputError unless (V, F) passes validate_mesh and 6·#F + #V fits the matrix indices.
void validate_surface(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::geometry::detail
