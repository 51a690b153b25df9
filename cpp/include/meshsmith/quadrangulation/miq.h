#pragma once
/// \file miq.h
/// Mixed-integer quadrangulation: a seamless, integer-grid parametrization that follows a cross
/// field (§5.2.2 step 3; Bommes, Zimmer & Kobbelt 2009 "Mixed-integer quadrangulation").
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/quadrangulation/cut_graph.h>

#include <Eigen/Core>

namespace meshsmith::quadrangulation {

struct MiqOptions {
  /// Target edge length of the quads, in input units (one unit of the integer grid). ≤ 0: twice
  /// the mean edge length of the input.
  double target_edge_length = 0.0;
  /// > 0: the grid unit is calibrated so that the continuous map (before the rounding) covers
  /// this many unit squares, i.e. about this many quads (the map's gradients are shorter than
  /// the field's where it curls, so √(area / quads) alone gave 6–11% fewer quads on the shared
  /// meshes); target_edge_length is then only the start. ≤ 0: the grid unit as given.
  double target_quads = 0.0;
  bool round_singularities = true;  ///< singular vertices on integer points
  bool round_translations = true;   ///< the seams' translations integer
  int repair_iterations = 10;       ///< rounds of stiffening flipped triangles and re-solving at most
                                    ///< (it stops after three rounds without fewer flips)
  double stiffening = 5.0;          ///< factor on the weight of a flipped triangle (and its neighbours) per round
  /// Where flips outlast the stiffening, move an integer unknown near them by ±1 and repair
  /// again, kept when fewer flips remain (at most four moves; MiqResult::rerounded_integers).
  bool reround = true;
  /// Interior edges whose dihedral angle exceeds this many degrees are features: where the
  /// combed cross follows such an edge (within 10°, as a field made with the same sharp_angle
  /// does), the coordinate across it is held constant along it and integer on both sides, so
  /// the edge lies on an integer iso-line and becomes a quad edge. ≤ 0: no features.
  double sharp_angle_degrees = 0.0;
  /// How far the grid's scale follows the conformal factor of the field's flat cone metric
  /// (0: a uniform scale, as in Bommes et al. 2009; 1: the whole factor). Where the cross field
  /// turns against parallel transport, a map with gradients s·u* cannot follow it without
  /// shear; with s = e^{λφ}, φ the log conformal factor whose gradient is the field's turning
  /// rotated by 90° (Cauchy–Riemann), the targets are integrable up to the field's harmonic part
  /// and the quads keep their right angles, at the price of quads of varying size.
  double conformal_scale = 1.0;
};

using CornerUV = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

struct MiqResult {
  CornerUV uv;                    ///< #F×6 (u0, v0, u1, v1, u2, v2): the parameter of each corner
  Eigen::Index flipped_before = 0;  ///< triangles with det(B − A, C − A) ≤ 0 after the rounding
  Eigen::Index flipped_after = 0;   ///< the same after the repair
  FieldCut cut;                   ///< the cut graph and the combed field the map follows
  Eigen::Index integer_variables = 0;  ///< seam translations and singular coordinates rounded
  double rounding_residual = 0.0;     ///< max |y − round(y)| over the integer variables when each was rounded
  int repair_rounds = 0;              ///< stiffening rounds run
  Eigen::Index feature_edges = 0;     ///< feature edges held on an integer iso-line (sharp_angle_degrees)
  Eigen::Index separations = 0;       ///< pairs of feature-line / cone corners kept on distinct iso-lines by the rounding
  Eigen::Index separation_conflicts = 0;  ///< roundings where no nearby integer kept every separation (the nearest taken)
  Eigen::Index released_feature_edges = 0;  ///< feature edges left free because the map folded with them held
  int release_rounds = 0;                   ///< re-solves with feature edges near the flips released
  int rerounded_integers = 0;  ///< integer unknowns moved by ±1 after the repair, where flips were left (step 4)
  /// flips of the map solved with every feature edge released, solved where flips were left with
  /// the features held (−1: not solved); no release round is run unless it is below those flips
  int flipped_unconstrained = -1;
  double target_edge_length = 0.0;  ///< the grid unit used, in input units (after the calibration to target_quads)
  /// the range of the grid's log scale λφ over the faces (MiqOptions::conformal_scale; 0, 0 without)
  double log_scale_min = 0.0, log_scale_max = 0.0;
};

/// A seamless integer-grid map of (V, F) following the cross field `theta` (#F angles, as
/// CrossField::theta). The surface is cut to a disk through the singularities (cut_graph); the
/// map minimizes Σ_f w_f A_f (‖∇u − s·u*_f‖² + ‖∇v − s·v*_f‖²), u*_f and v*_f = n × u*_f the
/// combed cross, s = 1 / target_edge_length, subject to the transition functions across the
/// seams — the two sides' (u, v) differ by a rotation by k·π/2 (the seam's period jump) and a
/// translation — with the translations and the singular vertices' coordinates integers. The
/// linear constraints are eliminated (each seam copy expressed through its twin), the reduced
/// system is factorized once by CHOLMOD, and the integers are rounded greedily, closest first,
/// each rounding updating all unrounded ones exactly through the integer block of the inverse
/// (no refactorization per rounding). Triangles whose map is flipped or degenerate are
/// stiffened (w_f ×= stiffening, neighbours too) and the map re-solved with the integers kept.
/// With sharp_angle_degrees > 0 the feature edges the combed cross follows are held on integer
/// iso-lines; integer corners (feature-line corners, cones) within a quad edge of each other on
/// different iso-lines are rounded onto distinct integers in their order, and where flips remain
/// the feature edges near them are released and the map solved again (up to six times, kept
/// when it has fewer flips; MiqResult::released_feature_edges counts them).
/// V: #V×3, F: #F×3. Result: per-corner (u, v); across every seam edge the two sides agree up to
/// a rotation by k·π/2 and an integer translation; singular vertices sit on integer points.
/// \pre a clean, connected, oriented 2-manifold.
/// \throw InputError as cross_field, for a theta that is not #F finite values, or a target edge
///        length that is not finite; SolverError if CHOLMOD fails; Cancelled from `progress`.
/// Complexity: one sparse factorization and one solve per integer variable (blocked), one
/// factorization per repair round, O(N³) for the greedy rounding of N integer variables.
MiqResult miq(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta, const MiqOptions& options = {},
              const Progress& progress = {});

}  // namespace meshsmith::quadrangulation
