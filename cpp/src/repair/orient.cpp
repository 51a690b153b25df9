// Consistent orientation (orient.h). The faces are the nodes of a graph whose arcs are the edges
// with exactly two face sides; an arc says whether the two faces already agree (their sides run in
// opposite directions) or disagree. A breadth-first walk per component assigns each face a flip
// bit relative to the component's first face; a visited neighbour whose bit contradicts the arc
// marks the component non-orientable. The per-component decision (signed volume for closed
// components, fewest flips otherwise) is then a sum over the component's faces.
#include <meshsmith/core/validation.h>
#include <meshsmith/repair/orient.h>
#include <meshsmith/topology/edge_incidence.h>

#include <Eigen/Geometry>

#include <cstddef>
#include <utility>

namespace meshsmith::repair {

OrientedFaces orient_faces(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  const auto incidence = topology::edge_incidence(F, V.rows());
  const int m = static_cast<int>(F.rows());

  // The face across each side (through a two-sided edge), or -1.
  std::vector<int> across(static_cast<std::size_t>(3) * m, -1);
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) != 2) continue;
    const int s = incidence.edge_sides[incidence.edge_offsets[e]];
    const int t = incidence.edge_sides[incidence.edge_offsets[e] + 1];
    if (s / 3 == t / 3) continue;
    across[s] = t;
    across[t] = s;
  }
  auto tail = [&](int side) { return F(side / 3, side % 3); };

  OrientedFaces result;
  std::vector<int> component(m, -1), queue;
  std::vector<char> flip(m, 0);
  queue.reserve(m);
  for (int seed = 0; seed < m; ++seed) {
    if (component[seed] >= 0) continue;
    const int label = result.components++;
    queue.clear();
    queue.push_back(seed);
    component[seed] = label;
    bool orientable = true, closed = true;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int f = queue[head];
      for (int k = 0; k < 3; ++k) {
        const int side = 3 * f + k, other = across[side];
        if (other < 0) {
          if (incidence.side_edge[side] >= 0) closed = false;  // boundary or non-manifold edge
          continue;
        }
        // Sides in the same direction: the faces disagree, so their flips must differ.
        const char wanted = static_cast<char>(flip[f] ^ (tail(side) == tail(other) ? 1 : 0));
        const int g = other / 3;
        if (component[g] < 0) {
          component[g] = label;
          flip[g] = wanted;
          queue.push_back(g);
        } else if (flip[g] != wanted) {
          orientable = false;
        }
      }
    }
    // queue now holds the component's faces.
    std::size_t flipped = 0;
    for (const int f : queue) flipped += flip[f];
    bool reverse = 2 * flipped > queue.size();
    if (closed && orientable) {
      const Eigen::Vector3d origin = V.row(F(seed, 0));
      double volume = 0.0;   // six times the signed volume, with the flips applied
      for (const int f : queue) {
        const Eigen::Vector3d p = V.row(F(f, 0)).transpose() - origin;
        const Eigen::Vector3d q = V.row(F(f, 1)).transpose() - origin;
        const Eigen::Vector3d r = V.row(F(f, 2)).transpose() - origin;
        const double signed_volume = p.dot(q.cross(r));
        volume += flip[f] ? -signed_volume : signed_volume;
      }
      if (volume != 0.0) reverse = volume < 0.0;
    }
    if (reverse) {
      for (const int f : queue) flip[f] ^= 1;
    }
    result.closed_components += closed ? 1 : 0;
    result.non_orientable_components += orientable ? 0 : 1;
  }

  result.F = F;
  for (int f = 0; f < m; ++f) {
    if (!flip[f]) continue;
    std::swap(result.F(f, 1), result.F(f, 2));
    result.flipped.push_back(f);
  }
  return result;
}

}  // namespace meshsmith::repair
