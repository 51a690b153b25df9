#pragma once
// Internal to the core (not installed): the forward and back substitution of a supernodal
// CHOLMOD factor for a few right-hand sides at once, on two threads — the per-solve step of
// deformation's k-harmonic and ARAP systems, where one factorization serves many solves.
#include <cholmod.h>

#include <Eigen/Core>

#include <vector>

namespace meshsmith::detail {

/// x = A⁻¹ b with A = Pᵀ L Lᵀ P from a supernodal CHOLMOD LLᵀ factor (MeshCholesky with
/// CholmodSupernodalLLt; real, int indices), for #A×c right-hand sides.
///
/// Why not cholmod_solve: a solve streams the factor's values twice and does two flops per
/// entry and column, so it is bound by memory bandwidth; CHOLMOD's supernodal solve instead
/// spends its time in one dtrsm + dgemm call per supernode (OpenBLAS packs the 3-column panels;
/// thousands of small supernodes per factor), and runs on one thread. Here each supernode's rows
/// of the right-hand sides are gathered into a row-major block (the c values of a row together
/// in one SIMD register: 3 columns are padded to 4), updated with fused loops over two columns
/// of the supernode at a time (the back substitution's dot products in four independent chains
/// of additions), and scattered back. The loops are compiled for the baseline x86-64 (SSE2) and
/// for AVX2, chosen at run time; neither contracts to FMA, so both give the same bits.
///
/// Sparse right-hand sides: the forward substitution skips every supernode whose own rows are
/// still zero when it is reached (no right-hand side there and no update from below), without
/// reading its part of the factor. A handle deformation's right-hand side is non-zero only on
/// the free rows next to the handle (−Q_FH d_H), so its forward pass touches the supernodes on
/// their paths to the root only.
///
/// Measured here (2 cores, machine loaded to 14–18 by other builds; CPU time per thread, medians
/// of 5) on the order-2 free block of the 100k-vertex torus (80k unknowns, 12.8M stored factor
/// entries, METIS order), three columns: 24 ms per thread for both passes before (SSE2, one
/// column per sweep, no skip); now the forward pass of a handle's right-hand side 1.5–2 ms (the
/// skip), the back substitution 21 ms (SSE2, one column per sweep) → 13 ms (AVX2) → 7.5 ms
/// (AVX2, two columns per sweep, four chains); the 100k-vertex cube sphere (12.6M entries) the
/// same. Tried and dropped: FMA (7.3 ms: the loop is then
/// bound by memory, and results would depend on the processor); ordering the handle's coupled
/// rows last (METIS on the rest; forward pass 0.15 ms, but 14.8M stored entries instead of
/// 12.8M: no net gain); CHOLMOD_NESDIS (12.9M entries); no supernode amalgamation (12.1M
/// entries, back substitution within noise of the default's).
///
/// Two threads: the supernodal elimination tree is cut into two groups of subtrees of about
/// equal storage and the "top" (the supernodes above the cut: the separators of the fill-reducing
/// order's first levels). The forward substitution runs the two groups concurrently — each adds
/// its updates to the top's rows into a private accumulator, summed before the top is solved on
/// one thread — and the back substitution runs the top first, then the two groups concurrently
/// (they only read the top's solution). Each thread then streams about half the factor.
/// Results are deterministic (the same order of operations on any machine) and equal to
/// cholmod_solve's to round-off.
///
/// The factor must outlive this object and stay unchanged. solve() is const and reentrant
/// (buffers are per call).
class SupernodalSolve {
 public:
  SupernodalSolve() = default;
  /// \pre factor.is_super, factor.is_ll, factor.xtype == CHOLMOD_REAL, int indices.
  explicit SupernodalSolve(const cholmod_factor& factor);

  /// A⁻¹ b for b: n×c (any c ≥ 0; columns are processed four at a time, 3 padded to 4).
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& b) const;

  Eigen::Index size() const { return n_; }

 private:
  template <int C>
  void substitute(const Eigen::Ref<const Eigen::MatrixXd>& b, Eigen::Index first, Eigen::MatrixXd& x) const;

  const cholmod_factor* factor_ = nullptr;
  Eigen::Index n_ = 0;
  /// The supernodes of the two concurrent groups and of the top, each increasing (children
  /// before parents: CHOLMOD numbers supernodes in a post-order).
  std::vector<int> group_[2], top_;
  /// For every row of the factor: its position among the top's rows, or −1.
  std::vector<int> top_row_;
  Eigen::Index top_rows_ = 0;
};

}  // namespace meshsmith::detail
