#pragma once
/// \file harmonic_deformer.h
/// k-harmonic systems with fixed vertices and the handle-based free-form deformation built on
/// them (§3.1.1 "Free-form Modeling"; Botsch & Kobbelt 2004, Jacobson et al. 2010 for the
/// order-k energy). One sparse Cholesky factorization of the free block serves any number of
/// right-hand sides: smoothing's bi-Laplacian fairing, repair's hole fairing, deformation.
///
/// The order-k operator is libigl's (igl::harmonic): Q = (−L M⁻¹)^(k−1) (−L), with L the cotan
/// Laplacian (geometry/laplacian.h, negative semi-definite) and M the Voronoi mass matrix, so
/// that order 1 is the Laplace equation ΔX = 0, order 2 the bi-Laplace equation Δ²X = 0 (a thin
/// plate, C¹ at the constraints) and order 3 Δ³X = 0 at the free vertices.
#include <meshsmith/core/types.h>
#include <meshsmith/deformation/multiresolution.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <vector>

namespace meshsmith::deformation {

/// The order-k operator Q = (−L M⁻¹)^(k−1) (−L) (#V×#V, symmetric positive semi-definite for
/// k = 2; equal to libigl's to round-off). Vertices of zero area (on degenerate triangles only)
/// and vertices used by no face contribute nothing to the products (their rows of L are zero).
/// \throw InputError for k ∉ {1, 2, 3} and as geometry::cotan_laplacian.
Eigen::SparseMatrix<double> k_harmonic_operator(const VertexRef& V, const FaceRef& F, int order);

/// A precomputed solve of Q X = 0 at the free vertices with X given at the constrained ones: the
/// free block Q_FF factorized once (CHOLMOD, supernodal LLᵀ; AMD order, METIS from 50k free
/// vertices on), so that solve() costs
/// one sparse product for the right-hand side and one pair of triangular solves, all columns at
/// once and on two threads, for any values at the constrained vertices.
/// Free vertices: every vertex used by a face that is not constrained. Vertices used by no face
/// are neither free nor solved for (their rows of a solution are 0). Solves may be called from
/// several threads at once.
class KHarmonicSolver {
 public:
  /// V: #V×3 positions, F: #F×3 triangles, constrained: distinct vertex indices (any order),
  /// order: k ∈ {1, 2, 3}.
  /// \pre every connected component of the mesh (through edges of non-zero cotangent weight)
  ///      holds a constrained vertex; no free vertex lies on degenerate triangles only.
  /// \throw InputError if V, F are invalid, an index is out of range or repeated, `constrained`
  ///        is empty, k ∉ {1, 2, 3}, or the precondition fails (the message names a vertex of the
  ///        unconstrained component: the system would be singular there);
  ///        SolverError if the free block is still not positive definite (negative cotangent
  ///        weights can make orders 1 and 3 indefinite).
  KHarmonicSolver(const VertexRef& V, const FaceRef& F, const std::vector<int>& constrained, int order = 2);
  ~KHarmonicSolver();
  KHarmonicSolver(KHarmonicSolver&&) noexcept;
  KHarmonicSolver& operator=(KHarmonicSolver&&) noexcept;

  int order() const { return order_; }
  Eigen::Index vertex_count() const { return n_vertices_; }
  const std::vector<int>& constrained() const { return constrained_; }
  /// The free vertices, increasing; row r of solve_free() is vertex free_vertices()[r].
  const std::vector<int>& free_vertices() const { return free_; }

  /// X_F = −Q_FF⁻¹ Q_FC X_C for the #constrained×c values X_C (rows in the order of
  /// constrained()). Returns #free×c.
  /// \throw InputError if X_C has the wrong number of rows or holds NaN/Inf.
  Eigen::MatrixXd solve_free(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values) const;

  /// X_F = Q_FF⁻¹ (B_F − Q_FC X_C): the same system with a right-hand side B_F (#free×c, rows in
  /// the order of free_vertices()) at the free vertices, e.g. ARAP's global step.
  /// \throw InputError as solve_free, or if B_F has the wrong shape or holds NaN/Inf.
  Eigen::MatrixXd solve_free(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values,
                             const Eigen::Ref<const Eigen::MatrixXd>& free_rhs) const;

  /// The whole #V×c solution: X_C on the constrained rows, solve_free() on the free rows, 0 on
  /// rows of vertices used by no face. \throw InputError as solve_free.
  Eigen::MatrixXd solve(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values) const;

