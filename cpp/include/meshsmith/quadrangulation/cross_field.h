#pragma once
/// \file cross_field.h
/// Cross fields (4-RoSy fields) on triangle meshes, their period jumps and singularities
/// (§5.2.2 step 1 "Cross field": a smooth per-face cross minimizing Σ (θ_i + κ_ij + π/2·p_ij − θ_j)²;
/// Bommes, Zimmer & Kobbelt 2009 "Mixed-integer quadrangulation"; solved in the power-4
/// representation of Knöppel, Crane, Pinkall & Schröder 2013 "Globally optimal direction fields").
///
/// Conventions. Face f's frame: e1 = the unit vector along its reference edge F(f,0) → F(f,1),
/// n = the unit normal of the counter-clockwise triangle, e2 = n × e1. A cross is an angle θ_f
/// against e1 (it stands for the four directions θ_f + k·π/2). Across an interior edge from
/// face f to face g, parallel transport (the Levi-Civita connection of the unfolded pair) maps
/// the angle θ in f's frame to θ + κ_fg in g's frame; the period jump p_fg is the integer with
/// θ_g − θ_f − κ_fg − p_fg·π/2 ∈ [−π/4, π/4).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::quadrangulation {

/// While an instance lives, the chapter's functions called on the same (V, F) as the call
/// before (compared entry by entry) share its checked mesh, face frames and edge adjacency
/// instead of building them again: `quadrangulate` calls a dozen of them on one mesh (pmp-bunny,
/// 69,666 faces: 12 builds of ~20 ms, 0.2 s of its 2.6 s). Instances nest (one per thread of
/// work is enough); when the last is destroyed the shared mesh is freed, so nothing stays in
/// memory between calls made outside one.
class SharedFieldMesh {
 public:
  SharedFieldMesh();
  ~SharedFieldMesh();
  SharedFieldMesh(const SharedFieldMesh&) = delete;
  SharedFieldMesh& operator=(const SharedFieldMesh&) = delete;
};

/// What the cross field follows besides smoothness.
enum class FieldAlignment {
  curvature,  ///< principal curvature directions where the surface is anisotropic (soft), the boundary (hard)
  smooth,     ///< the smoothest field (smallest eigenvector of the connection Laplacian); no boundary constraint
  boundary,   ///< the boundary (hard), smooth inside
};

/// How the period jumps are settled after the power-4 solve.
enum class FieldRounding {
  none,     ///< the power-4 field as solved (its jumps read off the angles)
  resolve,  ///< the power-4 field's jumps kept, the angles re-solved for the angle energy E
  greedy,   ///< greedy mixed-integer rounding of the jumps (Bommes et al. 2009), then the angles re-solved
};

struct CrossFieldOptions {
  FieldAlignment align = FieldAlignment::curvature;
  /// FieldRounding::none keeps today's power-4 field (the default).
  FieldRounding rounding = FieldRounding::none;
  /// Interior edges whose dihedral angle (between the face normals) exceeds this many degrees
  /// are features: their two faces are constrained to the edge direction. ≤ 0: no features.
  double sharp_angle_degrees = 0.0;
  /// User constraints: face constraint_faces[k] gets one direction of its cross along
  /// constraint_directions.row(k) (projected into the face plane).
  std::vector<int> constraint_faces;
  VertexMatrix constraint_directions;
  /// Weight of the curvature alignment against smoothness (FieldAlignment::curvature). 1e-3:
  /// at 1e-2 the pull of noisy principal directions outweighed smoothness on bumpy-cube (104
  /// singularities instead of 56, 81 MIQ flips instead of 26 at 3,000 quads).
  double curvature_weight = 1e-3;
  /// Weight of the crease alignment (FieldAlignment::curvature): each interior edge pulls its two
  /// faces' crosses towards its direction with weight crease_weight · w_e · (1 − cos β), β the
  /// dihedral angle — the extrinsic misfit of crosses that do not follow a fold. 0: none. 0.2:
  /// fandisk's quads follow its creases without sharp_angle (see quadrangulate's docstring).
  double crease_weight = 0.2;
};

/// The per-edge data of a cross field: one row per unique edge (topology::edges order).
struct FieldEdges {
  EdgeMatrix edges;             ///< #E×2 vertex pairs (i < j)
  EdgeMatrix faces;             ///< #E×2 the faces on each side (f, g), f's side runs i → j; g = −1 on a boundary edge
  Eigen::VectorXd connection;   ///< #E κ_fg in (−π, π] (0 on a boundary edge)
  Eigen::VectorXi period_jumps; ///< #E p_fg in {−1, 0, 1, 2} (0 on a boundary edge)
};

struct CrossField {
  Eigen::VectorXd theta;      ///< #F angle of the cross against each face's reference edge, in [0, π/2)
  VertexMatrix directions;    ///< #F×3 unit vector of the cross at angle theta (the other three: its rotations about n)
  FieldEdges edges;           ///< connection angles and period jumps
  Eigen::Index constrained_faces = 0;  ///< faces held by a hard constraint (boundary, feature, user)
  /// The angle energy E of theta (see cross_field), and of the power-4 field before any rounding
  /// (equal for FieldRounding::none). Normalized units: invariant to scaling the mesh.
  double energy = 0.0, initial_energy = 0.0;
  /// Interior edges whose period jump differs from the power-4 field's, both in the gauge of the
  /// power-4 angles combed along the rounding's forest (the reduced jumps of `edges` change with
  /// every angle that wraps around 0): how many jumps the rounding changed. 0 for none.
  Eigen::Index changed_jumps = 0;
};

