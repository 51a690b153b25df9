#pragma once
/// \file lscm.h
/// Least-squares conformal maps (§5.1.2; Lévy, Petitjean, Ray & Maillot 2002): minimize
/// Σ_Δ A_Δ ‖∇v − R₉₀ ∇u‖², which equals twice the conformal energy E_C = E_D − A (Dirichlet
/// energy minus the signed area of the image, Desbrun, Meyer & Alliez 2002), with a free
/// boundary. Two pinned vertices make the minimizer unique; the spectral variant (Mullen,
/// Tong, Alliez & Desbrun 2008) needs none: it takes the smallest non-trivial generalized
/// eigenvector of E_C against a boundary mass matrix.
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/distortion.h>

#include <Eigen/SparseCore>

#include <vector>

namespace meshsmith::parametrization {

/// Vertices held at given parameter positions.
struct PinnedVertices {
  std::vector<int> indices;      ///< #p distinct vertex indices
  geometry::ParameterMatrix uv;  ///< #p×2 their positions
};

/// The 2#V×2#V symmetric positive semi-definite matrix Q of the conformal energy, unknowns
/// stacked as (u_0..u_{n−1}, v_0..v_{n−1}): xᵀQx = 2 E_C(u, v) = Σ_ij −L_ij ((u_i−u_j)² + (v_i−v_j)²)/2
/// − Σ_{boundary sides i→j} (u_i v_j − u_j v_i), with L the cotangent Laplacian. Equals the Q
/// returned by libigl's lscm (−repdiag(L, 2) − 2·vector_area_matrix).
/// V: #V×3, F: #F×3. Columns are assembled directly (no triplets), rows sorted.
/// \throw InputError as geometry::cotan_laplacian.
Eigen::SparseMatrix<double> conformal_energy_matrix(const VertexRef& V, const FaceRef& F);

/// The two pins used when none are given: on the longest boundary loop, the far end of a double
/// sweep for the largest 3D distance (a vertex a farthest from the loop's first vertex, then b
/// farthest from a), pinned at (0, 0) and (|p_a − p_b|, 0) so the map has the surface's scale.
/// \pre as lscm. \throw InputError as lscm.
PinnedVertices default_lscm_pins(const VertexRef& V, const FaceRef& F);

/// LSCM with pinned vertices (at least two, at two different positions). V: #V×3, F: #F×3.
/// Returns #V×2. The map keeps the faces' orientation (triangles counter-clockwise), and equals
/// libigl's lscm(V, F, b, bc) for the same pins.
/// \pre a clean, connected, oriented 2-manifold with at least one boundary loop (a closed mesh has
///      no free boundary: cut it with cut_to_disk).
/// \throw InputError naming the problem; SolverError if the system is singular.
geometry::ParameterMatrix lscm(const VertexRef& V, const FaceRef& F, const PinnedVertices& pinned);

/// LSCM with default_lscm_pins. \pre (V, F) is a topological disk.
geometry::ParameterMatrix lscm(const VertexRef& V, const FaceRef& F);

/// Spectral conformal parametrization (free boundary, no pins): the eigenvector x of
/// Q x = λ B x with the smallest λ among those B-orthogonal to the translations, B the lumped
/// boundary length matrix (half the length of each adjacent boundary edge, for u and v alike).
/// Solved with Spectra (shift-and-invert Lanczos, Q − σB factorized once by CHOLMOD). The result
/// is centred (boundary-length-weighted) at the origin, scaled so its area equals the surface
/// area and oriented counter-clockwise; it is unique up to a rotation.
/// \pre as lscm(V, F, pinned). \throw InputError naming the problem; SolverError if the
///      eigensolver does not converge.
geometry::ParameterMatrix lscm_spectral(const VertexRef& V, const FaceRef& F);

}  // namespace meshsmith::parametrization
