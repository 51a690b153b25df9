// Format dispatch, file access, fan triangulation and the checks every writer shares.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/mesh_io.h>
#include <meshsmith/io/parsing.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <system_error>

#if defined(__unix__) || defined(__APPLE__)
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>
#ifdef MAP_POPULATE
#define MAP_POPULATE_IF_AVAILABLE MAP_POPULATE
#else
#define MAP_POPULATE_IF_AVAILABLE 0
#endif
#endif

namespace meshsmith::io {

namespace {

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

/// \throw InputError unless every value of `matrix` is finite.
template <typename Matrix>
void check_finite(const std::string& path, const Matrix& matrix, const char* name) {
  for (Eigen::Index r = 0; r < matrix.rows(); ++r)
    for (Eigen::Index c = 0; c < matrix.cols(); ++c)
      if (!std::isfinite(matrix(r, c)))
        throw InputError(path + ": cannot write: " + name + " row " + std::to_string(r) +
                         " is not finite");
}

/// \throw InputError unless `corners` (same layout as face_vertices) index [0, count) or are -1
/// where `allow_missing`.
void check_corner_indices(const std::string& path, const PolygonMesh& mesh,
                          const std::vector<int>& corners, Eigen::Index count, const char* name,
                          bool allow_missing) {
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const int index = corners[k];
    if ((index >= 0 && index < count) || (allow_missing && index == -1)) continue;
    const auto face = std::upper_bound(mesh.face_offsets.begin(), mesh.face_offsets.end(),
                                       static_cast<std::int64_t>(k)) - mesh.face_offsets.begin() - 1;
    throw InputError(path + ": cannot write: face " + std::to_string(face) + " has " + name +
                     " index " + std::to_string(index) + " outside [0, " + std::to_string(count) + ")");
  }
}

/// \throw InputError unless `colors` is empty or has `rows` rows of 3 or 4 values in [0, 1].
void check_colors(const std::string& path, const ColorMatrix& colors, const char* name,
                  Eigen::Index rows, const char* what) {
  if (colors.rows() == 0) return;
  if (colors.rows() != rows || (colors.cols() != 3 && colors.cols() != 4))
    throw InputError(path + ": cannot write: " + name + " has shape (" +
                     std::to_string(colors.rows()) + ", " + std::to_string(colors.cols()) +
                     "); expected (" + std::to_string(rows) + ", 3) or (" + std::to_string(rows) +
                     ", 4), one RGB or RGBA row per " + std::string(what).substr(0, std::strlen(what) - 1));
  for (Eigen::Index r = 0; r < colors.rows(); ++r)
    for (Eigen::Index c = 0; c < colors.cols(); ++c)
      if (!(colors(r, c) >= 0.0 && colors(r, c) <= 1.0))
        throw InputError(path + ": cannot write: " + name + " row " + std::to_string(r) +
                         " holds " + std::to_string(colors(r, c)) +
                         " (colour components are in [0, 1])");
}

const char* format_name(Format format) {
  switch (format) {
    case Format::obj: return "OBJ";
    case Format::off: return "OFF";
    case Format::ply: return "PLY";
    case Format::stl: return "STL";
    case Format::xyz: return "XYZ";
    case Format::glb: return "GLB";
    default: return "automatic";
  }
}

}  // namespace

