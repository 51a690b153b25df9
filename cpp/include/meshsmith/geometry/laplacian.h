#pragma once
/// \file laplacian.h
/// Discrete Laplace operators and mass matrices of triangle meshes (§1.2.4 "Discrete
/// Curvature", L = Hn = Σ ω_i (p_i − p); §3.0.2 uniform, cot and mean-value weights).
///
/// Sign convention (libigl's): every Laplacian L here has L_ij = w_ij, the edge weight, off the
/// diagonal and L_ii = −Σ_j L_ij, so L·1 = 0 and the cotangent Laplacian is negative
/// semi-definite.
/// Matrices are #V×#V, column-major (CSC) with sorted row indices and no duplicate entries;
/// they are assembled column by column (in parallel, deterministically) without triplets.
#include <meshsmith/core/types.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace meshsmith::geometry {

/// Cotangent Laplacian (§3.0.2 cot-weights; Pinkall & Polthier 1993, Meyer et al. 2003):
/// L_ij = ½ (cot α_ij + cot β_ij) for every edge ij, α, β the angles opposite the edge
/// (one angle on a boundary edge), L_ii = −Σ_j L_ij. Symmetric, negative semi-definite when all
/// weights are positive; has linear precision (L·f = 0 at interior vertices of a planar mesh for
/// f linear). Equals libigl's cotmatrix to round-off.
/// V: #V×3, F: #F×3. Returns #V×#V. A degenerate triangle (twice its area ≤ 8·ε·(longest
/// edge)²) contributes nothing: its cotangents are set to zero instead of ±∞.
/// \throw InputError if V or F is empty, V holds NaN/Inf or F indexes outside [0, #V).
Eigen::SparseMatrix<double> cotan_laplacian(const VertexRef& V, const FaceRef& F);

/// Intrinsic Delaunay cotangent Laplacian (§3.0.2 "Delaunay cot-weights"; Bobenko & Springborn
/// 2007, Fisher et al. 2007): the cotangent Laplacian of the intrinsic Delaunay triangulation of
/// the mesh's metric. Edges whose cot weight is negative (α_ij + β_ij > π) are flipped
/// intrinsically, on edge lengths only (the vertices and the surface's shape do not change), until
/// every edge is locally Delaunay; the Laplacian is assembled from the flipped triangulation, so
/// an intrinsic edge may join two vertices that share no mesh edge. A boundary edge whose one
/// opposite angle is obtuse (which no flip changes) is split intrinsically at the foot of that
/// angle's altitude (two right triangles), and each inserted vertex is lumped back onto the
/// split edge's ends (its value their linear interpolant, its weights shared between them in the
/// same proportions, the cross term that made the edge's weight negative dropped), so the
/// result stays #V×#V. Every off-diagonal entry is ≥ 0, interior and boundary (weights within
/// 1e-12·(1 + |cot α| + |cot β|) below zero, co-circular quads, are taken as 0); symmetric, rows
/// summing to zero, negative semi-definite; linear precision at every interior vertex (L·f = 0
/// there on a planar mesh for f linear). Equals cotan_laplacian on a mesh that is already
/// Delaunay with no obtuse angle opposite a boundary edge, and libigl's
/// intrinsic_delaunay_cotmatrix to round-off away from split edges (libigl keeps their negative
/// weights).
/// V: #V×3, F: #F×3. Returns #V×#V, the same pattern conventions as cotan_laplacian. Degenerate
/// triangles (a zero-length edge) contribute nothing and their edges are not flipped or split.
/// \pre the mesh is edge-manifold and consistently oriented (every interior edge has two faces
///      that traverse it in opposite directions).
/// \throw InputError as cotan_laplacian, or naming an edge with more than two faces or an
///        inconsistently oriented one; SolverError if the flips do not terminate (never seen).
/// Complexity: O(#F + flips + splits); a flip or split is O(1), the elimination O(splits).
Eigen::SparseMatrix<double> intrinsic_delaunay_cotan_laplacian(const VertexRef& V, const FaceRef& F);

/// Graph (uniform-weight) Laplacian (§3.0.2 uniform weights): L_ij = 1 for every edge ij,
/// L_ii = −deg(i). With `normalized` the rows are divided by the vertex degree (L_ij = 1/|N1(i)|,
/// L_ii = −1: the umbrella operator; not symmetric). A vertex used by no face has a zero row and
/// column (its diagonal entry is stored, as 0).
/// F: #F×3, n: #V (≥ every index of F + 1). Returns n×n.
/// \throw InputError if F is empty, n < 1 or an index of F is outside [0, n).
Eigen::SparseMatrix<double> uniform_laplacian(const FaceRef& F, Eigen::Index n, bool normalized = false);

/// Mean-value Laplacian (§3.0.2 mean value weights; Floater 2003): L_ij = (tan(α_ij/2) +
/// tan(β_ij/2)) / |p_j − p_i|, where α_ij, β_ij are the angles at vertex i in the two triangles
/// sharing edge ij (one on a boundary edge); L_ii = −Σ_j L_ij. Weights are positive for any
/// triangle; the operator has linear precision but is NOT symmetric (row i holds i's weights).
/// V: #V×3, F: #F×3. Returns #V×#V. Degenerate triangles and zero-length edges contribute nothing.
/// \throw InputError as cotan_laplacian.
Eigen::SparseMatrix<double> mean_value_laplacian(const VertexRef& V, const FaceRef& F);

/// Lumped (diagonal) mass matrices.
enum class MassMatrixType {
  barycentric,  ///< a third of the area of every incident triangle (libigl MASSMATRIX_TYPE_BARYCENTRIC)
  voronoi,      ///< mixed Voronoi area (Meyer et al. 2003): the Voronoi cell inside non-obtuse
                ///< triangles; for an obtuse triangle half its area to the obtuse corner and a
                ///< quarter to each other corner (libigl MASSMATRIX_TYPE_VORONOI)
};

/// The area associated with every vertex (the diagonal of mass_matrix). V: #V×3, F: #F×3.
/// Returns #V values, summing to the surface area; 0 for vertices used by no face.
/// \throw InputError as cotan_laplacian.
Eigen::VectorXd vertex_areas(const VertexRef& V, const FaceRef& F,
                             MassMatrixType type = MassMatrixType::voronoi);

/// Diagonal mass matrix M = diag(vertex_areas(V, F, type)), #V×#V; equals libigl's massmatrix.
/// \throw InputError as cotan_laplacian.
Eigen::SparseMatrix<double> mass_matrix(const VertexRef& V, const FaceRef& F,
                                        MassMatrixType type = MassMatrixType::voronoi);

}  // namespace meshsmith::geometry
