#pragma once
/// \file marching_cubes.h
/// Iso-surfaces of a scalar field sampled on a regular grid (marching cubes, §2.2 / §3.1 of the
/// curriculum; Lorensen & Cline 1987, face ambiguities resolved by the asymptotic decider of
/// Nielson & Hamann 1991), on the whole grid or only on the blocks of cells the surface passes
/// through (a surface-following narrow band, so a 512³ grid is never allocated).
///
/// Conventions, both variants: grid point (i, j, k) sits at origin + (i·sx, j·sy, k·sz); a value
/// below `iso` is inside, one at or above it outside; there is exactly one vertex per grid edge
/// whose end values straddle `iso` (linear interpolation along the edge, so the vertex set is
/// that of libigl's or scikit-image's marching cubes on the same grid), vertices are numbered
/// in the order of their edges (grid point in C order, then the axis); triangles are oriented
/// counter-clockwise seen from outside (normals point towards increasing values). Each cell's
/// surface is made of one disc per loop of crossings on the cell's faces, so the output is an
/// edge-manifold, consistently oriented mesh, closed wherever the level set does not leave the
/// grid (or, in the sparse variant, the region it reached from its seeds).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace meshsmith::reconstruction {

/// A regular grid of shape[0]·shape[1]·shape[2] points.
struct Grid {
  std::array<std::int64_t, 3> shape{2, 2, 2};  ///< points per axis, each >= 2
  std::array<double, 3> origin{0.0, 0.0, 0.0};  ///< position of point (0, 0, 0)
  std::array<double, 3> spacing{1.0, 1.0, 1.0}; ///< distance between neighbouring points per axis, > 0
};

/// An iso-surface mesh and what it cost.
struct ContourMesh {
  VertexMatrix V;                ///< #V×3 vertices, one per crossed grid edge (+ centre_vertices)
  FaceMatrix F;                  ///< #F×3 triangles, outward (towards values >= iso)
  std::int64_t centre_vertices = 0;  ///< extra vertices at the centre of a cell's loop (only where a
                                     ///< loop has no triangulation by chords inside the cell; rare)
  std::int64_t blocks = 0;       ///< blocks of cells visited (each holds up to block_size³ cells)
  std::int64_t evaluations = 0;  ///< grid values read or evaluated (block corners, with repeats)
};

/// Marching cubes on a dense grid. values: shape[0]·shape[1]·shape[2] doubles in C order
/// (values[(i·ny + j)·nz + k] at point (i, j, k)).
/// \pre every shape entry >= 2, spacing > 0 and finite, origin and iso finite, no NaN/Inf in
///      values; fewer than 2^31 output vertices and faces.
/// \throw InputError if a precondition fails (naming the first NaN value). \throw Cancelled.
/// O(#cells) time, O(#output) memory beyond the values; parallel (TBB), thread-count independent.
ContourMesh marching_cubes(const double* values, const Grid& grid, double iso = 0.0,
                           const Progress& progress = {});

/// Fills out[r] with the field's value at grid point points(r, ·) (integer grid indices, m×3) for
/// r < points.rows(); must return the same value for the same point every time.
using GridFunction = std::function<void(
    const Eigen::Ref<const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>>& points,
    double* out)>;

/// Options of marching_cubes_sparse.
struct SparseOptions {
  int block_size = 8;   ///< cells per block edge (values are evaluated on the (b+1)³ corners of a block)
  int dilation = 0;     ///< rings of blocks added around each seed's block before the surface is followed
  std::int64_t max_blocks = std::int64_t(1) << 22;  ///< stop rule against a field that is
                                                    ///< nowhere near its level set: InputError beyond it
};

/// Marching cubes on the blocks the surface passes through: starting from the blocks holding the
/// `seeds` (positions, m×3, e.g. the samples a field was fitted to), each wave evaluates `field`
/// on the corners of its new blocks (one call per wave), contours them, and adds every block
/// that shares a crossed grid edge with them; it stops when no block is added. The result is the
/// same mesh marching_cubes gives on the full grid for every connected piece of the level set
/// that passes through a seed block (other pieces are not found). Memory: O(visited blocks).
/// \pre grid as marching_cubes; seeds non-empty and finite (seeds outside the grid are
///      ignored; InputError if all are); block_size in [1, 64]; dilation in [0, 16].
/// \throw InputError if a precondition fails, `field` returns a NaN/Inf, or more than max_blocks
///        blocks are visited. \throw Cancelled. Whatever `field` throws propagates.
ContourMesh marching_cubes_sparse(const GridFunction& field, const Grid& grid, const VertexRef& seeds,
                                  double iso = 0.0, const SparseOptions& options = {},
                                  const Progress& progress = {});

/// The grid's checks as both functions apply them. \throw InputError.
void validate_grid(const Grid& grid);

}  // namespace meshsmith::reconstruction
