#pragma once
// Internal to the core (not installed): the one CHOLMOD set-up of the SPD solves of every
// chapter — parametrization's harmonic, stretch and LSCM systems (constrained_solve), the reduced
// ABF++ system, the angle-based layout and spectral LSCM's shift-and-invert; deformation's
// k-harmonic and ARAP systems; smoothing's implicit steps; quadrangulation's field and MIQ
// systems. A chapter's sources include it as "../core/mesh_cholesky.h".
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace meshsmith::detail {

/// While alive, the calling thread's OpenMP parallel regions run on one thread. Debian's
/// CHOLMOD 5.12 opens an OpenMP team of a hard-wired 4 threads (its CHOLMOD_OMP_NUM_THREADS,
/// deaf to OMP_NUM_THREADS) for every supernode above ~1000 entries, to clear and scatter a few
/// kB: on 2 cores these wake-ups cost more than the arithmetic. Measured on the 100k-face disk
/// (harmonic's free block, supernodal): factorization 95–110 ms with the teams, 55–61 ms
/// without; OpenBLAS's own threads (1 or 2) make no difference. Implemented by turning on the
/// thread's dynamic adjustment with a limit of one thread (omp_set_dynamic/omp_set_num_threads
/// of the OpenMP runtime CHOLMOD loaded, found with dlopen(RTLD_NOLOAD); nothing happens when
/// CHOLMOD was built without OpenMP), restored on destruction.
class SingleThreadedOpenMp {
 public:
  SingleThreadedOpenMp();
  ~SingleThreadedOpenMp();
  SingleThreadedOpenMp(const SingleThreadedOpenMp&) = delete;
  SingleThreadedOpenMp& operator=(const SingleThreadedOpenMp&) = delete;

 private:
  bool active_ = false;
  int saved_dynamic_ = 0;
  int saved_threads_ = 1;
};

/// While any instance is alive, the BLAS that CHOLMOD calls (OpenBLAS, when the process has
/// loaded it) runs on the calling thread only. OpenBLAS serves its threaded calls from one
/// thread pool, so two factorizations running side by side (SplitCholesky) queue behind each
/// other: measured on the two halves of the 100k-face disk, 30 ms and 60 ms side by side with
/// OpenBLAS's pool, 29 ms and 29 ms without it. Instances nest and may live on several threads:
/// the first sets one thread, the last restores the previous count.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

/// CHOLMOD's LLᵀ (lower triangle read) with its analysis and factorization run under
/// SingleThreadedOpenMp and SingleThreadedBlas (OpenBLAS's pool brings a lone factorization
/// nothing measurable, and its idle threads spin on the other core for a while afterwards). Call configure_cholesky before analyzing.
template <typename Scalar = double>
class MeshCholesky : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<Scalar>, Eigen::Lower> {
  using Base = Eigen::CholmodDecomposition<Eigen::SparseMatrix<Scalar>, Eigen::Lower>;

 public:
  MeshCholesky& compute(const Eigen::SparseMatrix<Scalar>& matrix) {
    const SingleThreadedBlas one_blas_thread;
    const SingleThreadedOpenMp one_thread;
    Base::compute(matrix);
    return *this;
  }
  void analyzePattern(const Eigen::SparseMatrix<Scalar>& matrix) {
    const SingleThreadedOpenMp one_thread;
    Base::analyzePattern(matrix);
  }
  void factorize(const Eigen::SparseMatrix<Scalar>& matrix) {
    const SingleThreadedBlas one_blas_thread;
    const SingleThreadedOpenMp one_thread;
    Base::factorize(matrix);
  }
  /// CHOLMOD's factor (null before compute/analyzePattern), e.g. for SupernodalSolve.
  const cholmod_factor* factor() const { return this->m_cholmodFactor; }
};

/// Which factorization suits which system. Measured here (2 cores, AMD EPYC; Debian's OpenBLAS,
/// which scripts/bootstrap.sh installs; threads limited as above) on harmonic's free block of the
/// 100k-face disk (49.5k unknowns):
/// - Laplacian-like systems (one unknown per vertex: harmonic, LSCM, the layout), supernodal.
///   With the vertex positions known (constrained_solve): geometric nested dissection
///   (nested_dissection.h; 10–11 ms of CPU, 6–7 ms on two threads; nnz(L) 1.97M, 2.45·10⁸ flops),
///   then SplitCholesky: the two halves (1.25·10⁸ flops each) analysed and factorized side by
///   side in 6 + 29 ms when the second core is free (55–60 ms when it is busy), the 251×251
///   Schur complement 3 ms. The same order in one CHOLMOD factorization: analysis 11 ms +
///   factorization 55–61 ms. AMD (no positions): analysis 23 ms (AMD itself 12 ms) +
///   factorization 61 ms (nnz(L) 2.17M, 3.57·10⁸ flops). Simplicial factorizations take
///   140–190 ms; METIS orders best (2.1·10⁸ flops) but itself takes 190 ms.
/// - the reduced ABF++ system (one unknown per interior-vertex condition, wider stencil):
///   simplicial METIS 1.0 s, simplicial AMD 2.4 s, supernodal AMD 3.0 s (reference BLAS).
/// - large systems factorized once and solved many times (deformation's k-harmonic and ARAP
///   systems, solved by SupernodalSolve): supernodal, METIS ordering, CHOLMOD's default
///   amalgamation {4, 16, 48}. A solve streams the stored factor, so its size is what counts: on
///   the order-2 free block of the 100k-vertex torus (80k unknowns) METIS gives nnz(L) 10.65M
///   (12.9M stored) against AMD's 14.2M, for 3.6·10⁹ factorization flops against 8.1·10⁹ (order
///   1: 3.3M against 4.25M); {8, 32, 64} would store 13.9M. On smaller systems METIS's ordering
///   costs more than it saves: nefertiti-lowres's order-2 block (28k unknowns) stores 3.2M
///   entries against AMD's 3.7M, for a factorization of 0.29 s of CPU time against 0.11 s.
enum class CholeskyKind {
  vertex_laplacian,          ///< supernodal, AMD ordering
  vertex_laplacian_solves,   ///< supernodal, METIS ordering, default amalgamation (many solves)
  vertex_laplacian_ordered,  ///< supernodal, the matrix is already in a fill-reducing order
  abf_reduced,               ///< simplicial, METIS ordering
};

/// Supernode amalgamation for vertex-Laplacian systems: CHOLMOD merges a child supernode into
/// its parent when the merged one has at most nrelax[0] columns, or at most nrelax[1] columns
/// (nrelax[2]) and a share of explicit zeros below zrelax[1] (zrelax[2]). Fewer, larger
/// supernodes mean fewer, larger BLAS calls: {8, 32, 64} instead of CHOLMOD's {4, 16, 48}
/// takes the factorization of harmonic's free block on the 100k-face disk from 55–60 ms to
/// 45 ms of CPU time (one thread, nested-dissection order; {12, 32, 96} the same, {16, 48, 96}
/// 64 ms).
inline void configure_vertex_supernodes(cholmod_common& common) {
  common.supernodal = CHOLMOD_SUPERNODAL;
  common.nrelax[0] = 8;
  common.nrelax[1] = 32;
  common.nrelax[2] = 64;
}

template <typename Scalar>
void configure_cholesky(MeshCholesky<Scalar>& solver, CholeskyKind kind) {
  solver.cholmod().nmethods = 1;
  switch (kind) {
    case CholeskyKind::vertex_laplacian:
      solver.setMode(Eigen::CholmodSupernodalLLt);
      configure_vertex_supernodes(solver.cholmod());
      solver.cholmod().method[0].ordering = CHOLMOD_AMD;
      break;
    case CholeskyKind::vertex_laplacian_solves:
      solver.setMode(Eigen::CholmodSupernodalLLt);
      solver.cholmod().supernodal = CHOLMOD_SUPERNODAL;
      solver.cholmod().method[0].ordering = CHOLMOD_METIS;
      break;
    case CholeskyKind::vertex_laplacian_ordered:
      solver.setMode(Eigen::CholmodSupernodalLLt);
      configure_vertex_supernodes(solver.cholmod());
      solver.cholmod().method[0].ordering = CHOLMOD_NATURAL;
      break;
    case CholeskyKind::abf_reduced:
      solver.setMode(Eigen::CholmodSimplicialLLt);
      solver.cholmod().method[0].ordering = CHOLMOD_METIS;
      break;
  }
}

}  // namespace meshsmith::detail
