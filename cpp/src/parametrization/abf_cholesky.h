#pragma once
// Internal to ABF (not installed): the CHOLMOD set-up of its two SPD solves (the reduced ABF++
// system and the layout's normal equations).
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace meshsmith::parametrization::detail {

using MeshCholesky = Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>;

/// Simplicial LLᵀ with a METIS nested-dissection ordering. Measured on the 100k-face ABF++
/// system here (Debian's reference BLAS): CHOLMOD's default (supernodal, AMD) 3.0 s per
/// factorization, simplicial + AMD 2.4 s, simplicial + METIS 1.0 s (half the flops of AMD on
/// these planar-graph matrices; the supernodal kernels gain nothing without a tuned BLAS).
inline void use_nested_dissection(MeshCholesky& solver) {
  solver.setMode(Eigen::CholmodSimplicialLLt);
  solver.cholmod().nmethods = 1;
  solver.cholmod().method[0].ordering = CHOLMOD_METIS;
}

}  // namespace meshsmith::parametrization::detail
