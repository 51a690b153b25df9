#pragma once
/// \file decimate.h
/// Incremental decimation (§4.2; Garland & Heckbert 1997, "Surface simplification using quadric
/// error metrics"; Wu & Kobbelt 2002, "Fast mesh decimation by multiple-choice techniques"):
/// one greedy loop of edge collapses, ordered by an error metric (§4.2.2), filtered by switchable
/// fairness criteria (§4.2.3) and always by the link condition, so a manifold mesh stays manifold
/// and keeps its Euler characteristic.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/decimation/collapse_record.h>

#include <cstdint>
#include <vector>

namespace meshsmith::decimation {

/// The local decimation operator (§4.2.1).
enum class CollapseOperator {
  edge,      ///< full-edge collapse: the merged vertex goes to the quadric's optimal position
  halfedge,  ///< half-edge collapse: one endpoint merges into the other, which does not move
};

/// The error metric that orders the collapses (§4.2.2). Whatever the cost, the merged vertex is
/// placed by the quadric (edge operator) or stays at the kept endpoint (half-edge operator).
enum class CollapseCost {
  /// Error quadrics: the area-weighted mean-normalised sum of squared distances to the planes of
  /// the original faces merged so far (length² units; see QemOptions::max_error).
  quadric,
  /// Squared distance of the new position to the least-squares plane of the vertices of both
  /// one-rings (length² units).
  plane_distance,
  /// |Σ signed volumes| swept by the faces around the moving vertices (length³ units).
  volume_change,
};

/// Options of decimate_qem. At least one stop rule (target_faces > 0 or max_error > 0).
struct QemOptions {
  /// Stop when the mesh has at most this many faces (0: no face target).
  Eigen::Index target_faces = 0;
  /// Stop when the cheapest remaining collapse costs more than this (0: no bound). For the
  /// quadric cost the unit is length²: each original face contributes its plane with the weight
  /// area / mean face area, so the error is a sum of squared plane distances in which an average
  /// face counts once.
  double max_error = 0;
  CollapseOperator collapse = CollapseOperator::edge;
  CollapseCost cost = CollapseCost::quadric;
  /// Multiple-choice decimation (Wu & Kobbelt): each step collapses the best of `candidates`
  /// random edges instead of the global best; 0 uses the full priority queue.
  int candidates = 0;
  std::uint64_t seed = 0;  ///< random stream of the multiple-choice variant
  // Fairness criteria (§4.2.3), each a switchable predicate on a candidate collapse.
  bool prevent_normal_flips = true;     ///< reject a collapse that turns a face's normal by ≥ 90°
  double max_normal_deviation_deg = 0;  ///< reject a turn of a face normal above this (0: off)
  /// Reject a collapse that makes a face's quality 4√3·area / Σ edge² (1: equilateral) lower
  /// than this and lower than it was (0: off).
  double min_triangle_quality = 0;
  int max_valence = 0;  ///< reject a collapse whose merged vertex would have more neighbours (0: off)
  /// Boundary vertices collapse only along the boundary (into a boundary neighbour over a
  /// boundary edge), interior vertices next to the boundary merge into the boundary vertex, and
  /// constraint planes through the boundary edges keep the boundary in place.
  bool keep_boundary = true;
  /// Fill QemResult::collapses (the vertex splits of a progressive mesh, §4.3).
  bool record_collapses = false;
  /// On meshes of at least 100,000 faces (quadric cost, full queue): the first 95% of the
  /// collapses, down to no fewer than 20,000 faces, run on four spatial parts at once
  /// (decimate_qem says how); false: one serial run.
  bool parallel = true;
};

/// Result of decimate_qem.
struct QemResult {
  VertexMatrix V;               ///< #V'×3 positions of the decimated mesh
  FaceMatrix F;                 ///< #F'×3 triangles, counter-clockwise like the input
  Eigen::VectorXi vertex_origin;  ///< #V': the input vertex each output vertex was (it is kept)
  /// The collapses performed, in order (only with record_collapses). Vertex indices refer to the
  /// working vertices: the input's, followed, when the input had to be split (non-manifold or
  /// inconsistently oriented, see split_vertex_origin), by the copies the split appended.
  std::vector<CollapseRecord> collapses;
  /// Largest cost of a performed collapse (units of the cost, input coordinates): +∞ when that
  /// exceeds the double range (squared distances of a mesh of size 1e155 and beyond).
  double max_collapse_error = 0;
  /// The same cost in the normalized frame the decimation ran in (core/normalization.h), and the
  /// power of two that maps it to input units: max_collapse_error = max_collapse_error_normalized ·
  /// 2^max_collapse_error_exponent, which stays usable where the product overflows.
  double max_collapse_error_normalized = 0;
  int max_collapse_error_exponent = 0;
  bool target_reached = false;    ///< target_faces reached (false: stopped by max_error or stuck)
  Eigen::Index collapse_count = 0;  ///< number of collapses performed
  /// Empty when the input was used as is. Otherwise the input vertex of each working vertex
  /// (#V + copies): vertices whose faces do not form one consistently oriented fan (pinches,
  /// non-manifold edges, flipped neighbours) were split into one copy per fan first.
  Eigen::VectorXi split_vertex_origin;
};

/// Greedy incremental decimation (§4.2): collapses the cheapest admissible edge until a stop rule
/// holds, keeping per-vertex error quadrics (summed on collapse; face planes weighted by area,
/// plus constraint planes along boundary and sharp edges) and a monotone queue of collapses (a
/// radix heap, one live entry per edge): each collapse re-costs the edges around the kept vertex
/// and drops those that die (the top is still re-costed before it is collapsed). Equal costs go
/// to the shorter edge first, then the smaller half-edge index. A collapse rejected by the checks
/// is retried when an edge at one of its ends collapses. On meshes of 100,000 faces or more
/// (QemOptions::parallel) the first 95% of the collapses, down to no fewer than 20,000 faces, run
/// on four spatial parts at once, in rounds under a common cost ceiling, with the part borders
/// shifted at each halving; a serial run does the rest. The result is deterministic and does not depend on the thread count.
/// O(#F log #F) time, about 250 bytes per face of memory. Runs on normalized coordinates
/// (core/normalization.h): coordinates from 1e-300 to 1e308 give the result of scale 1, scaled
/// exactly (quadrics are of degree 4 and overflowed from 1e77). Faces with a repeated vertex index are
/// dropped first; zero-area faces,
/// duplicate vertices, several components and holes are fine. Non-manifold or inconsistently
/// oriented input is split into manifold, oriented fans first (never torn further), and the
/// output refers back to the input through vertex_origin.
///
/// Invariants of the output: every collapse passes the link condition (the mesh stays manifold
/// and keeps its Euler characteristic; a closed component never shrinks below a tetrahedron),
/// no face normal flips (with prevent_normal_flips), boundaries stay (with keep_boundary).
///
/// V: #V×3 positions, F: #F×3 triangles.
/// \pre validate_mesh(V, F) passes (called here); options hold a stop rule, target_faces >= 0,
///      max_error >= 0, candidates >= 0, max_valence >= 0, min_triangle_quality in [0, 1],
///      max_normal_deviation_deg in [0, 180].
/// \throw InputError if a precondition fails, naming it, or if every face has a repeated index. \throw Cancelled through `progress`.
QemResult decimate_qem(const VertexRef& V, const FaceRef& F, const QemOptions& options,
                       const Progress& progress = {});

}  // namespace meshsmith::decimation
