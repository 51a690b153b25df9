// The cut is parametrization::cut_to_disk's, asked to pass through the singular vertices. The
// combing is one breadth-first sweep over the faces across uncut edges: face g reached from f
// turns its cross by the period jump between them, so the jump becomes 0. On a disk whose
// interior vertices are all regular the result does not depend on the sweep: around every
// loop of uncut edges the jumps sum to the enclosed indices, which are 0; the check at the end
// guards that invariant.
#include <meshsmith/quadrangulation/cut_graph.h>

#include "field_geometry.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/topology/dual_walk.h>

#include <algorithm>
#include <string>

namespace meshsmith::quadrangulation {

FieldCut cut_graph(const VertexRef& V, const FaceRef& F, const Eigen::VectorXd& theta) {
  const auto shared_mesh = detail::field_mesh(V, F, "cut_graph");
  const detail::FieldMesh& mesh = *shared_mesh;
  detail::check_angles(theta, F.rows(), "cut_graph");
  FieldCut out;
  const auto index = detail::vertex_indices(mesh, F, theta);
  for (std::size_t v = 0; v < index.size(); ++v) {
    if (index[v] != 0) out.singularities.vertices.push_back(static_cast<int>(v)), out.singularities.indices.push_back(index[v]);
  }
  out.cut = parametrization::cut_to_disk(V, F, out.singularities.vertices);
  const auto& incidence = mesh.checked.incidence;
  const Eigen::Index m = F.rows(), n_edges = incidence.n_edges();
  std::vector<char> is_cut(n_edges, 0);
  {
    // Seam edges are input edges (i < j, lexicographic), as incidence.edges: a merge finds them.
    Eigen::Index s = 0;
    for (Eigen::Index e = 0; e < n_edges && s < out.cut.seam_edges.rows(); ++e) {
      if (incidence.edges(e, 0) == out.cut.seam_edges(s, 0) && incidence.edges(e, 1) == out.cut.seam_edges(s, 1)) {
        is_cut[e] = 1, ++s;
      }
    }
  }
  auto jump = [&](int e, int from, const Eigen::VectorXd& angles) {
    const int to = mesh.other_face(e, from);
    const double x = angles[to] - angles[from] - mesh.transport(e, from);
    return static_cast<int>(std::lround((x - detail::quarter_residual(x)) / detail::kQuarter));
  };
  out.combed_theta = theta;
  topology::dual_spanning_tree(incidence, m, 0, [&](int e) { return is_cut[e] != 0; },
                               [&](int f, int e, int g) { out.combed_theta[g] -= detail::kQuarter * jump(e, f, out.combed_theta); });
  out.seam_jumps.resize(out.cut.seam_edges.rows());
  Eigen::Index s = 0;
  for (Eigen::Index e = 0; e < n_edges; ++e) {
    if (incidence.side_count(e) != 2) continue;
    const int p = jump(static_cast<int>(e), mesh.edge_faces(e, 0), out.combed_theta);
    const int reduced = ((p % 4) + 4) % 4;  // four quarter turns are the same cross
    if (is_cut[e]) {
      out.seam_jumps[s++] = reduced == 3 ? -1 : reduced;
    } else if (reduced != 0) {
      throw SolverError("cut_graph: the field does not comb across edge (" + std::to_string(incidence.edges(e, 0)) +
                        ", " + std::to_string(incidence.edges(e, 1)) + "): a singularity is off the cut; please report this mesh");
    }
  }
  return out;
}

}  // namespace meshsmith::quadrangulation
