// Bindings of the io chapter: read/write meshes and point clouds (meshsmith::io).
#include "bindings.h"
#include "convert.h"

#include <meshsmith/io/mesh_io.h>

namespace meshsmith::python {

namespace {

using Int64Column = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>;
using Int64Triangles = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

io::Format format_argument(const py::object& format);

io::WriteOptions write_options(const py::object& format, bool binary, bool big_endian) {
  io::WriteOptions options;
  options.format = format_argument(format);
  options.binary = binary;
  options.big_endian = big_endian;
  return options;
}

io::Format format_argument(const py::object& format) {
  if (format.is_none()) return io::Format::automatic;
  return io::format_from_name(py::str(format));
}

/// Fan triangles of polygons (offsets, corners) as int64; one pass when all are triangles.
Int64Triangles triangles_int64(const std::vector<std::int64_t>& offsets, const std::vector<int>& corners) {
  const auto faces = static_cast<Eigen::Index>(offsets.size()) - 1;
  if (offsets.back() == 3 * static_cast<std::int64_t>(faces))  // every face has >= 3 corners
    return Eigen::Map<const FaceMatrix>(corners.data(), faces, 3).cast<std::int64_t>();
  return io::triangulate_fan(offsets, corners).cast<std::int64_t>();
}

Int64Column to_int64(const std::vector<int>& values) {
  Int64Column out(static_cast<Eigen::Index>(values.size()));
  for (std::size_t k = 0; k < values.size(); ++k) out[k] = values[k];
  return out;
}

Int64Column to_int64(const std::vector<std::int64_t>& values) {
  return Eigen::Map<const Int64Column>(values.data(), static_cast<Eigen::Index>(values.size()));
}

/// Flat corner indices from an (n, columns) integer array-like (checked by as_index_matrix).
std::vector<int> corner_indices(const py::object& object, const char* name, Eigen::Index columns) {
  IndexArray array = as_index_matrix(object, name, columns);
  return std::vector<int>(array.data(), array.data() + array.size());
}

/// Colours as an (n, 3) or (n, 4) array-like of reals.
io::ColorMatrix color_rows(const py::object& object, const char* name) {
  RealArray array;
  try {
    array = as_real_matrix(object, name, 3);
  } catch (const InputError& rgb) {
    try {
      array = as_real_matrix(object, name, 4);
    } catch (const InputError&) {
      throw InputError(std::string(rgb.what()) + " (colours are RGB (n, 3) or RGBA (n, 4))");
    }
  }
  return Eigen::Map<const io::ColorMatrix>(array.data(), array.shape(0), array.shape(1));
}

/// Rows of `colors` (one per polygon) repeated for each fan triangle of its polygon.
io::ColorMatrix per_triangle(const io::ColorMatrix& colors, const std::vector<std::int64_t>& offsets) {
  if (colors.rows() == 0 || offsets.back() == 3 * (static_cast<std::int64_t>(offsets.size()) - 1)) return colors;
  std::int64_t triangles = 0;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) triangles += offsets[f + 1] - offsets[f] - 2;
  io::ColorMatrix out(triangles, colors.cols());
  Eigen::Index row = 0;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
    for (std::int64_t k = 0; k < offsets[f + 1] - offsets[f] - 2; ++k) out.row(row++) = colors.row(f);
  return out;
}

VertexMatrix real_rows(const py::object& object, const char* name, Eigen::Index columns) {
  RealArray array = as_real_matrix(object, name, columns);
  VertexMatrix out(array.shape(0), 3);
  for (py::ssize_t r = 0; r < array.shape(0); ++r)
    for (py::ssize_t c = 0; c < 3; ++c) out(r, c) = c < columns ? array.data()[r * columns + c] : 0.0;
  return out;
}

/// The mesh that write_mesh's arguments describe. Triangles: F (m, 3), F_uv / F_normal (m, 3).
/// Polygons: F is the flat corner list (k, 1) with `offsets` (m+1, 1), and F_uv / F_normal are
/// flat lists like F. UV / N without corner indices are per vertex (the writers check their
/// row count).
io::PolygonMesh mesh_argument(const py::object& V, const py::object& F, const py::object& offsets,
                            const py::object& UV, const py::object& F_uv, const py::object& N,
                            const py::object& F_normal, const py::object& colors,
                            const py::object& face_colors) {
  const bool polygons = !offsets.is_none();
  const Eigen::Index columns = polygons ? 1 : 3;
  io::PolygonMesh mesh;
  mesh.V = VertexMatrix(map_vertices(as_real_matrix(V, "V", 3)));
  mesh.face_vertices = corner_indices(F, polygons ? "faces.indices" : "F", columns);
  if (polygons) {
    std::vector<int> starts = corner_indices(offsets, "faces.offsets", 1);
    mesh.face_offsets.assign(starts.begin(), starts.end());
  } else {
    mesh.face_offsets.resize(mesh.face_vertices.size() / 3 + 1);
    for (std::size_t f = 0; f < mesh.face_offsets.size(); ++f) mesh.face_offsets[f] = 3 * static_cast<std::int64_t>(f);
  }
  if (!UV.is_none()) {
    mesh.UV = real_rows(UV, "UV", 2).leftCols<2>();
    if (!F_uv.is_none()) mesh.face_uvs = corner_indices(F_uv, "F_uv", columns);
  } else if (!F_uv.is_none()) {
    throw InputError("F_uv given without UV");
  }
  if (!N.is_none()) {
    mesh.N = VertexMatrix(map_vertices(as_real_matrix(N, "N", 3)));
    if (!F_normal.is_none()) mesh.face_normals = corner_indices(F_normal, "F_normal", columns);
  } else if (!F_normal.is_none()) {
    throw InputError("F_normal given without N");
  }
  if (!colors.is_none()) mesh.colors = color_rows(colors, "colors");
  if (!face_colors.is_none()) mesh.face_colors = color_rows(face_colors, "face_colors");
  return mesh;
}

}  // namespace

