#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/topology/boundary.h>
#include <meshsmith/topology/characteristics.h>
#include <meshsmith/topology/components.h>
#include <meshsmith/topology/manifold.h>

#include <sstream>

namespace meshsmith::topology {

namespace {

Eigen::Index count_referenced_vertices(const FaceRef& F, Eigen::Index n_vertices) {
  std::vector<char> referenced(n_vertices, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) referenced[F(f, c)] = 1;
  Eigen::Index count = 0;
  for (char r : referenced) count += r;
  return count;
}

/// Orients each component by a depth-first search across its two-sided edges; returns the first
/// face where the orientation contradicts itself (the component is non-orientable), or -1.
int first_non_orientable_face(const FaceRef& F, const EdgeIncidence& incidence) {
  std::vector<signed char> flip(F.rows(), -1);  // -1: not reached yet
  std::vector<int> queue;
  for (Eigen::Index seed = 0; seed < F.rows(); ++seed) {
    if (flip[seed] >= 0) continue;
    flip[seed] = 0;
    queue.assign(1, static_cast<int>(seed));
    while (!queue.empty()) {
      const int f = queue.back();
      queue.pop_back();
      for (int k = 0; k < 3; ++k) {
        const int e = incidence.side_edge[3 * f + k];
        if (e < 0 || incidence.side_count(e) != 2) continue;
        const int s1 = incidence.edge_sides[incidence.edge_offsets[e]];
        const int other = s1 == 3 * f + k ? incidence.edge_sides[incidence.edge_offsets[e] + 1] : s1;
        const int g = other / 3;
        if (g == f) continue;
        // Sides in the same direction mean g must be flipped relative to f.
        const bool same_direction = F(f, k) == F(g, other % 3);
        const signed char wanted = static_cast<signed char>(flip[f] ^ (same_direction ? 1 : 0));
        if (flip[g] < 0) {
          flip[g] = wanted;
          queue.push_back(g);
        } else if (flip[g] != wanted) {
          return g;
        }
      }
    }
  }
  return -1;
}

/// Genus of each component from χ_c = 2 − 2g_c − b_c, for a mesh known to be manifold and orientable.
std::vector<int> genera_of_manifold(const FaceRef& F, const EdgeIncidence& incidence,
                                    const Components& components,
                                    const std::vector<std::vector<int>>& loops) {
  const int count = components.count;
  std::vector<long long> chi(count, 0), boundaries(count, 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) ++chi[components.face_labels[f]];
  for (Eigen::Index v = 0; v < incidence.n_vertices; ++v)
    if (components.vertex_labels[v] >= 0) ++chi[components.vertex_labels[v]];
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) --chi[components.vertex_labels[incidence.edges(e, 0)]];
  for (const auto& loop : loops) ++boundaries[components.vertex_labels[loop.front()]];
  std::vector<int> genera(count);
  for (int c = 0; c < count; ++c) genera[c] = static_cast<int>((2 - chi[c] - boundaries[c]) / 2);
  return genera;
}

/// Checks the preconditions of genus_per_component (throwing as documented there), then the genera.
std::vector<int> checked_genera(const FaceRef& F, const EdgeIncidence& incidence,
                                const Components& components,
                                const std::vector<std::vector<int>>& loops) {
  const EdgeMatrix bad_edges = non_manifold_edges(incidence);
  if (bad_edges.rows() > 0) {
    std::ostringstream message;
    message << "the mesh is not manifold: edge (" << bad_edges(0, 0) << ", " << bad_edges(0, 1)
            << ") has more than two faces (" << bad_edges.rows()
            << " such edges); genus is undefined (see split_non_manifold_vertices)";
    throw InputError(message.str());
  }
  const std::vector<int> bad_vertices = non_manifold_vertices(F, incidence);
  if (!bad_vertices.empty()) {
    std::ostringstream message;
    message << "the mesh is not manifold: vertex " << bad_vertices.front()
            << " joins several fans of faces (" << bad_vertices.size()
            << " such vertices); genus is undefined (see split_non_manifold_vertices)";
    throw InputError(message.str());
  }
  const int bad_face = first_non_orientable_face(F, incidence);
  if (bad_face >= 0) {
    std::ostringstream message;
    message << "component " << components.face_labels[bad_face] << " (around face " << bad_face
            << ") is not orientable: genus is undefined";
    throw InputError(message.str());
  }
  return genera_of_manifold(F, incidence, components, loops);
}

}  // namespace

long long euler_characteristic(const FaceRef& F) { return euler_characteristic(F, edge_incidence(F)); }

long long euler_characteristic(const FaceRef& F, const EdgeIncidence& incidence) {
  return static_cast<long long>(count_referenced_vertices(F, incidence.n_vertices)) -
         static_cast<long long>(incidence.n_edges()) + static_cast<long long>(F.rows());
}

std::vector<int> genus_per_component(const FaceRef& F) {
  const EdgeIncidence incidence = edge_incidence(F);
  return checked_genera(F, incidence, connected_components(F, incidence.n_vertices),
                          boundary_loops(F, incidence));
}

MeshInfo mesh_info(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  const EdgeIncidence incidence = edge_incidence(F, V.rows());
  const Components components = connected_components(F, V.rows());
  const auto loops = boundary_loops(F, incidence);
  MeshInfo info;
  info.n_vertices = V.rows();
  info.n_faces = F.rows();
  info.n_edges = incidence.n_edges();
  info.n_components = components.count;
  info.n_boundary_loops = static_cast<Eigen::Index>(loops.size());
  info.n_boundary_edges = count_boundary_edges(incidence);
  info.euler_characteristic = euler_characteristic(F, incidence);
  info.n_non_manifold_edges = non_manifold_edges(incidence).rows();
  info.n_non_manifold_vertices = static_cast<Eigen::Index>(non_manifold_vertices(F, incidence).size());
  info.is_manifold = info.n_non_manifold_edges == 0 && info.n_non_manifold_vertices == 0;
  info.is_oriented = is_oriented(F, incidence);
  info.n_unreferenced_vertices = V.rows() - count_referenced_vertices(F, V.rows());
  if (info.is_manifold && first_non_orientable_face(F, incidence) < 0) {
    int total = 0;
    for (int g : genera_of_manifold(F, incidence, components, loops)) total += g;
    info.genus = total;
  }
  return info;
}

}  // namespace meshsmith::topology
