#pragma once
/// \file distortion.h
/// Distortion of a piecewise-linear parametrization, per triangle and per vertex (§1.2.2 the
/// Jacobian, first fundamental form and its singular values; §1.2.4 per-triangle stretch; §5
/// isometric / conformal / equiareal maps, s_Δ = sqrt((σ1² + σ2²) / 2) and its area-weighted
/// per-vertex average). Stretch follows Sander, Snyder, Gortler, Hoppe, "Texture mapping
/// progressive meshes", SIGGRAPH 2001.
#include <meshsmith/core/types.h>

#include <cstdint>
#include <vector>

namespace meshsmith::geometry {

/// #V by 2 parameter (UV) positions.
using ParameterMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using ParameterRef = Eigen::Ref<const ParameterMatrix>;
/// #F by 4 row-major 2×2 Jacobians: row f holds (J00, J01, J10, J11).
using JacobianMatrix = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;
/// #F by 2 singular values (σ1 ≥ σ2 ≥ 0).
using SingularValueMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Per-triangle and per-vertex distortion measures of the map UV → surface.
///
/// The map of triangle f is the affine map from its parameter triangle (UV rows of its corners)
/// onto its 3D triangle. Its Jacobian J (2×2) is expressed in the orthonormal frame (x, y) of
/// the 3D triangle: x along v1 − v0, y = n × x with n the unit normal (v1 − v0) × (v2 − v0), so
/// the 3D triangle is counter-clockwise in its own frame and det J < 0 exactly when the UV
/// triangle is clockwise (flipped). JᵀJ is the first fundamental form I of §1.2.2; σ1 ≥ σ2 are
/// the singular values of J (square roots of the eigenvalues of I).
///
/// Measures (each 1 for an isometry):
///  - isometric: symmetric Dirichlet energy normalized to 1 at isometries,
///    (σ1² + σ2² + σ1⁻² + σ2⁻²) / 4 (≥ 1, = 1 iff σ1 = σ2 = 1);
///  - conformal: σ1 / σ2 (≥ 1, = 1 iff the map preserves angles);
///  - area: σ1 σ2 = |det J| = 3D area / UV area (= 1 iff equiareal);
///  - stretch_l2: s_Δ = sqrt((σ1² + σ2²) / 2) (Sander et al.'s L2 stretch, §5);
///  - stretch_linf: σ1 (Sander et al.'s L∞ stretch).
///
/// Degenerate triangles:
///  - UV triangle of zero signed area (exactly) with a 3D triangle of positive area: the map
///    does not exist; J and σ1, σ2 are +inf, every measure is +inf, the face is listed in
///    `degenerate_parameter_faces` (so vertex averages and the global stretch touching it are
///    +inf too, as Sander's stretch is).
///  - 3D triangle of zero area (repeated or collinear corners): J is computed in a frame along
///    its longest non-zero edge (J = 0 if all corners coincide), σ2 = 0, so conformal and
///    isometric are +inf and area is 0. Its weight in every average is its area, 0, so it is
///    left out of the averages; it is listed in `degenerate_surface_faces` and never flipped.
struct TriangleDistortion {
  JacobianMatrix jacobians;                 ///< #F×4, (J00, J01, J10, J11)
  SingularValueMatrix singular_values;      ///< #F×2, σ1 ≥ σ2 ≥ 0
  Eigen::VectorXd isometric;                ///< #F, (σ1² + σ2² + σ1⁻² + σ2⁻²) / 4
  Eigen::VectorXd conformal;                ///< #F, σ1 / σ2
  Eigen::VectorXd area;                     ///< #F, σ1 σ2
  Eigen::VectorXd stretch_l2;               ///< #F, sqrt((σ1² + σ2²) / 2)
  Eigen::VectorXd stretch_linf;             ///< #F, σ1
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1> flipped;  ///< #F, 1 where det J < 0
  Eigen::VectorXd surface_areas;            ///< #F, 3D triangle areas (the weights)
  Eigen::VectorXd parameter_areas;          ///< #F, signed UV triangle areas (< 0: flipped)

  /// Per-vertex area-weighted averages Σ_{f∋i} A_f m_f / Σ_{f∋i} A_f (§5, s_{p_i}); NaN for a
  /// vertex with no incident triangle of positive 3D area (unreferenced, or only degenerate).
  Eigen::VectorXd vertex_isometric, vertex_conformal, vertex_area, vertex_stretch_l2,
      vertex_stretch_linf;

  /// sqrt(Σ A_f s_f² / Σ A_f) over the faces of positive 3D area (1 for an isometry).
  double global_stretch_l2 = 0.0;
  /// Sander et al.'s scale-invariant L2 stretch: global_stretch_l2 · sqrt(Σ |UV area| / Σ A_f);
  /// 1 for any map that is an isometry up to one uniform scale; +inf when every UV triangle has
  /// zero area (no scale undoes that).
  double normalized_global_stretch_l2 = 0.0;
  /// max_f σ1 over the faces of positive 3D area.
  /// (The three global values are NaN when no face has positive 3D area: nothing to average.)
  double global_stretch_linf = 0.0;

  std::vector<int> flipped_faces;               ///< faces with det J < 0, ascending
  std::vector<int> degenerate_parameter_faces;  ///< UV area 0, 3D area > 0 (infinite distortion)
  std::vector<int> degenerate_surface_faces;    ///< 3D area 0 (weight 0)
};

/// Distortion of the parametrization UV of the mesh (V, F).
/// V: #V×3 surface positions, F: #F×3 triangles, UV: #V×2 parameter positions.
/// Deterministic: per-face work runs in parallel (TBB), sums run in a fixed order.
/// \pre validate_mesh(V, F) passes; UV has #V rows, all finite.
/// \throw InputError if the precondition fails (the message names the offending row).
TriangleDistortion triangle_distortion(const VertexRef& V, const FaceRef& F, const ParameterRef& UV);

}  // namespace meshsmith::geometry
