#include <meshsmith/core/errors.h>
#include <meshsmith/core/mesh.h>
#include <meshsmith/core/validation.h>

#include <OpenMesh/Core/System/omstream.hh>

#include <sstream>
#include <vector>

namespace meshsmith {

TriMesh to_trimesh(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F, /*allow_empty_faces=*/true);
  TriMesh mesh;
  mesh.reserve(V.rows(), 3 * F.rows() / 2, F.rows());
  std::vector<TriMesh::VertexHandle> handles(V.rows());
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    handles[v] = mesh.add_vertex(TriMesh::Point(V(v, 0), V(v, 1), V(v, 2)));
  }
  // OpenMesh prints "complex edge" to its error stream for a rejected face; we report it as an
  // InputError instead, so silence the stream while adding faces.
  struct SilenceOpenMeshErrors {
    bool was_enabled = omerr().is_enabled();
    SilenceOpenMeshErrors() { omerr().disable(); }
    ~SilenceOpenMeshErrors() { if (was_enabled) omerr().enable(); }
  } silence;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (a == b || b == c || a == c) {
      std::ostringstream message;  // in the error branches only: one per face is slow
      message << "F[" << f << "] = (" << a << ", " << b << ", " << c << ") repeats a vertex";
      throw InputError(message.str());
    }
    const auto face = mesh.add_face(handles[a], handles[b], handles[c]);
    if (!face.is_valid()) {
      std::ostringstream message;
      message << "F[" << f << "] = (" << a << ", " << b << ", " << c
              << ") makes the mesh non-manifold (an edge with more than two faces, a vertex whose"
                 " faces do not form one fan, or inconsistent orientation); run"
                 " topology.split_non_manifold_vertices or repair first";
      throw InputError(message.str());
    }
  }
  return mesh;
}

Mesh from_trimesh(const TriMesh& mesh) {
  Mesh result;
  std::vector<int> new_index(mesh.n_vertices(), -1);
  int count = 0;
  for (auto v : mesh.vertices()) new_index[v.idx()] = count++;
  result.V.resize(count, 3);
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    result.V.row(new_index[v.idx()]) << p[0], p[1], p[2];
  }
  result.F.resize(static_cast<Eigen::Index>(mesh.n_faces()), 3);
  Eigen::Index row = 0;
  for (auto f : mesh.faces()) {
    int corner = 0;
    for (auto v : f.vertices()) result.F(row, corner++) = new_index[v.idx()];
    ++row;
  }
  result.F.conservativeResize(row, 3);
  return result;
}

}  // namespace meshsmith
