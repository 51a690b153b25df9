#pragma once
/// \file abf.h
/// Angle-Based Flattening (§5.1.3): free-boundary parametrization of a disk-topology triangle
/// mesh that optimizes the angles of the flattened triangles, then lays them out in the plane.
///
/// ABF: Sheffer, de Sturler, "Parameterization of faceted surfaces for meshing using angle-based
/// flattening", Engineering with Computers 17, 2001.
/// ABF++: Sheffer, Lévy, Mogilnitskaya, Bogart, "ABF++: fast and robust angle based flattening",
/// ACM Transactions on Graphics 24(2), 2005.
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>

#include <vector>

namespace meshsmith::parametrization {

/// #F by 3 angles (radians), column k the angle at corner k of the face (at vertex F(f, k)).
using AngleMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using AngleRef = Eigen::Ref<const AngleMatrix>;

/// How each Newton step of ABF is solved; both give the same iterates (to round-off).
enum class AbfMethod {
  AbfPlusPlus,  ///< the reduced system of ABF++ (§3 of the 2005 paper), factorized by CHOLMOD
  Abf,          ///< the full KKT system of ABF, factorized by sparse LU in a block order (for comparison)
};

struct AbfOptions {
  AbfMethod method = AbfMethod::AbfPlusPlus;
  int max_iterations = 30;     ///< Newton iterations at most (≥ 1)
  double tolerance = 1e-8;     ///< stop when the constraint residual (∞-norm) is at most this
  /// The optimal angles β are clamped to [minimum_angle, π − minimum_angle] (radians), so that
  /// needle triangles get finite weights 1/β² and sin β > 0.
  double minimum_angle = 1e-4;
};

struct AbfResult {
  geometry::ParameterMatrix uv;       ///< #V×2 coordinates; every triangle counter-clockwise when bijective
  AngleMatrix angles;                 ///< #F×3 optimized angles α (radians)
  AngleMatrix optimal_angles;         ///< #F×3 the targets β (3D angles rescaled, then clamped)
  int iterations = 0;                 ///< Newton iterations taken
  /// Final constraint residual, ∞-norm over: |Σ_t α − π| per triangle, |Σ_v α − 2π| per interior
  /// vertex, |Σ log sin α_next − Σ log sin α_prev| per interior vertex (the wheel condition).
  double residual = 0.0;
  /// Residual before the first step ([0]) and after each iteration (size iterations + 1).
  std::vector<double> residual_history;
};

/// Minimizes Σ_corners (α − β)² / β² over the angles α of the flattened mesh subject to
///  - the triangle condition: the three angles of each triangle sum to π;
///  - the vertex condition: the angles around each interior vertex sum to 2π;
///  - the wheel condition: Π sin α_next / Π sin α_prev = 1 around each interior vertex (α_next,
///    α_prev: the angles at the next and previous corners of each triangle of the vertex), so
///    the edge lengths the angles imply close up around the vertex;
/// by Newton's method on the Lagrangian, starting from α = β, λ = 0, with the Hessian in α
/// approximated, as in ABF++ §3, by the energy's diagonal 2/β² (the log-sine terms' curvature,
/// also diagonal, is left out: it can make the block indefinite). β are the 3D angles, those
/// around an interior vertex rescaled to sum to 2π. Each step is solved as `options.method`
/// says (both give the same iterates): ABF++ eliminates the diagonal angle block, then the
/// diagonal triangle block, and
/// factorizes the remaining (2 #interior vertices)² SPD system with CHOLMOD, its symbolic
/// analysis done once. The angles are then laid out by uv_from_angles (angle_reconstruction.h),
/// pinning the two boundary vertices farthest apart, and scaled about the first pin (at the
/// origin) so that the UV area equals the surface area (a developable surface comes out isometric).
///
/// V: #V×3 positions, F: #F×3 triangles. Progress is reported once per Newton iteration (stage
/// "ABF++ Newton iteration k, residual r"), around each factorization of plain ABF, and for the
/// layout; a factorization itself cannot be interrupted (about 0.5 s at 70k faces).
/// \pre the mesh is a topological disk: one connected component, manifold, oriented, one
///      boundary loop, every vertex used, no face of zero area (needle faces are fine: their β
///      are clamped to minimum_angle).
/// \throw InputError naming the problem (parametrization's shared input checks): closed mesh
///        (cut it first with cut_to_disk), several boundary loops or components, non-manifold
///        or non-oriented, unreferenced vertex, a face with a repeated vertex or of zero area
///        (its index), bad options.
/// \throw SolverError if the residual is still above the tolerance after max_iterations (the
///        message gives it), or a factorization fails.
/// \throw Cancelled if the progress callback asks to stop.
AbfResult abf(const VertexRef& V, const FaceRef& F, const AbfOptions& options = {},
              const Progress& progress = {});

}  // namespace meshsmith::parametrization