struct Singularities {
  std::vector<int> vertices;  ///< the singular vertices, increasing
  std::vector<int> indices;   ///< their indices in quarter turns (+1: valence-3 corner, −1: valence 5)
};

/// A cross field on (V, F) (§5.2.2 step 1). The power-4 complex numbers z_f = e^{4iθ_f}
/// minimize Σ_edges w_e |z_g − e^{4iκ_fg} z_f|² (w_e = |e|² / (A_f + A_g)), plus the soft
/// curvature term Σ_f λ·A_f/Ā·a_f |z_f − z*_f|² for align = curvature (z*_f from the principal
/// direction d1 of the vertices, a_f ∈ [0, 1] the agreement-weighted anisotropy |k1 − k2| /
/// (|k1| + |k2|)), with hard constraints (boundary edges for align = curvature | boundary;
/// feature edges above `sharp_angle_degrees`; user constraints) eliminated. Unconstrained
/// smooth fields are the smallest eigenvector of the Hermitian connection Laplacian (inverse
/// iteration, CHOLMOD); constrained or curvature-aligned ones one sparse SPD solve. Where
/// curvature gives no anisotropic face (a sphere), align = curvature falls back to smooth.
/// The angle energy of the result is E(θ) = Σ_e w_e r(θ_g − θ_f − κ_fg)² + Σ_f μ_f r(θ_f − θ*_f)²
/// (r: the residual mod π/2 in [−π/4, π/4), i.e. the period jumps p_fg and the alignment's
/// quarter turns taken nearest; μ_f = λ·A_f/Ā·a_f, the power-4 terms' second-order
/// expansion ÷ 16). options.rounding: FieldRounding::none returns the power-4 field;
/// FieldRounding::resolve keeps its jumps and minimizes E over the free angles (one real SPD
/// solve); FieldRounding::greedy (Bommes et al. 2009 §4, as CoMISo) fixes the jumps of a dual
/// spanning forest rooted at the hard faces (the gauge), starts the other jumps as reals from
/// the power-4 field (its convex relaxation, Knöppel et al. 2013), rounds them greedily — all
/// those within 0.1 of an integer at once, then one at a time the closest, each followed by a
/// few Gauss–Seidel sweeps of the angles around it — and solves the angles once with all
/// jumps fixed; if that E is above the resolve candidate's (same factorization), the resolve
/// candidate is returned (then changed_jumps counts only the edges whose residual left
/// [−π/4, π/4) in the re-solve). Both never raise E above the power-4 field's; hard constraints stay exact.
/// V: #V×3, F: #F×3.
/// \pre a clean, connected, oriented 2-manifold (parametrization::detail::check_mesh).
/// \throw InputError naming the offending face, vertex or edge for non-manifold or otherwise
///        bad input (and `meshsmith clean`), for a constraint face out of range, or a
///        direction that is not finite or is normal to its face; SolverError if CHOLMOD fails.
/// Complexity: one factorization of a #F × #F sparse complex Hermitian matrix; resolve and
/// greedy add one of a real #F × #F SPD matrix (greedy's roundings are local: O(#E) overall).
CrossField cross_field(const VertexRef& V, const FaceRef& F, const CrossFieldOptions& options = {},
                       const Progress& progress = {});

/// The connection angles κ and, for the per-face angles `theta` (#F), the period jumps of
/// every edge of (V, F).
/// \throw InputError as cross_field, or if theta has the wrong size or is not finite.
FieldEdges field_edges(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta);

/// Per-face angles θ of (#F×3) direction vectors in the face frames (the inverse of
/// CrossField::directions).
/// \throw InputError naming the face if a direction is not finite or is normal to its face.
Eigen::VectorXd field_angles(const VertexRef& V, const FaceRef& F, const VertexRef& directions);

/// #F×3 unit directions of the angles `theta` in the face frames.
VertexMatrix field_directions(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta);

/// The singular vertices of the cross field `theta` (#F) and their indices in quarter turns
/// (§5.2.2: the index of an interior vertex is (K_v + Σ δ)/(π/2) with K_v the angle defect and δ
/// the field's rotation against parallel transport across each edge of its fan,
/// counter-clockwise; at a boundary vertex K_v = π − Σ angles and the turn from the first
/// boundary edge to the field and from the field to the last boundary edge count). The indices
/// sum to 4χ exactly on a closed mesh, and on a mesh with boundary when the field is aligned to
/// the boundary (Poincaré–Hopf).
/// \throw InputError as field_edges.
Singularities singularities(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta);

/// The angles minimizing Σ_e w_e (θ_g − θ_f − κ_e − π/2·p_e)² (w_e as in cross_field) with the
/// period jumps p given per edge (#E, field_edges' order, unreduced) and the `held` faces (#F,
/// nonzero: held) kept at theta; a pull of 10⁻⁹ · mean(w) towards theta makes a free region
/// without a held face unique. One CHOLMOD factorization (merge_singularities' re-solve).
/// Returns the angles reduced to [0, π/2), with their period jumps and singularities (one mesh
/// set-up for the three).
/// \throw InputError as field_edges, for jumps or held of the wrong size; SolverError if CHOLMOD fails.
struct ResolvedAngles {
  Eigen::VectorXd theta;         ///< #F in [0, π/2)
  Eigen::VectorXi period_jumps;  ///< #E, as FieldEdges::period_jumps
  Singularities singularities;
};
ResolvedAngles resolve_angles(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta,
                              const std::vector<int>& jumps, const std::vector<char>& held);

}  // namespace meshsmith::quadrangulation
