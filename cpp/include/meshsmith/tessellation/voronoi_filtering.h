#pragma once
// Curve and surface reconstruction from samples by Voronoi filtering (§2.1.3), with the
// approximate medial axis and local feature size of §2.1.2.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <Eigen/Core>

namespace meshsmith::tessellation {

/// The crust of 2D samples (§2.1.3; Amenta, Bern & Eppstein 1998): Delaunay triangulation of the
/// samples together with the Voronoi vertices of the samples (CGAL Delaunay_triangulation_2,
/// exact predicates); the edges joining two samples form the reconstructed curve(s).
/// samples: n×2. Returns #E×2 edges (i < j, sorted) into the samples. For an R-sample with
/// R < 0.252 (the bound of the paper; the curriculum quotes the older R <= 0.06) each sample is
/// joined to exactly its two neighbours along the curve.
/// \pre n >= 3, finite, not all collinear, no two samples equal.
/// \throw InputError if a precondition fails (naming the offending sample).
EdgeMatrix crust(const Eigen::Ref<const Eigen::MatrixXd>& samples);

/// Approximate medial axis of a curve sampled densely (§2.1.2): the part of the Voronoi diagram
/// of the samples dual to the Delaunay edges that are not crust edges (the Voronoi edges that do
/// not cross the curve). Its vertices are Voronoi vertices, which converge to the medial axis as
/// the sampling gets denser (in 2D every Voronoi vertex does). Exactly the Voronoi edges between
/// two Voronoi vertices are returned (the inner axis and the bounded part of the outer axis: the
/// circumcentres of the triangles between the curve and the convex hull, far out for thin hull
/// triangles); the unbounded rays dual to convex-hull edges
/// (the outer axis's branches to infinity) are left out, so the result is finite.
struct MedialAxis {
  Eigen::MatrixXd vertices;  ///< #MV×2 Voronoi vertices used by the edges
  EdgeMatrix edges;          ///< #ME×2 Voronoi edges into `vertices`
};

/// \pre as crust. \throw InputError as crust.
MedialAxis medial_axis(const Eigen::Ref<const Eigen::MatrixXd>& samples);

/// Approximate local feature size LFS(p) = d(p, MA) of each sample (§2.1.2): the distance to the
/// nearest vertex of medial_axis(samples). An approximation that converges as the sampling gets
/// denser; it overestimates slightly where the medial-axis vertices are sparse.
/// Returns n values. \pre as crust. \throw InputError as crust.
Eigen::VectorXd local_feature_size(const Eigen::Ref<const Eigen::MatrixXd>& samples);

/// Estimated sampling ratio: the smallest R for which the samples are an R-sample of the curve
/// reconstructed by crust() (§2.1.2: every curve point c has a sample within R·LFS(c)). Each
/// crust edge pq is taken as the curve between p and q; its worst point is its midpoint, at
/// |pq|/2 from a sample, where LFS >= max(LFS(p), LFS(q)) - |pq|/2 (LFS is 1-Lipschitz), with LFS
/// from local_feature_size(). Returns +inf when that bound is not positive.
/// \pre as crust. \throw InputError as crust.
double sampling_ratio(const Eigen::Ref<const Eigen::MatrixXd>& samples);

struct CoconeOptions {
  /// Half-opening of the cocone around the plane orthogonal to the pole vector, in radians
  /// (θ = π/8 in Amenta, Choi, Dey & Leekha 2002).
  double cocone_angle = 0.39269908169872414;
  /// Holes of the extracted surface bounded by simple loops of at most this many edges are
  /// closed, and so are nearly planar ones (least principal spread of the loop's points at most
  /// 0.4 of the largest) of at most 4× this many edges (0: leave every hole open).
  int max_hole_edges = 8;
};

/// Surface reconstruction by the Cocone algorithm (§2.1.3 in 3D; Amenta, Choi, Dey & Leekha
/// 2002), a refinement of the Amenta–Bern–Kamvysselis crust with poles: Delaunay triangulation of
/// the points (CGAL Delaunay_triangulation_3); each point's pole p+ is the farthest Voronoi vertex
/// of its cell (on the convex hull: the average outward normal of its hull faces), n_p = p+ - p
/// estimates the normal; a Delaunay triangle is a candidate when its dual Voronoi edge meets the
/// cocone {x : angle(x - p, ±n_p) >= π/2 - θ} of each of its three corners. Manifold extraction:
/// sharp-edge pruning (the candidates around an edge whose candidates all lie in a wedge of less
/// than π/2, i.e. two consecutive ones leave a gap over 3π/2, are removed; up to 3 rounds: this
/// removes triangles folded back across flat tetrahedra), then dangling candidates (a free edge
/// and an edge shared by more than two candidates) are removed repeatedly, then the outer surface
/// of what remains is collected by a walk that, across each edge, takes the neighbour first
/// reached when turning outwards and never uses a directed edge twice (so at most two triangles
/// per edge, consistently oriented; one walk per connected surface, seeded at its extreme point
/// in x). Repair: small holes (see CoconeOptions::max_hole_edges) are closed by the minimum-area
/// triangulation of the loop (dynamic programming; no triangle facing against the pole normals
/// of two corners when avoidable); at a vertex where the triangles form several fans
/// only the largest fan is kept (then small holes are closed again; up to 3 rounds); each point
/// left on no triangle is inserted into the triangle it projects into and the edges around it are
/// flipped while that makes the triangles agree better with the corner normals (or as well, and
/// the two angles opposite the edge exceed π); an inward triangle (against the normals of two of
/// its corners) is cut out with its three neighbours and the hole re-triangulated, when the
/// region is a disk whose new triangulation faces outwards, else (a pleat) the stars of its
/// corners are cut out, re-triangulated and the corners inserted again, kept only when all of
/// that faces outwards with no longer edges (up to 32 such attempts).
/// points: n×3. Returns (V = the points, F = #F×3 triangles, consistently oriented, outwards).
/// Manifold and watertight when the sampling is dense and free of noise; every point is used
/// when the surface is closed. progress: stages "delaunay" (35%), "crust_3d: poles", "cocone",
/// "pruning", "extraction", "repair".
/// \pre n >= 4, finite, not coplanar, no two points equal.
/// \throw InputError if a precondition fails; Cancelled when progress cancels.
Mesh crust_3d(const Eigen::Ref<const Eigen::MatrixXd>& points, const CoconeOptions& options = {},
              const Progress& progress = {});

}  // namespace meshsmith::tessellation
