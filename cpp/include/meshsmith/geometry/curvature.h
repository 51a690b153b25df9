#pragma once
/// \file curvature.h
/// Discrete curvatures of triangle meshes (§1.2.3–1.2.4): Gaussian curvature as angle defect,
/// mean curvature from the cotangent Laplacian, principal curvatures and directions.
///
/// Sign convention: normals point out of a closed counter-clockwise mesh, and curvature is
/// positive where the surface bends away from its normal (a sphere with outward normals has
/// H = 1/r, K = 1/r², k1 = k2 = 1/r).
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/laplacian.h>

#include <Eigen/Core>

namespace meshsmith::geometry {

/// What the Gaussian curvature of a boundary vertex is measured against.
enum class BoundaryAngle {
  full_turn,  ///< 2π − Σθ everywhere, boundary vertices included (libigl's gaussian_curvature)
  half_turn,  ///< π − Σθ at boundary vertices: the boundary's discrete geodesic curvature is
              ///< counted, so Σ_i K_i = 2πχ holds on surfaces with boundary too (Gauss–Bonnet)
};

struct GaussianCurvatureOptions {
  BoundaryAngle boundary = BoundaryAngle::full_turn;
  /// false: integrated curvature (the angle defect itself); true: pointwise curvature, the
  /// defect divided by the vertex area of `area` (0 where that area is 0).
  bool pointwise = false;
  MassMatrixType area = MassMatrixType::voronoi;
};

/// Discrete Gaussian curvature as angle defect (§1.2.4: K = (2π − Σ_i α_i) / A), with the
/// interior angles Σθ of the triangles at each vertex. Integrated by default (equals libigl's
/// gaussian_curvature), so Σ K = 2πχ on closed meshes. A vertex on a boundary edge (an edge of
/// exactly one triangle) is a boundary vertex. A vertex used by no face has Σθ = 0, so its
/// integrated value is 2π (as libigl), and its pointwise value 0.
/// V: #V×3, F: #F×3. Returns #V values.
/// \throw InputError if V or F is empty, V holds NaN/Inf or F indexes outside [0, #V).
Eigen::VectorXd gaussian_curvature(const VertexRef& V, const FaceRef& F,
                                   const GaussianCurvatureOptions& options = {});

struct MeanCurvature {
  Eigen::VectorXd H;  ///< #V signed mean curvature, H = ½(k1 + k2); > 0 on a sphere
  VertexMatrix Hn;    ///< #V×3 mean-curvature normal Hn = −½ M⁻¹ L V (points outward on a sphere)
};

/// Mean curvature from the cotangent Laplacian (§1.2.4: L(f) = Hn): Δx = −2Hn, discretised as
/// Hn = −½ M⁻¹ L V with L = cotan_laplacian and M = mass_matrix(V, F, area). The sign of H is
/// that of Hn · n with n the angle-weighted vertex normal. Vertices with zero area (unused by
/// any face) get H = 0 and Hn = 0. At boundary vertices L V has a boundary term, so the values
/// there do not estimate the surface's curvature.
/// \throw InputError as gaussian_curvature.
MeanCurvature mean_curvature(const VertexRef& V, const FaceRef& F,
                             MassMatrixType area = MassMatrixType::voronoi);

/// How principal curvatures are estimated.
enum class PrincipalCurvatureMethod {
  /// A height function z = a x² + b xy + c y² + d x + e y fitted by least squares, in the
  /// tangent frame of the angle-weighted vertex normal, to the vertex's 2-ring (grown to at most
  /// 4 rings until it has 8 neighbours); k1, k2 and the directions are the eigenpairs of its
  /// shape operator I⁻¹ II at the vertex. Converges as O(h²) on spheres and tori, regular or not.
  quadric_fit,
  /// Per-face second fundamental forms fitted to the change of vertex normals along the edges,
  /// averaged at each vertex in its tangent frame with mixed-Voronoi corner weights
  /// (Rusinkiewicz 2004). O(h²) on regular meshes, but it inherits the O(h) error of vertex
  /// normals on irregular ones (≈2% on subdivided icospheres, whatever the resolution).
  shape_operator,
  /// k = H ± sqrt(max(H² − K, 0)) from the cotangent mean curvature and the pointwise angle
  /// defect (Meyer et al. 2003); directions from the shape operator above. Exact umbilics
  /// (spheres) converge as O(h²), but the square root amplifies errors where k1 ≈ k2.
  mean_gaussian,
};

struct PrincipalCurvatures {
  Eigen::VectorXd k1;  ///< #V maximal curvature
  Eigen::VectorXd k2;  ///< #V minimal curvature, k2 ≤ k1
  VertexMatrix d1;     ///< #V×3 unit direction of k1, tangent to the vertex normal
  VertexMatrix d2;     ///< #V×3 unit direction of k2 (= n × d1)
};

/// Principal curvatures k1 ≥ k2 and their directions at every vertex (§1.2.1: eigen-
/// decomposition of the second fundamental form). libigl's principal_curvature fits quadrics
/// over a neighbourhood of radius 5 (Panozzo et al. 2010): smoother on noisy scans, but on
/// coarse smooth meshes it errs by ≈10% (1280-face icosphere) and ≈5% (128×64 torus), where
/// quadric_fit errs by ≈2% and ≈1%; the estimators here are local (1-ring or 2-ring).
/// Vertices without a usable neighbourhood (no normal, fewer than 5 neighbours, degenerate
/// faces only) get zero curvatures and zero directions.
/// \throw InputError as gaussian_curvature.
PrincipalCurvatures principal_curvatures(
    const VertexRef& V, const FaceRef& F,
    PrincipalCurvatureMethod method = PrincipalCurvatureMethod::quadric_fit);

}  // namespace meshsmith::geometry
