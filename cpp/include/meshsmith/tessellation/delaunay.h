#pragma once
/// \file delaunay.h
/// 2D tessellations (curriculum §2.1.1): Delaunay triangulation, constrained Delaunay
/// triangulation of planar straight-line graphs, Voronoi diagram, Lawson edge flips and
/// Ruppert/Chew Delaunay refinement ("Steiner points ⇒ angles ≥ 20°"), terminating near small input angles.
///
/// Points are row-major (n, 2) double matrices; triangles are (m, 3) int rows, counter-clockwise.
/// Triangulations and the incircle / orientation tests behind them use exact predicates (CGAL's
/// filtered kernel), so degenerate input (collinear triples, cocircular quadruples) is handled
/// consistently; constructed points (intersections, circumcentres, Steiner points) are doubles,
/// computed on the points multiplied by a power of two that brings them to unit magnitude (exact),
/// so huge or tiny coordinates neither overflow nor underflow.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::tessellation {

/// n by 2 planar points.
using PointMatrix2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using PointRef2 = Eigen::Ref<const PointMatrix2>;
/// (m, 2) index pairs.
using SegmentRef = Eigen::Ref<const EdgeMatrix>;

/// Delaunay triangulation of a point set.
struct DelaunayResult {
  FaceMatrix F;                 ///< (m, 3) CCW triangles, indices into the input points
  Eigen::VectorXi merged;       ///< (n,) representative of each input point: merged[i] == i for
                                ///< kept points, the smallest index with the same coordinates else
};

/// Delaunay triangulation of P (n, 2) (CGAL Delaunay_triangulation_2, spatially sorted insertion).
/// Exactly equal points are merged: the first occurrence is kept and the others are reported in
/// `merged`. With cocircular points the triangulation of each cocircular polygon is one of the
/// valid ones (CGAL's symbolic perturbation), so it may differ from another library's.
/// \throw InputError for NaN/Inf, fewer than 3 distinct points, or all points collinear.
DelaunayResult delaunay(const PointRef2& P);

/// Triangulation with possibly new vertices (intersection or Steiner points).
struct PlanarMesh {
  PointMatrix2 V;       ///< (n + k, 2): the n input points (unchanged, same order), then k new ones
  FaceMatrix F;         ///< (m, 3) CCW triangles of the domain
  int steiner_count = 0;  ///< k: vertices that are not input points
};

/// Constrained Delaunay triangulation of a planar straight-line graph (P, segments), restricted to
/// its domain. Crossing segments are split at their intersection points (added to V, computed in
/// double precision; the predicates stay exact). The domain is every face that cannot be reached
/// from the unbounded face, nor from a face containing a hole seed, without crossing a segment
/// (Triangle's convention). Duplicate input points stay in V but are unreferenced.
/// \pre segments index P; no zero-length segment.
/// \throw InputError for NaN/Inf, an out-of-range or degenerate segment, fewer than 3 distinct
///        points, all points collinear, points spanning less than 1e-100 of their magnitude, a
///        hole seed with NaN/Inf, or two segments crossing so close to a vertex that double
///        precision cannot place their intersection (the message names the vertex).
PlanarMesh constrained_delaunay(const PointRef2& P, const SegmentRef& segments,
                                const PointRef2& holes);

/// Options of Delaunay refinement.
struct RefineOptions {
  double min_angle_degrees = 20.7;  ///< triangles with a smaller angle are split
  double max_area = 0;              ///< > 0: triangles with a larger area are split
  int max_steiner_points = 1000000; ///< termination guard
};

