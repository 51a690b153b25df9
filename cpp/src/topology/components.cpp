#include <meshsmith/topology/components.h>
#include <meshsmith/topology/edge_incidence.h>

#include "union_find.h"

namespace meshsmith::topology {

Components connected_components(const FaceRef& F, Eigen::Index n_vertices) {
  const Eigen::Index n = checked_vertex_count(F, n_vertices);
  UnionFind sets(static_cast<int>(n));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    sets.unite(F(f, 0), F(f, 1));
    sets.unite(F(f, 0), F(f, 2));
  }
  Components result;
  result.face_labels.resize(F.rows());
  result.vertex_labels.setConstant(n, -1);
  std::vector<int> root_label(n, -1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int root = sets.find(F(f, 0));
    if (root_label[root] < 0) root_label[root] = result.count++;
    result.face_labels[f] = root_label[root];
    for (int c = 0; c < 3; ++c) result.vertex_labels[F(f, c)] = root_label[root];
  }
  return result;
}

}  // namespace meshsmith::topology