void bind_io(py::module_& m) {
  m.def("read_mesh", [](const std::string& path, const py::object& format, bool triangulate,
                        bool with_uv, bool with_normals, bool with_colors) {
    io::ReadOptions options;
    options.format = format_argument(format);
    options.with_uv = with_uv;
    options.with_normals = with_normals;
    options.with_colors = with_colors;
    io::PolygonMesh mesh;
    Int64Triangles F, F_uv, F_normal;
    Int64Column offsets, indices, uv_indices, normal_indices;
    {
      py::gil_scoped_release release;
      mesh = io::read_mesh(path, options);
      if (triangulate) {
        F = triangles_int64(mesh.face_offsets, mesh.face_vertices);
        if (!mesh.face_uvs.empty()) F_uv = triangles_int64(mesh.face_offsets, mesh.face_uvs);
        if (!mesh.face_normals.empty()) F_normal = triangles_int64(mesh.face_offsets, mesh.face_normals);
        mesh.face_colors = per_triangle(mesh.face_colors, mesh.face_offsets);
      } else {
        offsets = to_int64(mesh.face_offsets);
        indices = to_int64(mesh.face_vertices);
        uv_indices = to_int64(mesh.face_uvs);
        normal_indices = to_int64(mesh.face_normals);
      }
    }
    py::dict out;
    out["V"] = to_numpy(std::move(mesh.V));
    const bool has_uv = !mesh.face_uvs.empty(), has_normals = !mesh.face_normals.empty();
    out["UV"] = has_uv ? py::object(to_numpy(std::move(mesh.UV))) : py::none();
    out["N"] = has_normals ? py::object(to_numpy(std::move(mesh.N))) : py::none();
    const bool has_colors = mesh.colors.rows() > 0, has_face_colors = mesh.face_colors.rows() > 0;
    out["colors"] = has_colors ? py::object(to_numpy(std::move(mesh.colors))) : py::none();
    out["face_colors"] = has_face_colors ? py::object(to_numpy(std::move(mesh.face_colors))) : py::none();
    py::list warnings;
    for (const std::string& warning : mesh.warnings) warnings.append(warning);
    out["warnings"] = warnings;
    if (mesh.range_grid_rows > 0 && mesh.range_grid_cols > 0) {
      py::array_t<std::int64_t> grid({mesh.range_grid_rows, mesh.range_grid_cols});
      std::copy(mesh.range_grid.begin(), mesh.range_grid.end(), grid.mutable_data());
      out["range_grid"] = grid;
    } else {
      out["range_grid"] = py::none();
    }
    if (triangulate) {
      out["F"] = to_numpy(std::move(F));
      out["F_uv"] = has_uv ? py::object(to_numpy(std::move(F_uv))) : py::none();
      out["F_normal"] = has_normals ? py::object(to_numpy(std::move(F_normal))) : py::none();
    } else {
      out["offsets"] = to_numpy(std::move(offsets));
      out["indices"] = to_numpy(std::move(indices));
      out["uv_indices"] = has_uv ? py::object(to_numpy(std::move(uv_indices))) : py::none();
      out["normal_indices"] = has_normals ? py::object(to_numpy(std::move(normal_indices))) : py::none();
    }
    return out;
  }, py::arg("path"), py::arg("format") = py::none(), py::arg("triangulate") = true,
     py::arg("with_uv") = false, py::arg("with_normals") = false, py::arg("with_colors") = false,
     "Reads a mesh file; returns a dict of numpy arrays (see meshsmith.io.read_mesh).");

  m.def("write_mesh", [](const std::string& path, const py::object& V, const py::object& F,
                         const py::object& offsets, const py::object& UV, const py::object& F_uv,
                         const py::object& N, const py::object& F_normal,
                         const py::object& colors, const py::object& face_colors,
                         const py::object& format, bool binary, bool big_endian) {
    const io::WriteOptions options = write_options(format, binary, big_endian);
    const io::PolygonMesh mesh = mesh_argument(V, F, offsets, UV, F_uv, N, F_normal, colors, face_colors);
    py::gil_scoped_release release;
    io::write_mesh(path, mesh, options);
  }, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("offsets") = py::none(),
     py::arg("UV") = py::none(), py::arg("F_uv") = py::none(), py::arg("N") = py::none(),
     py::arg("F_normal") = py::none(), py::arg("colors") = py::none(),
     py::arg("face_colors") = py::none(), py::arg("format") = py::none(), py::arg("binary") = true,
     py::arg("big_endian") = false);

  m.def("checked_mesh", [](const std::string& path, const py::object& V, const py::object& F,
                           const py::object& offsets, const py::object& UV, const py::object& F_uv,
                           const py::object& N, const py::object& F_normal,
                           const py::object& colors, const py::object& face_colors,
                           const py::object& format) {
    // write_mesh's conversions and checks for a writer in Python (GLB): the mesh as flat arrays.
    io::PolygonMesh mesh = mesh_argument(V, F, offsets, UV, F_uv, N, F_normal, colors, face_colors);
    io::check_writable(path, mesh);
    io::check_format_holds(path, mesh, format_argument(format));
    py::dict out;
    auto optional = [](auto&& matrix) {
      return matrix.rows() > 0 ? py::object(to_numpy(std::move(matrix))) : py::object(py::none());
    };
    auto corners = [](const std::vector<int>& values) {
      return values.empty() ? py::object(py::none()) : py::object(to_numpy(to_int64(values)));
    };
    out["offsets"] = to_numpy(to_int64(mesh.face_offsets));
    out["indices"] = to_numpy(to_int64(mesh.face_vertices));
    out["uv_indices"] = corners(mesh.face_uvs);
    out["normal_indices"] = corners(mesh.face_normals);
    out["V"] = to_numpy(std::move(mesh.V));
    out["UV"] = optional(std::move(mesh.UV));
    out["N"] = optional(std::move(mesh.N));
    out["colors"] = optional(std::move(mesh.colors));
    out["face_colors"] = optional(std::move(mesh.face_colors));
    return out;
  }, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("offsets") = py::none(),
     py::arg("UV") = py::none(), py::arg("F_uv") = py::none(), py::arg("N") = py::none(),
     py::arg("F_normal") = py::none(), py::arg("colors") = py::none(),
     py::arg("face_colors") = py::none(), py::arg("format") = py::none());

  m.def("read_points", [](const std::string& path, const py::object& format) {
    io::PointCloud points;
    const io::Format requested = format_argument(format);
    {
      py::gil_scoped_release release;
      points = io::read_points(path, requested);
    }
    const bool normals = points.N.rows() > 0;
    return py::make_tuple(to_numpy(std::move(points.P)),
                          normals ? py::object(to_numpy(std::move(points.N))) : py::none());
  }, py::arg("path"), py::arg("format") = py::none());

  m.def("write_points", [](const std::string& path, const py::object& P, const py::object& N,
                           const py::object& format, bool binary, bool big_endian) {
    io::PointCloud points;
    const io::WriteOptions options = write_options(format, binary, big_endian);
    points.P = VertexMatrix(map_vertices(as_real_matrix(P, "P", 3)));
    if (!N.is_none()) points.N = VertexMatrix(map_vertices(as_real_matrix(N, "N", 3)));
    py::gil_scoped_release release;
    io::write_points(path, points, options);
  }, py::arg("path"), py::arg("P"), py::arg("N") = py::none(), py::arg("format") = py::none(),
     py::arg("binary") = true, py::arg("big_endian") = false);

  m.def("triangulate_fan", [](const py::object& offsets, const py::object& indices) {
    std::vector<int> starts = corner_indices(offsets, "offsets", 1);
    std::vector<int> corners = corner_indices(indices, "indices", 1);
    // Same checks as the writers: offsets start at 0, grow by >= 3, end at len(indices).
    if (starts.empty() || starts.front() != 0) throw InputError("offsets must start at 0");
    for (std::size_t f = 0; f + 1 < starts.size(); ++f)
      if (starts[f + 1] - starts[f] < 3)
        throw InputError("polygon " + std::to_string(f) + " has fewer than 3 corners");
    if (static_cast<std::size_t>(starts.back()) != corners.size())
      throw InputError("offsets must end at len(indices)");
    std::vector<std::int64_t> wide(starts.begin(), starts.end());
    Int64Triangles F = io::triangulate_fan(wide, corners).cast<std::int64_t>();
    return to_numpy(std::move(F));
  }, py::arg("offsets"), py::arg("indices"));
}

}  // namespace meshsmith::python
