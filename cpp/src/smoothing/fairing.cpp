// Bi-Laplacian fairing on the deformation chapter's k-harmonic solver: the held set is the
// boundary, its inner ring and the caller's fixed vertices; the solve is for positions.
#include <meshsmith/smoothing/fairing.h>

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/deformation/harmonic_deformer.h>
#include <meshsmith/topology/edge_incidence.h>

#include <string>

namespace meshsmith::smoothing {

VertexMatrix bilaplacian(const VertexRef& V, const FaceRef& F, const std::vector<int>& fixed) {
  validate_mesh(V, F);
  const Eigen::Index n = V.rows();
  std::vector<char> held(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    const int v = fixed[k];
    if (v < 0 || v >= n) {
      throw InputError("bilaplacian: fixed[" + std::to_string(k) + "] = " + std::to_string(v) + " is outside [0, " +
                       std::to_string(n) + ")");
    }
    if (held[v]) throw InputError("bilaplacian: fixed lists vertex " + std::to_string(v) + " twice");
    held[v] = 1;
  }
  const topology::EdgeIncidence incidence = topology::edge_incidence(F, n);
  std::vector<char> on_boundary(static_cast<std::size_t>(n), 0);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) == 1) on_boundary[incidence.edges(e, 0)] = on_boundary[incidence.edges(e, 1)] = 1;
  }
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    const int a = incidence.edges(e, 0), b = incidence.edges(e, 1);
    if (on_boundary[a] || on_boundary[b]) held[a] = held[b] = 1;
  }
  std::vector<int> constrained;
  for (Eigen::Index v = 0; v < n; ++v)
    if (held[v]) constrained.push_back(static_cast<int>(v));
  if (constrained.empty()) {
    throw InputError("bilaplacian: the mesh is closed and no vertex is fixed: nothing holds the surface (pass "
                     "fixed vertices)");
  }
  const deformation::KHarmonicSolver solver(V, F, constrained, 2);
  Eigen::MatrixXd values(static_cast<Eigen::Index>(constrained.size()), 3);
  for (std::size_t k = 0; k < constrained.size(); ++k) values.row(static_cast<Eigen::Index>(k)) = V.row(constrained[k]);
  const Eigen::MatrixXd faired = solver.solve_free(values);
  VertexMatrix out = V;
  const std::vector<int>& free = solver.free_vertices();
  for (std::size_t r = 0; r < free.size(); ++r) out.row(free[r]) = faired.row(static_cast<Eigen::Index>(r));
  return out;
}

}  // namespace meshsmith::smoothing
