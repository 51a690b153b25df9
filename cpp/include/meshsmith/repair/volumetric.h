#pragma once
/// \file volumetric.h
/// Volumetric repair (§2.4.2 of the curriculum; after Ju 2004 "Robust repair of polygonal models",
/// with dual contouring, Ju et al. 2002): the triangles are rasterized into a grid of voxels
/// (stored sparsely: only 8×8×8 bricks near the surface hold cells, every other brick is one
/// state byte), the occupied voxels are closed by ρ (dilated, flood-filled from outside, eroded
/// back), and the boundary of the solid is extracted by dual contouring with one QEF vertex per grid
/// corner, so the result is a closed, manifold, outward-oriented mesh whatever the input was
/// (self-intersections, overlapping components, gaps and holes narrower than 2ρ are resolved).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <array>
#include <cstdint>

namespace meshsmith::repair {

/// Options of volumetric_repair.
struct VolumetricOptions {
  double epsilon = 0.0;   ///< > 0: the voxels' diagonal (edge epsilon/√3)
  double rho = 0.0;       ///< >= 0: closing radius (gaps and holes up to about 2ρ wide are closed)
  int smoothing = 3;      ///< rounds of feature-aware smoothing (0: none)
  std::int64_t max_cells = std::int64_t(1) << 25;  ///< memory cap on the cells stored (sparse: cells of the
                                                  ///< bricks near the surface, and the bricks; dense: all)
  bool dense = false;     ///< true: the whole dense voxel grid (~10 bytes a cell of the bounding box)
  /// >= 0 (opt-in, e.g. 0.25): coarse output where the surface is flat. The fine mesh is simplified by QEM edge
  /// collapses whose quadric error stays below (adaptive_error·ε)² (step 7); 0: one vertex per
  /// boundary corner of the finest cells everywhere.
  double adaptive_error = 0.0;
};

/// What volumetric_repair did.
struct VolumetricReport {
  std::array<std::int64_t, 3> shape{0, 0, 0};  ///< voxels per axis (of the whole grid, stored or not)
  double dense_cells = 0.0;        ///< shape's product: the cells a dense grid has
  std::int64_t stored_cells = 0;   ///< cells stored (sparse: 512 per brick near the surface; dense: all)
  double cell_size = 0.0;          ///< voxel edge
  std::int64_t occupied_cells = 0; ///< voxels a triangle overlaps
  std::int64_t inside_cells = 0;   ///< voxels of the solid after closing and the manifold fix
  std::int64_t closing_cells = 0;  ///< voxels the closing (dilate, fill, erode) added beyond occupied+enclosed
  std::int64_t manifold_cells = 0; ///< voxels added to remove the configurations whose boundary is not manifold
  std::int64_t sharp_vertices = 0; ///< vertices whose QEF has rank >= 2 (on a feature edge or corner)
  std::int64_t unconstrained_vertices = 0;  ///< vertices with no input surface near (closed holes, gaps)
  std::int64_t untangled_vertices = 0;      ///< vertices moved back towards their grid corner to undo a self-intersection
  std::int64_t fine_faces = 0;     ///< faces of the fine mesh (before the adaptive step; = output faces without it)
  double adaptive_bound = 0.0;     ///< the quadric bound the adaptive step used (length²; 0: not run)
  double adaptive_max_error = 0.0; ///< the largest quadric error of a collapse it made (length²)
  int adaptive_retries = 0;        ///< times the result self-intersected and the bound was quartered (4: the fine mesh is returned)
};

/// The repaired mesh and its report.
struct VolumetricResult {
  VertexMatrix V;  ///< #V'×3
  FaceMatrix F;    ///< #F'×3, outward
  VolumetricReport report;
};

/// Volumetric repair of a triangle soup. Steps: (1) voxels of edge h = ε/√3 over the bounding box
/// padded by ρ + 2h + 8h (the same lattice for both grids); a voxel is occupied when a triangle
/// overlaps it (separating-axis test of Akenine-Möller made conservative in floating point: the box is
/// enlarged by a bound on the rounding error of every projection, so no voxel a triangle touches is
/// missed), found by recursive octant subdivision of the triangle's bounding cube (cost ∝ its area in
/// cells). (2) Closing by ρ: voxels whose centres lie within ρ of an occupied one's are filled, the
/// outside is flood-filled (6-connected) from the grid's corner, every voxel it does not reach is
/// inside, then the outside grows back by ρ; occupied voxels always stay inside. Sparse (default):
/// dilation and erosion are balls of radius ρ stamped around the rim cells of the occupied set and of
/// the outside (the nearest cell of a set is on its rim), the flood fill visits a uniform brick as one
/// node, and only bricks the stamps or the flood's walls touch store cells, so memory and time follow
/// the surface's area in cells (× ρ/h), plus one byte and one int32 per brick of the bounding box
/// (1/512 of the dense grid). Dense: exact Euclidean distance transforms (Felzenszwalb & Huttenlocher)
/// over every voxel; the same solid. Why bricks and not an adaptive octree: the fine extraction has one
/// vertex per boundary corner of the finest cells either way (coarse output comes from step 7), so an
/// octree would only change how the empty and the enclosed space is stored, which the coarse brick
/// array already makes 512× smaller; the bricks keep the dense grid's neighbour
/// arithmetic, its well-composedness fix and so its manifold guarantee unchanged (no cracks between
/// cells of different size to handle). (3) The solid is made well-composed (no two voxels meeting only
/// along an edge or at a corner without a common face neighbour, in the solid or in its complement) by
/// adding voxels until none of those configurations is left; the voxel boundary of a well-composed set
/// is a 2-manifold, so the dual-contouring mesh, which has its combinatorics (one vertex per boundary
/// grid corner, one quad per boundary voxel face), is closed and manifold by construction (the
/// project's answer to DC's non-manifold cells). (4) Each vertex minimizes the QEF of the planes of the
/// input triangles nearest to the centres of its boundary faces (pseudo-inverse truncated at 2% of the
/// largest eigenvalue, about the mass point), clamped to its cell (the 8 voxels around the corner,
/// corner ± h: occupied voxels count as inside, so the input surface may lie anywhere in them), so
/// sharp edges and corners survive; vertices without input surface within 1.5h stay at the corner. (5)
/// Smoothing moves each vertex towards the mean of its neighbours only along the null space of its QEF
/// (flat vertices glide in their plane, edge vertices along the edge, corners stay), clamped to the
/// cell. (6) Quads are split along the shorter diagonal; faces found intersecting
/// (repair::self_intersections) have their vertices moved towards their corners until none is left (the
/// all-corner voxel surface is embedded); the first check covers every face, later ones only the faces
/// near the vertices just moved. (7) Adaptive output (adaptive_error > 0): the fine mesh is simplified
/// by decimation::decimate_qem (greedy QEM edge collapses, Garland & Heckbert 1997) until the cheapest
/// collapse would cost more than (adaptive_error·ε)²: a merged vertex's quadric sums its squared
/// distances to the planes of the fine faces it replaced (weighted by area / mean area, about 1 for these
/// uniform faces), so it stays within about adaptive_error·ε of each; flat regions become a few large
/// triangles while creases keep their planes on both sides. Every collapse passes the link condition
/// (closed, manifold, genus kept) and flips no normal; a result that self-intersects is redone from the
/// fine mesh with a quarter of the bound, at most three times, then the fine mesh is returned. Why this
/// and not octree simplification of the dual contour (Ju et al. 2002) with manifold dual contouring's
/// tests (Schaefer, Ju & Warren 2007): cells merge there only inside aligned octree cells, so a flat
/// region across a coarse cell's boundary stays fine along it, and its manifold guarantee needs those
/// extra topology tests; collapses on the fine mesh are not tied to the lattice and the link condition
/// is the manifold guarantee, from code the decimation chapter already tests. The cost: the fine mesh is
/// built first, so peak memory follows the fine output (~1 KB a fine face), not the coarse one.
/// V: #V×3, F: #F×3 (validate_mesh). Memory: sparse, 512 bytes a stored brick + 5 bytes a brick
/// of the box + ~250 bytes an output vertex; dense, about 10 bytes a voxel.
/// \throw InputError if validate_mesh fails, epsilon is not finite and > 0, rho is not finite and
///        >= 0, smoothing < 0, more than 2,097,150 voxels along an axis, or more than max_cells
///        cells stored (dense: the grid's voxels; sparse: the bricks' cells, or bricks; the message
///        gives the count). \throw Cancelled from progress.
VolumetricResult volumetric_repair(const VertexRef& V, const FaceRef& F, const VolumetricOptions& options,
                                   const Progress& progress = {});

}  // namespace meshsmith::repair
