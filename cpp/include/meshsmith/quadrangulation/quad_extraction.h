#pragma once
/// \file quad_extraction.h
/// Quad extraction from a seamless parametrization: the integer grid of the (u, v) map, pulled back
/// onto the surface as a quad mesh (§5.2.2 step 4; the QEx setting of Ebke, Bommes, Chen and
/// Kobbelt, "QEx: Robust Quad Mesh Extraction", SIGGRAPH Asia 2013).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::quadrangulation {

/// #Q by 4 quads: indices into the rows of a VertexMatrix, counter-clockwise seen from outside.
using QuadMatrix = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;
/// #F*3 by 2 per-corner parameter positions: row 3f + k is corner k of face f.
using CornerUVMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using CornerUVRef = Eigen::Ref<const CornerUVMatrix>;

/// What extract_quads found in the parametrization and what it had to leave out. A clean
/// extraction has every count of left-out squares at zero and euler_output == euler_input.
struct QuadExtractionReport {
  Eigen::Index flipped_triangles = 0;      ///< faces whose (u, v) triangle is clockwise (after untangling)
  Eigen::Index degenerate_triangles = 0;   ///< faces whose (u, v) triangle has zero area
  Eigen::Index non_seamless_edges = 0;     ///< interior edges whose two sides are not related by
                                           ///< a quarter-turn rotation and an integer translation
                                           ///< (tolerance 1e-6 × max(1, |uv|))
  Eigen::Index non_integer_singularities = 0;  ///< singular vertices whose fixed point is not an integer point
  Eigen::Index untangled_vertices = 0;      ///< free vertices of clockwise triangles moved (in (u, v)) to
                                           ///< the mean of their ring, which left fewer bad triangles
  std::vector<int> singular_vertices;      ///< vertices with a non-zero index, ascending
  std::vector<int> singular_indices;       ///< their indices in quarter turns (+1: valence 3, −1: valence 5)
  Eigen::Index squares_cut_by_boundary = 0;  ///< unit squares crossed by a boundary edge (boundary
                                             ///< not on an integer iso-line): left out
  Eigen::Index squares_inconsistent = 0;   ///< squares whose pieces do not fit together (flips,
                                           ///< degenerate triangles, seams that do not match): left out
  Eigen::Index quads_non_manifold = 0;     ///< quads removed so that the rest is manifold
  long long euler_input = 0;               ///< χ of the triangle mesh
  long long euler_output = 0;              ///< χ of the quad mesh
  bool mirrored = false;                   ///< the map was clockwise overall and was read mirrored (v → −v)
  /// True when nothing was left out and χ is preserved: a pure, complete quad mesh.
  bool complete() const {
    return squares_cut_by_boundary == 0 && squares_inconsistent == 0 && quads_non_manifold == 0 &&
           euler_output == euler_input;
  }
};

struct QuadExtraction {
  VertexMatrix V;               ///< #Vq×3 grid nodes on the surface
  QuadMatrix Q;                 ///< #Q×4 quads, each the preimage of one unit square [i, i+1]×[j, j+1]
  CornerUVMatrix node_uv;       ///< #Vq×2 integer (u, v) of each node in the chart of the face it was found in
  Eigen::VectorXi node_face;    ///< #Vq: that face
  QuadExtractionReport report;
};

/// Extracts the quad mesh of the integer grid of a seamless parametrization: every unit square of
/// the grid whose preimage is a complete disk on the surface becomes one quad, with its corners at
/// the preimages of the integer points. Inside each triangle the squares are found with exact
/// predicates (the map is first made exactly seamless on a dyadic grid, so that every test
/// agrees across seams), and squares are glued across edges through the seams' transitions.
///
/// V: #V×3 positions. F: #F×3 triangles. UV: #F*3×2 per-corner (u, v) (row 3f + k), seamless:
/// across each interior edge the two sides differ by a rotation kπ/2 and an integer translation,
/// singular vertices sit on integer points, boundaries on integer iso-lines.
/// Where it is not (flipped or zero-area triangles, seams that do not match, non-integer
/// singularities, boundaries across squares), the squares concerned are left out, quads are removed
/// until the rest is manifold, and the report counts each: the result is always a manifold,
/// consistently oriented pure quad mesh, complete when report.complete().
/// \pre validate_mesh(V, F) passes; F is manifold (edges and vertices); UV is finite, |uv| < 2^40.
/// \throw InputError if a precondition fails (the message names the face, edge or vertex), or if the
///        triangles' bounding boxes in (u, v) hold more than 2^26 unit squares.
/// Complexity: O(#F + #quads) expected (ordered maps: × log).
QuadExtraction extract_quads(const VertexRef& V, const FaceRef& F, const CornerUVRef& UV,
                             const Progress& progress = {});

}  // namespace meshsmith::quadrangulation