void check_writable(const std::string& path, const PolygonMesh& mesh) {
  check_finite(path, mesh.V, "V");
  check_finite(path, mesh.UV, "UV");
  check_finite(path, mesh.N, "N");
  check_colors(path, mesh.colors, "colors", mesh.V.rows(), "vertices");
  check_colors(path, mesh.face_colors, "face_colors", mesh.face_count(), "faces");
  const auto& offsets = mesh.face_offsets;
  if (offsets.empty() || offsets.front() != 0)
    throw InputError(path + ": cannot write: face offsets must start at 0");
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
    if (offsets[f + 1] - offsets[f] < 3)
      throw InputError(path + ": cannot write: face " + std::to_string(f) + " has " +
                       std::to_string(offsets[f + 1] - offsets[f]) +
                       " corners (at least 3 needed)");
  if (offsets.back() != static_cast<std::int64_t>(mesh.face_vertices.size()))
    throw InputError(path + ": cannot write: the face offsets end at " +
                     std::to_string(offsets.back()) + " but there are " +
                     std::to_string(mesh.face_vertices.size()) + " corner indices");
  check_corner_indices(path, mesh, mesh.face_vertices, mesh.V.rows(), "vertex", false);
  // Normals or UVs without corner indices are per vertex: one row per vertex.
  if (mesh.N.rows() > 0 && mesh.face_normals.empty() && mesh.N.rows() != mesh.V.rows())
    throw InputError(path + ": cannot write: N has " + std::to_string(mesh.N.rows()) +
                     " rows and no corner indices (F_normal), but there are " +
                     std::to_string(mesh.V.rows()) + " vertices");
  if (mesh.UV.rows() > 0 && mesh.face_uvs.empty() && mesh.UV.rows() != mesh.V.rows())
    throw InputError(path + ": cannot write: UV has " + std::to_string(mesh.UV.rows()) +
                     " rows and no corner indices (F_uv), but there are " +
                     std::to_string(mesh.V.rows()) + " vertices");
  if (!mesh.face_uvs.empty()) {
    if (mesh.face_uvs.size() != mesh.face_vertices.size())
      throw InputError(path + ": cannot write: F_uv must have one index per face corner");
    check_corner_indices(path, mesh, mesh.face_uvs, mesh.UV.rows(), "texture coordinate", true);
  }
  if (!mesh.face_normals.empty()) {
    if (mesh.face_normals.size() != mesh.face_vertices.size())
      throw InputError(path + ": cannot write: F_normal must have one index per face corner");
    check_corner_indices(path, mesh, mesh.face_normals, mesh.N.rows(), "normal", true);
  }
}

FileContents read_file_contents(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found)
    throw InputError(path + ": file does not exist");
  if (status.type() == fs::file_type::directory)
    throw InputError(path + ": is a directory, not a file");
  if (error) throw InputError(path + ": cannot access file: " + error.message());
  if (status.type() != fs::file_type::regular)
    throw InputError(path + ": not a regular file");
  const auto size = static_cast<std::size_t>(fs::file_size(path, error));
  if (error) throw InputError(path + ": cannot read file size: " + error.message());
  if (size == 0) throw InputError(path + ": file is empty");
#if defined(__unix__) || defined(__APPLE__)
  const int descriptor = ::open(path.c_str(), O_RDONLY);
  if (descriptor < 0) throw InputError(path + ": cannot open file: " + std::strerror(errno));
  void* mapping = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE_IF_AVAILABLE, descriptor, 0);
  ::close(descriptor);
  if (mapping != MAP_FAILED) return FileContents(mapping, size);
#endif
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw InputError(path + ": cannot open file: " + std::strerror(errno));
  std::unique_ptr<char[]> data(new char[size]);
  if (std::fread(data.get(), 1, size, file.get()) != size)
    throw InputError(path + ": cannot read the whole file");
  return FileContents(std::move(data), size);
}

FileContents::~FileContents() {
#if defined(__unix__) || defined(__APPLE__)
  if (mapping_) ::munmap(const_cast<void*>(mapping_), size_);
#endif
}

void write_file_contents(const std::string& path, std::string_view contents) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file)
    throw InputError(path + ": cannot open file for writing: " + std::strerror(errno));
  if (std::fwrite(contents.data(), 1, contents.size(), file.get()) != contents.size())
    throw InputError(path + ": cannot write file: " + std::strerror(errno));
  if (std::fclose(file.release()) != 0)
    throw InputError(path + ": cannot write file: " + std::strerror(errno));
}

Format format_from_name(const std::string& name) {
  const std::string lower = lowercase(name);
  if (lower == "obj") return Format::obj;
  if (lower == "off") return Format::off;
  if (lower == "ply") return Format::ply;
  if (lower == "stl") return Format::stl;
  if (lower == "xyz") return Format::xyz;
  if (lower == "glb") return Format::glb;
  throw InputError("unknown file format '" + name + "' (expected obj, off, ply, stl, glb or xyz)");
}

