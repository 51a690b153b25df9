#pragma once
/// \file poisson.h
/// Screened Poisson surface reconstruction (§2.2, §3.1; Kazhdan, Bolitho & Hoppe 2006, Kazhdan &
/// Hoppe 2013) from oriented samples, on an octree adapted to the samples' density.
///
/// The indicator χ minimises ∫ |∇χ − V|² + α 2^d Σ_s a_s χ(p_s)² with trilinear (Q1) elements,
/// where V is the samples' outward normals a_s n_s splatted trilinearly at each sample's depth
/// (the deepest level where the support of the node nearest to the sample, its 8 cells, holds
/// >= samples_per_node samples; a_s is the sample's share of the surface area in that support;
/// the screening sums over the samples whose depth + refinement >= d, by default all). Level
/// `coarse_depth` is the full (2^d + 1)³ grid over the bounding cube (natural boundary
/// conditions); each finer level d keeps only the blocks of 2³ cells within band + 1 cells of
/// the samples refined to d. A block of level d + 1 is a cell of level d, so the levels form an
/// octree whose leaves are the band cells without a block on the next level.
/// e is `extraction_depth`, or by default the deepest level that at least half of the samples
/// reach (their depth, above): the resolution the samples support.
/// adaptive: a sample is refined to one level beyond its own depth only (at most
/// e), so the octree reaches e only where the samples are dense (Kazhdan & Hoppe's adaptive
/// octree), and the surface is extracted on the leaves, crack-free across leaves of different
/// sizes (the iso-segments of each leaf's faces taken on the finest leaves across them, as in
/// Kazhdan, Klein, Dalal & Hoppe 2007, "Unconstrained isosurface extraction on arbitrary
/// octrees"); the mesh is finer where the samples are denser. adaptive = false (the default,
/// faster and as accurate on the shared clouds: see poisson.py): every sample is
/// refined to e, the band_refinement levels beyond e only around the samples whose depth reaches
/// them, and the surface is extracted by marching_cubes_sparse on the grid of depth e.
/// A level takes the coarser solution as its boundary values and initial guess and is solved by
/// Jacobi-preconditioned conjugate gradients (a cascadic multigrid: coarse to fine, one CG run
/// per level, no V-cycles). χ is thereby defined everywhere (the finest band where it exists,
/// coarser levels elsewhere; continuous because the Q1 spaces are nested), and its iso-surface
/// at the mean of χ over the samples is closed, oriented and manifold wherever the surface stays
/// inside the bounding cube. Open3D and PoissonRecon extract on the leaves of their
/// sample-adapted octree, so their meshes have about the size of ours at the same `depth`.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <cstdint>
#include <vector>

namespace meshsmith::reconstruction {

/// Options of poisson().
struct PoissonOptions {
  int depth = 8;                  ///< finest level: 2^depth cells along the bounding cube's edge, in [2, 10]
  double screening = 8.0;         ///< α, the weight pulling χ to the iso-value at the samples (>= 0;
                                  ///< not PoissonRecon's point-weight scale: see poisson.py)
  double samples_per_node = 1.5;  ///< samples a node's support must hold for a sample to be splatted at its level (> 0)
  double scale = 1.1;             ///< bounding cube edge ÷ the samples' largest extent (>= 1)
  int coarse_depth = 4;           ///< the level solved on the full grid (clamped to [2, depth])
  int band = 1;                   ///< cells kept around the samples on finer levels, in [1, 16]
  int refinement = 10;            ///< levels beyond a sample's depth where it screens χ, in [0, 10] (10: all)
  int band_refinement = 0;        ///< adaptive = false: levels solved beyond the extraction depth (around the samples whose depth reaches them), in [0, 10]
  int extraction_depth = 0;       ///< e: the finest leaves' depth (adaptive = false: of the marching-cubes grid), in [2, depth]; 0: automatic
  bool adaptive = false;           ///< an octree adapted to the samples' depths, extracted on its leaves
                                  ///< (false: bands around every sample up to one extraction depth)
  int max_iterations = 300;       ///< conjugate-gradient iterations per level (>= 1)
  double tolerance = 1e-3;        ///< relative residual that ends a level's iterations (> 0; measured on
                                  ///< pmp-bunny.xyz: 1e-4 took 17 iterations per level instead of 12
                                  ///< for the same distances to the ground truth to 1e-7 × diagonal)
};

/// What one level of the cascade did.
struct PoissonLevel {
  int depth = 0;
  std::int64_t unknowns = 0;    ///< free nodes (the band's interior)
  std::int64_t boundary = 0;    ///< nodes given by the coarser level
  int iterations = 0;
  double residual = 0.0;        ///< relative residual reached
};

/// The reconstructed surface.
struct PoissonResult {
  VertexMatrix V;             ///< #V×3
  FaceMatrix F;               ///< #F×3, outward
  Eigen::VectorXd density;    ///< #V: samples within 2 finest cells of the vertex (low: unsupported)
  double iso = 0.0;           ///< the iso-value (mean χ at the samples)
  int extraction_depth = 0;   ///< e: the depth of the finest leaves (adaptive = false: of the marching-cubes grid)
  std::vector<PoissonLevel> levels;
};

/// Screened Poisson reconstruction of the oriented samples P (#P×3) with normals N (#P×3,
/// outward, any non-zero length). Deterministic: the result does not depend on the thread count.
/// \pre #P >= 4 and P finite, not all on one line; N of P's shape, finite, no zero row; the
///      options within the ranges above; band_refinement 0 when adaptive.
/// \throw InputError if a precondition fails (naming the row or option). \throw Cancelled.
/// Time and memory O(#P + band cells at the finest level), about O(4^depth) for a surface.
/// The samples' checks of poisson() and graph_cut(): P finite, at least 4 rows, not all on one
/// line or at one point. \throw InputError naming the failure.
void validate_surface_samples(const VertexRef& P);

PoissonResult poisson(const VertexRef& P, const VertexRef& N, const PoissonOptions& options = {},
                      const Progress& progress = {});

}  // namespace meshsmith::reconstruction
