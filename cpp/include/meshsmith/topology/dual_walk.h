#pragma once
/// \file dual_walk.h
/// Breadth-first walks over the dual graph of a triangle mesh: faces are the nodes, interior
/// (two-sided) edges the arcs (§2, the dual spanning trees of cut graphs and field combing).
/// Header-only on top of EdgeIncidence so that a walk costs no extra pass over the mesh.
#include <meshsmith/topology/edge_incidence.h>

#include <deque>
#include <vector>

namespace meshsmith::topology {

/// The face on the other side of edge e from face f. \pre side_count(e) == 2 and f is on e.
inline int face_across(const EdgeIncidence& incidence, int e, int f) {
  const int s0 = incidence.edge_sides[incidence.edge_offsets[e]];
  const int s1 = incidence.edge_sides[incidence.edge_offsets[e] + 1];
  return s0 / 3 == f ? s1 / 3 : s0 / 3;
}

/// Breadth-first dual spanning tree from face `root`, crossing only two-sided edges for which
/// `blocked(e)` is false; `cross(f, e, g)` is called once per tree arc, when face g is first
/// reached from face f across edge e (faces in breadth-first order). Returns, per face, whether
/// it was reached. O(#F). \pre 0 <= root < n_faces; incidence computed from the same faces.
template <class Blocked, class Cross>
std::vector<char> dual_spanning_tree(const EdgeIncidence& incidence, Eigen::Index n_faces, int root,
                                     Blocked&& blocked, Cross&& cross) {
  std::vector<char> reached(n_faces, 0);
  std::deque<int> queue{root};
  reached[root] = 1;
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int k = 0; k < 3; ++k) {
      const int e = incidence.side_edge[3 * f + k];
      if (e < 0 || incidence.side_count(e) != 2 || blocked(e)) continue;
      const int g = face_across(incidence, e, f);
      if (reached[g]) continue;
      reached[g] = 1;
      cross(f, e, g);
      queue.push_back(g);
    }
  }
  return reached;
}

}  // namespace meshsmith::topology