 private:
  Eigen::MatrixXd solve_free_impl(const Eigen::Ref<const Eigen::MatrixXd>& constrained_values,
                                  const Eigen::Ref<const Eigen::MatrixXd>* free_rhs) const;
  struct Factorization;
  std::unique_ptr<Factorization> factorization_;
  int order_ = 2;
  Eigen::Index n_vertices_ = 0;
  std::vector<int> constrained_, free_;
};

/// The k-harmonic interpolant of values `bc` at the vertices `b` (libigl's igl::harmonic(V, F, b,
/// bc, k)): X with X_b = bc and (Q X)_i = 0 at every other vertex used by a face.
/// V: #V×3, F: #F×3, b: #b distinct indices, bc: #b×c. Returns #V×c (rows of vertices used by no
/// face are 0). \throw InputError, SolverError as KHarmonicSolver and solve.
Eigen::MatrixXd harmonic(const VertexRef& V, const FaceRef& F, const std::vector<int>& b, const Eigen::MatrixXd& bc,
                         int order = 2);

/// Handle-based deformation (§3.1.1): the handle vertices move, the fixed ones stay, and the
/// displacement of every other vertex is k-harmonic (order 2: Δ²d = 0, libigl's
/// igl::harmonic(V, F, b, D_b, 2) with D_b the handle and fixed displacements). Precomputes the
/// factorization and the response to the four control points of the handle (the 4-point
/// representation h = Q (a, b, c, d)ᵀ of §3.1.1: the handle's centroid a and a + s·e_x, a + s·e_y,
/// a + s·e_z, s the handle's extent), so transform() costs one #free×4 by 4×3 product and
/// deform() one back-substitution.
///
/// With `details` (the detail-preserving variant of §3.1.1–3.1.2), the surface is split into a
/// smooth base (the same k-harmonic system solved for positions: the fairing of the free region
/// with the handle and fixed vertices held) plus per-vertex details expressed in local frames of
/// the base (its normal and a tangent towards a fixed neighbour); a deformation moves the base
/// and re-adds the details in the moved base's frames, so the details turn with the surface.
class HarmonicDeformer {
 public:
  /// handle: #H distinct vertex indices (non-empty); fixed: #X distinct vertex indices, none in
  /// the handle (may be empty when the handle holds every component).
  /// \throw InputError for an empty handle, an index out of range, repeated, or both in the
  ///        handle and fixed (naming it), and as KHarmonicSolver.
  HarmonicDeformer(const VertexRef& V, const FaceRef& F, const std::vector<int>& handle, const std::vector<int>& fixed,
                   int order = 2, bool details = false);

  /// The deformed positions (#V×3) for the handle vertices at handle_positions (#H×3, in the
  /// order of `handle`); fixed vertices and vertices used by no face keep their positions.
  /// \throw InputError for a wrong shape or NaN/Inf.
  VertexMatrix deform(const VertexRef& handle_positions) const;

  /// The deformed positions (#V×3) when the handle undergoes the affine map T (4×4, acting on
  /// column vectors (x, y, z, 1)ᵀ; its last row must be (0, 0, 0, 1)).
  /// \throw InputError if T holds NaN/Inf or is not affine.
  VertexMatrix transform(const Eigen::Matrix4d& T) const;

  const std::vector<int>& handle() const { return handle_; }
  const std::vector<int>& fixed() const { return fixed_; }
  int order() const { return solver_.order(); }
  bool details() const { return details_; }

 private:
  VertexMatrix finish(const Eigen::MatrixXd& free_displacement, const VertexRef* handle_positions,
                      const Eigen::Matrix4d* T) const;

  VertexMatrix V_;
  FaceMatrix F_;
  std::vector<int> handle_, fixed_;
  KHarmonicSolver solver_;
  Eigen::Matrix<double, 4, 3> control_points_;  ///< a, b, c, d (rows)
  Eigen::MatrixXd handle_coordinates_;          ///< #H×4 affine coordinates of the handle in them
  Eigen::MatrixXd control_response_;            ///< #free×4: free displacement per unit control move
  bool details_ = false;
  VertexMatrix base_;                           ///< #V×3 smooth base (details only)
  DetailFrames details_frames_;                 ///< the details over base_ (free vertices only)
};

}  // namespace meshsmith::deformation
