// mesh_counts FILE: reads a mesh with the meshsmith SDK and prints its counts, one "name: value"
// per line, then decimates it to half its faces (QEM) and builds its progressive mesh. Exit status 1 with a one-line message on stderr for unreadable or invalid input.
#include <meshsmith/core/build_info.h>
#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>
#include <meshsmith/decimation/decimate.h>
#include <meshsmith/decimation/progressive_mesh.h>
#include <meshsmith/io/mesh_io.h>
#include <meshsmith/topology/edge_incidence.h>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: mesh_counts FILE\n";
    return 2;
  }
  try {
    const meshsmith::io::PolygonMesh polygons = meshsmith::io::read_mesh(argv[1]);
    const meshsmith::FaceMatrix F = meshsmith::io::triangulate_fan(polygons.face_offsets, polygons.face_vertices);
    meshsmith::validate_mesh(polygons.V, F);
    std::cout << "meshsmith: " << meshsmith::version() << "\n"
              << "vertices: " << polygons.V.rows() << "\n"
              << "faces: " << F.rows() << "\n"
              << "edges: " << meshsmith::topology::edges(F).rows() << "\n";
    meshsmith::decimation::QemOptions options;
    options.target_faces = F.rows() / 2;
    const auto decimated = meshsmith::decimation::decimate_qem(polygons.V, F, options);
    std::cout << "decimated faces: " << decimated.F.rows() << "\n";
    auto progressive = meshsmith::decimation::progressive_mesh(polygons.V, F, options);
    progressive.set_level(progressive.split_count());
    const meshsmith::Mesh full = progressive.current_mesh();
    std::cout << "progressive splits: " << progressive.split_count() << "\n"
              << "progressive full level equals input: "
              << (full.V == polygons.V && full.F.rows() == F.rows() ? "yes" : "no") << "\n";
    return 0;
  } catch (const meshsmith::InputError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
