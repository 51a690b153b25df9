#include "input_checks.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/topology/boundary.h>
#include <meshsmith/topology/characteristics.h>
#include <meshsmith/topology/components.h>
#include <meshsmith/topology/manifold.h>

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>
#include <string>

namespace meshsmith::parametrization::detail {

namespace {

[[noreturn]] void fail(const char* function, const std::string& message) {
  throw InputError(std::string(function) + ": " + message);
}

void check_faces(const VertexRef& V, const FaceRef& F, const char* function) {
  std::vector<char> used(static_cast<std::size_t>(V.rows()), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (a == b || b == c || c == a) {
      fail(function, "face " + std::to_string(f) + " repeats a vertex (" + std::to_string(a) + ", " +
                         std::to_string(b) + ", " + std::to_string(c) + "): remove degenerate faces first "
                         "(meshsmith.repair.clean)");
    }
    const Eigen::Vector3d p = V.row(a), q = V.row(b), r = V.row(c);
    if ((q - p).cross(r - p).squaredNorm() == 0.0) {
      Eigen::Vector3d ab, ac;
      const CoordinateFrame own = triangle_edge_vectors(V.row(a).data(), V.row(b).data(), V.row(c).data(), ab, ac);
      if (ab.cross(ac).squaredNorm() == 0.0)
        fail(function, "face " + std::to_string(f) + " has zero area (collinear corners): remove or repair "
                       "degenerate faces first");
      // A true triangle whose area is below the double range in the mesh's frame: the maps solve
      // one linear system over the whole mesh, in one scale, which cannot hold both it and a vertex
      // that far away (its own-frame figures would be fine, the system's coefficients are not).
      Eigen::Index far = 0, column = 0;
      V.cwiseAbs().maxCoeff(&far, &column);
      const int mesh_exponent = normalizing_frame(V).exponent;
      fail(function, "face " + std::to_string(f) + " is about 2^" + std::to_string(mesh_exponent - own.exponent) +
                         " times smaller than the mesh, whose largest coordinate is at vertex " + std::to_string(far) +
                         ": one linear system over the whole mesh cannot hold both scales (the face's area is "
                         "below the double range in it); move or remove that far vertex, or "
                         "parametrize the parts separately");
    }
    used[a] = used[b] = used[c] = 1;
  }
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!used[v]) {
      fail(function, "vertex " + std::to_string(v) + " is used by no face (isolated vertex): "
                     "remove unreferenced vertices first "
                     "(meshsmith.repair.remove_unreferenced)");
    }
  }
}

}  // namespace

NormalizedVertices normalized(const VertexRef& V) {
  validate_vertices(V, "V");
  NormalizedVertices result;
  result.frame = normalizing_frame(V);
  result.V = result.frame.normalize_vertices(V);
  return result;
}

CheckedMesh check_mesh(const VertexRef& V, const FaceRef& F, Requirement requirement, const char* function) {
  validate_mesh(V, F);
  check_faces(V, F, function);
  CheckedMesh mesh;
  mesh.incidence = topology::edge_incidence(F, V.rows());
  const auto& incidence = mesh.incidence;
  for (Eigen::Index e = 0; e < incidence.n_edges(); ++e) {
    if (incidence.side_count(e) > 2) {
      fail(function, "edge (" + std::to_string(incidence.edges(e, 0)) + ", " + std::to_string(incidence.edges(e, 1)) +
                         ") has " + std::to_string(incidence.side_count(e)) +
                         " incident faces (non-manifold): clean the mesh first with meshsmith.repair.clean "
                         "(`meshsmith clean` on the command line)");
    }
  }
  const auto pinched = topology::non_manifold_vertices(F, incidence);
  if (!pinched.empty()) {
    fail(function, "vertex " + std::to_string(pinched.front()) + " is non-manifold (" + std::to_string(pinched.size()) +
                       " such vertices): clean the mesh first with meshsmith.repair.clean (`meshsmith clean` "
                       "on the command line)");
  }
  if (!topology::is_oriented(F, incidence)) {
    fail(function, "the faces are not consistently oriented (or the surface is not orientable): clean the mesh "
                   "first with meshsmith.repair.clean (`meshsmith clean` on the command line)");
  }
  const auto components = topology::connected_components(F, V.rows());
  if (components.count > 1) {
    Eigen::Index other = 0;
    while (components.vertex_labels[other] == components.vertex_labels[0]) ++other;
    fail(function, "the mesh has " + std::to_string(components.count) + " connected components (vertex " +
                       std::to_string(other) + " is not connected to vertex 0): parametrize each component separately");
  }
  mesh.boundary_loops = topology::boundary_loops(F, incidence);
  mesh.euler_characteristic = topology::euler_characteristic(F, incidence);
  const auto loops = static_cast<long long>(mesh.boundary_loops.size());
  if (requirement != Requirement::any && loops == 0) {
    fail(function, "the mesh is closed (no boundary loop; genus " + std::to_string((2 - mesh.euler_characteristic) / 2) +
                       "): cut it to a disk first with parametrization.cut_to_disk");
  }
  if (requirement == Requirement::disk && !mesh.is_disk()) {
    const long long genus = (2 - mesh.euler_characteristic - loops) / 2;
    fail(function, "the mesh is not a topological disk (genus " + std::to_string(genus) + ", " + std::to_string(loops) +
                       " boundary loops): cut it to a disk first with parametrization.cut_to_disk, or give the "
                       "constrained vertices explicitly");
  }
  return mesh;
}

void check_constrained_vertices(const std::vector<int>& indices, const Eigen::Ref<const Eigen::MatrixX2d>& uv,
                                Eigen::Index n, const char* what, const char* function) {
  if (static_cast<Eigen::Index>(indices.size()) != uv.rows()) {
    fail(function, std::string(what) + " has " + std::to_string(indices.size()) + " vertices but " +
                       std::to_string(uv.rows()) + " positions were given");
  }
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const int v = indices[k];
    if (v < 0 || v >= n) {
      fail(function, std::string(what) + " entry " + std::to_string(k) + " is vertex " + std::to_string(v) +
                         ", outside [0, " + std::to_string(n) + ")");
    }
    if (seen[v]) fail(function, std::string(what) + " lists vertex " + std::to_string(v) + " twice");
    seen[v] = 1;
    if (!std::isfinite(uv(k, 0)) || !std::isfinite(uv(k, 1))) {
      fail(function, std::string(what) + " position " + std::to_string(k) + " is not finite");
    }
  }
}

}  // namespace meshsmith::parametrization::detail
