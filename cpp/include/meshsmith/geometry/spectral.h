#pragma once
/// \file spectral.h
/// Eigenpairs of the cotangent Laplace–Beltrami operator (§1.2.4 Laplace operator; the
/// "manifold harmonics" of Vallet & Lévy 2008).
#include <meshsmith/core/progress.h>
#include <meshsmith/core/types.h>
#include <meshsmith/geometry/laplacian.h>

#include <Eigen/Core>

namespace meshsmith::geometry {

struct LaplacianEigenpairs {
  Eigen::VectorXd values;   ///< k eigenvalues λ, ascending (λ_0 ≈ 0 on a connected mesh)
  Eigen::MatrixXd vectors;  ///< #V×k eigenvectors, M-orthonormal: Uᵀ M U = I
};

/// The k smallest eigenpairs of the generalised problem −L u = λ M u, with L = cotan_laplacian
/// and M = mass_matrix(V, F, mass). Solved with Spectra's Lanczos iteration in shift-and-invert
/// mode around a small negative shift, the shifted matrix −L − σM factorised once by CHOLMOD.
/// On the unit sphere λ → l(l+1) with multiplicity 2l+1 as the mesh is refined.
/// V: #V×3, F: #F×3, 1 ≤ k < #V.
/// \pre every vertex is used by a face (M must be positive definite).
/// \throw InputError for bad (V, F), k out of range or a vertex with zero area;
/// SolverError if the factorisation or the iteration fails.
LaplacianEigenpairs laplacian_eigenpairs(const VertexRef& V, const FaceRef& F, Eigen::Index k,
                                         MassMatrixType mass = MassMatrixType::voronoi,
                                         const Progress& progress = {});

}  // namespace meshsmith::geometry
