#include <meshsmith/topology/components.h>
#include <meshsmith/topology/edge_incidence.h>

#include "union_find.h"

namespace meshsmith::topology {

namespace {

/// Labels from a union-find whose sets are identified through `set_of_face(f)`: components are
/// numbered by first face; a vertex takes the label of its lowest-numbered face.
template <typename SetOfFace>
Components label_components(const FaceRef& F, Eigen::Index n_vertices, int n_sets,
                            const SetOfFace& set_of_face) {
  Components result;
  result.face_labels.resize(F.rows());
  result.vertex_labels.setConstant(n_vertices, -1);
  std::vector<int> set_label(n_sets, -1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int set = set_of_face(f);
    if (set_label[set] < 0) set_label[set] = result.count++;
    result.face_labels[f] = set_label[set];
    for (int c = 0; c < 3; ++c)
      if (result.vertex_labels[F(f, c)] < 0) result.vertex_labels[F(f, c)] = set_label[set];
  }
  return result;
}

}  // namespace

Components connected_components(const FaceRef& F, Eigen::Index n_vertices, Connectivity connectivity) {
  if (connectivity == Connectivity::Vertex) {
    const Eigen::Index n = checked_vertex_count(F, n_vertices);
    UnionFind vertices(static_cast<int>(n));
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      vertices.unite(F(f, 0), F(f, 1));
      vertices.unite(F(f, 0), F(f, 2));
    }
    return label_components(F, n, static_cast<int>(n), [&](Eigen::Index f) { return vertices.find(F(f, 0)); });
  }
  const EdgeIncidence incidence = edge_incidence(F, n_vertices);
  UnionFind faces(static_cast<int>(F.rows()));
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e)
    for (int k = incidence.edge_offsets[e] + 1; k < incidence.edge_offsets[e + 1]; ++k)
      faces.unite(incidence.edge_sides[k - 1] / 3, incidence.edge_sides[k] / 3);
  return label_components(F, incidence.n_vertices, static_cast<int>(F.rows()),
                          [&](Eigen::Index f) { return faces.find(static_cast<int>(f)); });
}

}  // namespace meshsmith::topology
