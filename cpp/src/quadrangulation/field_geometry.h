#pragma once
// Internal to the quadrangulation chapter (not installed): the checked input, face frames and
// edge-to-face adjacency that the cross field, the cut graph and MIQ share.
#include <meshsmith/parametrization/mesh_checks.h>
#include <meshsmith/quadrangulation/cross_field.h>

#include "../core/mesh_cholesky.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <vector>

namespace meshsmith::quadrangulation::detail {

constexpr double kPi = 3.14159265358979323846;
constexpr double kQuarter = kPi / 2;

/// x reduced by multiples of π/2 into [−π/4, π/4).
inline double quarter_residual(double x) { return x - kQuarter * std::floor((x + kQuarter / 2) / kQuarter); }

/// x wrapped into (−π, π].
inline double wrap_angle(double x) { return x - 2 * kPi * std::ceil((x - kPi) / (2 * kPi)); }

/// The checked mesh on normalized coordinates with its face frames and edge adjacency.
struct FieldMesh {
  VertexMatrix V;  ///< normalized positions (every quantity used here is scale-invariant)
  CoordinateFrame frame;  ///< input lengths = 2^frame.exponent normalized lengths
  parametrization::detail::CheckedMesh checked;
  VertexMatrix e1, e2, normal;  ///< #F×3 face frames
  Eigen::VectorXd area;         ///< #F face areas (normalized units)
  EdgeMatrix edge_faces;        ///< #E×2 (f, g): f's side runs i → j (or f is the only face), g = −1 on the boundary
  Eigen::VectorXd connection;   ///< #E κ_fg

  FieldMesh(const VertexRef& input_V, const FaceRef& F, const char* function);
  Eigen::Index n_faces() const { return area.size(); }
  /// The angle of the vector d (tangent to face f) in f's frame.
  double angle_in_face(int f, const Eigen::Vector3d& d) const { return std::atan2(d.dot(e2.row(f)), d.dot(e1.row(f))); }
  /// κ from face `from` to the other face of edge e.
  double transport(int e, int from) const { return edge_faces(e, 0) == from ? connection[e] : -connection[e]; }
  int other_face(int e, int f) const { return edge_faces(e, 0) == f ? edge_faces(e, 1) : edge_faces(e, 0); }
};

/// The FieldMesh of (V, F): the one made by the call before when a SharedFieldMesh lives and
/// V and F equal that call's, else a new one. \throw InputError as FieldMesh's constructor.
std::shared_ptr<const FieldMesh> field_mesh(const VertexRef& V, const FaceRef& F, const char* function);

/// The chapter's SPD solver: the parametrization chapter's supernodal CHOLMOD LLᵀ (AMD, one
/// ordering, OpenMP and BLAS on the calling thread). CHOLMOD's default set-up (several orderings
/// tried, OpenMP teams of 4) took 9.5 s of the 10 s cross field of a 100k-face mesh here.
using Cholesky = meshsmith::detail::MeshCholesky<double>;

inline void configure_cholmod(Cholesky& solver) {
  meshsmith::detail::configure_cholesky(solver, meshsmith::detail::CholeskyKind::vertex_laplacian);
}

/// The period jumps p_fg of the angles theta across every edge (0 on the boundary).
Eigen::VectorXi period_jumps(const FieldMesh& mesh, const Eigen::VectorXd& theta);

/// theta checked: #F finite values.
/// \throw InputError naming the first bad face.
void check_angles(const Eigen::VectorXd& theta, Eigen::Index n_faces, const char* function);

/// Per-vertex indices in quarter turns (all #V, zeros included).
std::vector<int> vertex_indices(const FieldMesh& mesh, const FaceRef& F, const Eigen::VectorXd& theta);

}  // namespace meshsmith::quadrangulation::detail