/// Ruppert's Delaunay refinement of the PSLG (P, segments) minus its holes (§2.1.1; Ruppert 1995,
/// Shewchuk 2002), our own loop on CGAL's constrained Delaunay triangulation: encroached
/// subsegments (diametral circles) are split first; then the worst triangle gets its circumcentre
/// or off-centre (Üngör 2004), unless that point encroaches a subsegment or lies beyond one,
/// which is split instead. Near small input angles (two segments meeting at less than 60°):
///  - a subsegment at the apex is split on a concentric shell (a power-of-two distance from the
///    apex), so the two sides get points at equal distances;
///  - a skinny triangle whose shortest edge joins two such points of one shell is left alone
///    (Triangle's seditious-edge rule);
///  - the terminator: in a wedge narrower than 0.5°, a skinny triangle whose three vertices all lie
///    on the wedge's two sides is left alone when its split would fall on those sides, and a
///    vertex on one side does not encroach the other (resolving such a wedge would take of the
///    order of 1/angle Steiner points per doubling of the distance from its apex).
/// Termination: Ruppert's analysis guarantees it for min_angle <= 20.7° away from small input
/// angles; near them the three rules above stop it (Shewchuk 2002, §6; Miller, Pav & Walkington
/// 2003); above 20.7° it terminates in practice up to 33° (every test domain), and the Steiner cap
/// turns any remaining runaway (a channel narrower than 1e-6 of its length, which needs a million
/// points; some domains at 34°: 2.5 s to the default cap next to a 1e-15 feature) into a
/// SolverError. Result: every triangle with an angle below min_angle
/// has its three vertices on the two segments of one small input angle (it lies in that angle's
/// cluster), or is so small (its split point within 2^-40 ~ 1e-12 of the coordinates' magnitude
/// of its vertices) that double precision cannot place the point;
/// area-bad triangles (max_area) are always split.
/// \pre P finite; segments index P.
/// \throw InputError as constrained_delaunay, or for min_angle outside (0, 35) or max_area < 0.
/// \throw SolverError if more than max_steiner_points points would be inserted.
/// \throw Cancelled (or what the callback throws) when `progress` says stop; it is polled every
///        256 refinement steps (microseconds each) and throttled to one call per 50 ms.
PlanarMesh refine(const PointRef2& P, const SegmentRef& segments, const PointRef2& holes,
                  const RefineOptions& options, const Progress& progress = {});

/// Result of Lawson's flip algorithm.
struct FlipResult {
  FaceMatrix F;         ///< same triangle count, CCW
  long flip_count = 0;  ///< edge flips performed
};

/// Lawson edge flips on a planar triangulation (V, F) until every interior edge is locally
/// Delaunay (α + γ ≤ 180°, the opposite vertex is not strictly inside the circumcircle — exact
/// incircle test, so cocircular quadruples stop flipping). Triangles given clockwise are
/// reoriented. Only the connectivity changes.
/// \throw InputError for NaN/Inf, an out-of-range index, a degenerate (zero-area) triangle, an
///        edge shared by more than two triangles or two triangles with inconsistent orientation.
/// \throw SolverError if the flip count exceeds the theoretical bound (cannot happen on a valid
///        planar triangulation; guards against overlapping input).
FlipResult flip_to_delaunay(const PointRef2& V, const FaceRef& F);

/// Voronoi diagram of the points (dual of their Delaunay triangulation).
struct VoronoiDiagram {
  PointMatrix2 vertices;   ///< (m, 2) circumcentre of Delaunay triangle t = vertex t
  EdgeMatrix edges;        ///< (e, 2) vertex indices; second is -1 for an infinite ray
  PointMatrix2 directions; ///< (e, 2) unit direction of each ray (0 for finite edges)
  EdgeMatrix edge_sites;   ///< (e, 2) the two sites each edge separates
  std::vector<PointMatrix2> cells;  ///< per input point: its cell ∩ bounds, CCW (empty if none)
  DelaunayResult delaunay;          ///< the dual triangulation (triangle t ↔ vertex t)
};

/// Voronoi diagram of P (n, 2) with cells clipped to the box bounds = (xmin, ymin, xmax, ymax).
/// Cells come from clipping the box by the bisector half-planes of each site's Delaunay neighbours
/// (Sutherland-Hodgman in double precision). Duplicate points share their representative's cell.
/// \throw InputError as delaunay(), for points spanning less than 1e-100 of their magnitude, or
///        for an empty / non-finite box.
VoronoiDiagram voronoi(const PointRef2& P, const Eigen::Vector4d& bounds);

}  // namespace meshsmith::tessellation
