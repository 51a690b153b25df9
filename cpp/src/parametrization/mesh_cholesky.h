#pragma once
// Internal to the parametrization chapter (not installed): the one CHOLMOD set-up of its SPD
// solves — harmonic, stretch and LSCM systems (constrained_solve), the reduced ABF++ system and
// the angle-based layout.
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace meshsmith::parametrization::detail {

template <typename Scalar = double>
using MeshCholesky = Eigen::CholmodDecomposition<Eigen::SparseMatrix<Scalar>, Eigen::Lower>;

/// Which factorization suits which system. Measured here (2 cores; Debian's OpenBLAS, which
/// scripts/bootstrap.sh installs) on the 100k-face disk:
/// - Laplacian-like systems (one unknown per vertex: harmonic, LSCM, the layout): supernodal
///   with AMD 0.14 s, simplicial AMD 0.20 s, simplicial METIS 0.31 s.
/// - the reduced ABF++ system (one unknown per interior-vertex condition, wider stencil):
///   simplicial METIS 1.0 s, simplicial AMD 2.4 s, supernodal AMD 3.0 s (reference BLAS).
enum class CholeskyKind { vertex_laplacian, abf_reduced };

template <typename Scalar>
void configure_cholesky(MeshCholesky<Scalar>& solver, CholeskyKind kind) {
  solver.cholmod().nmethods = 1;
  if (kind == CholeskyKind::vertex_laplacian) {
    solver.setMode(Eigen::CholmodSupernodalLLt);
    solver.cholmod().method[0].ordering = CHOLMOD_AMD;
  } else {
    solver.setMode(Eigen::CholmodSimplicialLLt);
    solver.cholmod().method[0].ordering = CHOLMOD_METIS;
  }
}

}  // namespace meshsmith::parametrization::detail