Format resolve_format(const std::string& path, Format requested) {
  if (requested != Format::automatic) return requested;
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension.size() < 2)
    throw InputError(path + ": no file extension to tell the format (pass format=...)");
  try {
    return format_from_name(extension.substr(1));
  } catch (const InputError&) {
    throw InputError(path + ": unknown file extension '" + extension +
                     "' (expected .obj, .off, .ply, .stl, .glb or .xyz, or pass format=...)");
  }
}

FaceMatrix triangulate_fan(const std::vector<std::int64_t>& offsets,
                           const std::vector<int>& corners) {
  std::int64_t triangles = 0;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f)
    triangles += std::max<std::int64_t>(0, offsets[f + 1] - offsets[f] - 2);
  FaceMatrix F(triangles, 3);
  Eigen::Index row = 0;
  for (std::size_t f = 0; f + 1 < offsets.size(); ++f) {
    const std::int64_t begin = offsets[f], end = offsets[f + 1];
    for (std::int64_t k = begin + 1; k + 1 < end; ++k, ++row) {
      F(row, 0) = corners[begin];
      F(row, 1) = corners[k];
      F(row, 2) = corners[k + 1];
    }
  }
  return F;
}

PolygonMesh read_mesh(const std::string& path, const ReadOptions& options) {
  const Format format = resolve_format(path, options.format);
  if (format == Format::xyz)
    throw InputError(path + ": XYZ files hold point clouds, not meshes (use read_points)");
  if (format == Format::glb)
    throw InputError(path + ": GLB files are read by the Python package (meshsmith.io.read_mesh)");
  const FileContents contents = read_file_contents(path);
  PolygonMesh mesh;
  switch (format) {
    case Format::obj: mesh = parse_obj(path, contents, options); break;
    case Format::off: mesh = parse_off(path, contents); break;
    case Format::ply: mesh = parse_ply(path, contents, true); break;
    case Format::stl: mesh = parse_stl(path, contents); break;
    default: break;
  }
  if (!options.with_uv) {
    mesh.UV.resize(0, 2);
    mesh.face_uvs.clear();
  }
  if (!options.with_normals) {
    mesh.N.resize(0, 3);
    mesh.face_normals.clear();
  }
  if (!options.with_colors) {
    mesh.colors.resize(0, 3);
    mesh.face_colors.resize(0, 3);
  }
  return mesh;
}

void write_mesh(const std::string& path, const PolygonMesh& mesh, const WriteOptions& options) {
  const Format format = resolve_format(path, options.format);
  if (format == Format::glb)
    throw InputError(path + ": GLB files are written by the Python package (meshsmith.io.write_mesh)");
  check_writable(path, mesh);
  check_format_holds(path, mesh, format);
  if (options.binary && (format == Format::stl || format == Format::off)) {
    const double largest = mesh.V.size() ? mesh.V.cwiseAbs().maxCoeff() : 0.0;
    if (largest > static_cast<double>(std::numeric_limits<float>::max()))
      throw InputError(path + ": cannot write: binary " + format_name(format) +
                       " stores float32 and V holds " + std::to_string(largest));
  }
  if (format == Format::stl && mesh.face_count() == 0)
    throw InputError(path + ": cannot write: an STL file needs at least one face");
  std::string contents;
  switch (format) {
    case Format::obj: contents = format_obj(mesh); break;
    case Format::off: contents = format_off(mesh, options.binary); break;
    case Format::ply: contents = format_ply(mesh, options.binary, options.big_endian); break;
    case Format::stl: contents = format_stl(mesh, options.binary); break;
    default:
      throw InputError(path + ": cannot write a mesh as " + format_name(format) +
                       " (use write_points for point clouds)");
  }
  write_file_contents(path, contents);
}

