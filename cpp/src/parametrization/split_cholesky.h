#pragma once
// Internal to the parametrization chapter: a sparse Cholesky solve that uses both cores, for a
// system in nested-dissection order (nested_dissection.h) split at its top separator.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <complex>
#include <memory>

namespace meshsmith::parametrization::detail {

/// Solves A x = b for an SPD (Hermitian positive definite) A whose variables are ordered as
/// two parts with no entry between them, then their separator S:
///     A = [A₁₁ 0 A₁ₛ; 0 A₂₂ A₂ₛ; Aₛ₁ Aₛ₂ Aₛₛ].
/// The two "bordered" matrices Mᵢ = [Aᵢᵢ Aᵢₛ; Aₛᵢ Aₛₛ] are factorized by CHOLMOD (supernodal,
/// in the given order) concurrently. Each is positive definite: its Schur complement
/// Tᵢ = Aₛₛ − Aₛᵢ Aᵢᵢ⁻¹ Aᵢₛ is that of A plus a positive semi-definite term. The trailing
/// block of Mᵢ's factor is chol(Tᵢ), so A's Schur complement Aₛₛ − Σ Aₛᵢ Aᵢᵢ⁻¹ Aᵢₛ = T₁ + T₂ − Aₛₛ
/// is formed densely (#S is O(√n) on a surface mesh) and factorized with Eigen. A solve is a
/// forward substitution in each part (concurrently), a dense solve on S, and a back
/// substitution in each part (concurrently). BLAS runs on the calling threads
/// (SingleThreadedBlas). Measured on the 100k-face disk (harmonic's free block): see
/// mesh_cholesky.h.
template <typename Scalar>
class SplitCholesky {
 public:
  using Sparse = Eigen::SparseMatrix<Scalar>;
  using Dense = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

  /// lower: the n×n lower triangle of A (CSC, rows sorted in each column), ordered as above
  /// with #part₁ = first_part ≥ 1, #part₂ = second_part ≥ 1.
  /// \throw SolverError naming `function` if A is not positive definite.
  SplitCholesky(const Sparse& lower, Eigen::Index first_part, Eigen::Index second_part, const char* function);
  ~SplitCholesky();
  SplitCholesky(const SplitCholesky&) = delete;
  SplitCholesky& operator=(const SplitCholesky&) = delete;

  /// x = A⁻¹ b for the n×c right-hand sides b.
  Dense solve(const Dense& b) const;

 private:
  struct Part;
  std::unique_ptr<Part> parts_[2];
  Eigen::Index separator_begin_ = 0;
  Eigen::LLT<Dense, Eigen::Lower> schur_;
};

extern template class SplitCholesky<double>;
extern template class SplitCholesky<std::complex<double>>;

}  // namespace meshsmith::parametrization::detail