void check_format_holds(const std::string& path, const PolygonMesh& mesh, Format format) {
  format = resolve_format(path, format);
  const char* name = format_name(format);
  auto refuse = [&](const std::string& attribute, const std::string& instead) {
    throw InputError(path + ": cannot write " + attribute + ": " + name + " cannot hold them (" +
                     instead + ")");
  };
  const bool normals = mesh.N.rows() > 0, uvs = mesh.UV.rows() > 0;
  const bool colors = mesh.colors.rows() > 0, face_colors = mesh.face_colors.rows() > 0;
  VertexMatrix vertex_normals;
  UVMatrix vertex_uvs;
  switch (format) {
    case Format::stl:
      // Suggest only formats that hold them as they are (per vertex or per corner).
      if (normals)
        refuse("normals", std::string("STL stores facet normals computed from the positions; ") +
                              (per_vertex_values(mesh, mesh.N, mesh.face_normals, vertex_normals)
                                   ? "write OBJ, PLY, OFF or GLB" : "write OBJ or GLB"));
      if (uvs)
        refuse("UV (texture coordinates)", per_vertex_values(mesh, mesh.UV, mesh.face_uvs, vertex_uvs)
                                               ? "write OBJ, PLY, OFF or GLB" : "write OBJ, PLY or GLB");
      if (colors) refuse("colors (vertex colours)", "write PLY, OFF, OBJ or GLB");
      if (face_colors) refuse("face_colors (face colours)", "write PLY or OFF");
      break;
    case Format::obj:
      if (face_colors) refuse("face_colors (face colours)", "write PLY or OFF");
      if (colors && mesh.colors.cols() == 4)
        for (Eigen::Index r = 0; r < mesh.colors.rows(); ++r)
          if (mesh.colors(r, 3) != 1.0)
            refuse("colors with alpha (row " + std::to_string(r) + " has alpha " +
                       std::to_string(mesh.colors(r, 3)) + ")",
                   "OBJ colours are r g b; write PLY, OFF or GLB");
      break;
    case Format::ply:
      if (normals && !per_vertex_values(mesh, mesh.N, mesh.face_normals, vertex_normals))
        refuse("normals (per corner)", "PLY normals are per vertex; write OBJ or GLB");
      break;
    case Format::glb:
      if (face_colors) refuse("face_colors (face colours)", "glTF colours are per vertex; write PLY or OFF");
      if (uvs && std::find(mesh.face_uvs.begin(), mesh.face_uvs.end(), -1) != mesh.face_uvs.end())
        refuse("UV (texture coordinates) on only some corners", "glTF vertices have all or none; write OBJ or PLY");
      if (normals && std::find(mesh.face_normals.begin(), mesh.face_normals.end(), -1) != mesh.face_normals.end())
        refuse("normals on only some corners", "glTF vertices have all or none; write OBJ");
      break;
    case Format::off:
      if (normals && !per_vertex_values(mesh, mesh.N, mesh.face_normals, vertex_normals))
        refuse("normals (per corner)", "OFF normals are per vertex; write OBJ or GLB");
      if (uvs && !per_vertex_values(mesh, mesh.UV, mesh.face_uvs, vertex_uvs))
        refuse("UV (per-corner texture coordinates)", "OFF texture coordinates are per vertex; write OBJ, PLY or GLB");
      break;
    default: break;
  }
}

PointCloud read_points(const std::string& path, Format requested) {
  const Format format = resolve_format(path, requested);
  if (format != Format::xyz && format != Format::ply)
    throw InputError(path + ": read_points reads XYZ and PLY files, not " + format_name(format));
  const FileContents contents = read_file_contents(path);
  if (format == Format::xyz) return parse_xyz(path, contents);
  PolygonMesh mesh = parse_ply(path, contents, false);
  PointCloud points;
  points.P = std::move(mesh.V);
  if (mesh.N.rows() == points.P.rows()) points.N = std::move(mesh.N);
  return points;
}

void write_points(const std::string& path, const PointCloud& points,
                  const WriteOptions& options) {
  const Format format = resolve_format(path, options.format);
  if (points.N.rows() != 0 && points.N.rows() != points.P.rows())
    throw InputError(path + ": cannot write: N has " + std::to_string(points.N.rows()) +
                     " rows but P has " + std::to_string(points.P.rows()));
  check_finite(path, points.P, "P");
  check_finite(path, points.N, "N");
  std::string contents;
  if (format == Format::xyz) {
    contents = format_xyz(points);
  } else if (format == Format::ply) {
    PolygonMesh cloud;
    cloud.V = points.P;
    cloud.N = points.N;
    contents = format_ply(cloud, options.binary, options.big_endian);
  } else {
    throw InputError(path + ": write_points writes XYZ and PLY files, not " +
                     format_name(format));
  }
  write_file_contents(path, contents);
}

}  // namespace meshsmith::io
