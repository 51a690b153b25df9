#pragma once
/// \file mesh_io.h
/// Reading and writing meshes and point clouds: OBJ, OFF (ASCII and binary), PLY (ASCII and
/// binary, both endiannesses), STL (ASCII and binary) and XYZ point files, with the attributes
/// each format can hold (normals, texture coordinates, vertex and face colours; see PolygonMesh
/// and check_format_holds). glTF binary (.glb) is known here by name only: the Python package
/// (meshsmith.io) reads and writes it.
///
/// Every reader maps the whole file into memory (read-only; read into a buffer where mapping is
/// unavailable) and parses it with std::from_chars and hand-rolled integer loops (text) or direct
/// byte decoding (binary); no stream is read token by token. OBJ files of 4 MB and more are
/// parsed in pieces on all cores (TBB) and joined; the result does not depend on the thread
/// count, and a file whose pieces cannot stand alone (relative indices) or that holds an error
/// is parsed in one piece, so that errors carry their true line numbers. Every count a header states
/// is checked against what the rest of the file can hold before anything is allocated, so a
/// corrupt or hostile file costs at most a small multiple of its own size in memory.
/// Errors are InputError with the file name and the line (text) or byte offset (binary).
#include <meshsmith/core/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace meshsmith::io {

/// File formats. `automatic` means "from the file extension" (case-insensitive:
/// .obj .off .ply .stl .xyz .glb). `glb` is handled by the Python package; read_mesh and write_mesh
/// here throw InputError for it.
enum class Format { automatic, obj, off, ply, stl, xyz, glb };

/// The format named by `name` ("obj", "OFF", "ply", ...).
/// \throw InputError for a name that is not one of the formats.
Format format_from_name(const std::string& name);

/// The format of `path` from its extension when `requested` is automatic, else `requested`.
/// \throw InputError (naming the file) for an unknown or missing extension.
Format resolve_format(const std::string& path, Format requested);

/// #UV by 2 texture coordinates.
using UVMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
/// #rows by 3 (RGB) or 4 (RGBA) colour components, each in [0, 1].
using ColorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A polygon mesh with optional attributes, as read from a file or given to a writer.
///
/// Faces are stored compressed: face f has the corners face_offsets[f] .. face_offsets[f+1]-1
/// of face_vertices (zero-based rows of V). face_offsets has #F+1 entries and starts at 0.
/// UV (#UV by 2) and N (#N by 3) are texture coordinates and normals with their own indices:
/// face_uvs / face_normals, when not empty, hold one index per corner (same layout as
/// face_vertices) into UV / N, or -1 where that face gave none. Per-vertex attributes are the
/// case face_uvs == face_vertices (readers give that) or, for writers, UV / N with #V rows and
/// empty corner indices. OBJ fills them from `f v/vt/vn`; PLY from
/// per-vertex properties (u,v / s,t / texture_u,texture_v and nx,ny,nz; corner indices equal to
/// the vertex indices) or per-corner face `texcoord` lists; OFF from its N and ST columns.
/// colors: #V by 3 or 4 (RGB, RGBA) in [0, 1], or 0 rows; face_colors: #F by 3 or 4, or 0 rows.
/// 8-bit file values v are stored as v / 255 (16-bit: v / 65535). Every polygon has at least 3
/// corners. warnings: one line per kind of thing a reader skipped (with its count), for the
/// caller to show.
struct PolygonMesh {
  VertexMatrix V;
  std::vector<std::int64_t> face_offsets{0};
  std::vector<int> face_vertices;
  UVMatrix UV;
  std::vector<int> face_uvs;
  VertexMatrix N;
  std::vector<int> face_normals;
  ColorMatrix colors;
  ColorMatrix face_colors;
  std::vector<std::string> warnings;
  /// A range scan's grid (PLY's `range_grid` element, with `obj_info num_rows R` and `obj_info
  /// num_cols C` in the header, as the Stanford scans store it): R·C cells in row-major order,
  /// each the vertex sampled there or -1 where the scanner saw nothing; empty when the file has
  /// none. Readers do not mesh it (meshsmith.io.read_range_scan does).
  std::vector<int> range_grid;
  std::int64_t range_grid_rows = 0, range_grid_cols = 0;

  std::int64_t face_count() const { return static_cast<std::int64_t>(face_offsets.size()) - 1; }
};

/// What read_mesh keeps beyond V and the faces.
struct ReadOptions {
  Format format = Format::automatic;
  bool with_uv = false;       ///< keep texture coordinates (UV, face_uvs)
  bool with_normals = false;  ///< keep normals (N, face_normals)
  bool with_colors = false;   ///< keep vertex and face colours
};

/// Reads the mesh of an OBJ, OFF, PLY or STL file with the attributes `options` asks for.
/// Polygons are kept as they are (see triangulate_fan). STL vertices that have exactly the same coordinates are merged so the result
/// is indexed (vertex order: first appearance). A point-cloud file gives V and no faces.
/// \throw InputError naming the file and line / byte offset: missing file, directory, empty file,
///        unknown extension, truncated data, counts that the file cannot hold, unparsable tokens,
///        non-finite coordinates, polygons with fewer than 3 corners, indices out of range.
PolygonMesh read_mesh(const std::string& path, const ReadOptions& options = {});

/// Splits every polygon of `offsets`/`corners` (layout of PolygonMesh) into a fan of triangles
/// (v0, v_i, v_i+1), in face order. #triangles = sum over faces of (size - 2).
/// \pre every face has at least 3 corners (read_mesh guarantees it).
FaceMatrix triangulate_fan(const std::vector<std::int64_t>& offsets,
                           const std::vector<int>& corners);

/// How write_mesh / write_points encode the file.
struct WriteOptions {
  Format format = Format::automatic;
  bool binary = true;       ///< PLY, STL and OFF: binary (OBJ and XYZ are always ASCII)
  bool big_endian = false;  ///< binary PLY only: binary_big_endian instead of little
};

/// What every writer relies on (write_mesh calls it first): finite values, colours with 3 or 4
/// columns in [0, 1] and one row per vertex / face, well-formed face offsets (at least 3 corners
/// each), corner indices in range (-1 allowed for UVs and normals), attribute rows matching.
/// \throw InputError naming the file, the array and the offending row or face.
void check_writable(const std::string& path, const PolygonMesh& mesh);

/// Checks that `format` can hold every attribute of `mesh` (write_mesh calls it second).
/// \throw InputError "<path>: cannot write <attribute> (...): <format> cannot hold them (...)",
///        <attribute> being the Python keyword (normals, UV, colors, face_colors), with a format
///        that can hold it, when
///        `mesh` has an attribute that `format` cannot hold:
///        STL holds none (only positions; facet normals come from them); OBJ no face colours and
///        no colour alpha below 1; PLY no per-corner normals; OFF no per-corner normals or UVs;
///        GLB no face colours and no corners without UVs or normals when others have them.
///        Per-corner attributes whose corners agree at every vertex count as per-vertex.
void check_format_holds(const std::string& path, const PolygonMesh& mesh, Format format);

/// Writes a mesh with every attribute it has. Coordinates and attributes in text formats are
/// printed in the shortest form that reads back to the same double (exact round trip); binary
/// PLY stores doubles (exact; colours as uchar when every value is a multiple of 1/255, else
/// double); binary OFF and binary STL store float32, as those formats prescribe (binary OFF
/// colours as 4 floats RGBA). OBJ writes UV / N with `f v/vt/vn` and colours as `v x y z r g b`;
/// PLY writes per-vertex N (nx ny nz), UV (texture_u texture_v, or a face `texcoord` list of
/// u v pairs when they are per corner) and colours (red green blue [alpha]) on the vertex and
/// face elements; OFF writes the [ST][C][N]OFF columns and colours after each face's indices.
/// STL gets fan-triangulated polygons and per-facet normals.
/// \throw InputError for unknown formats, indices out of range, non-finite values, colours
///        outside [0, 1], faces with fewer than 3 corners, attribute row counts that do not match,
///        attributes the format cannot hold (check_format_holds), or a file that cannot be
///        written.
void write_mesh(const std::string& path, const PolygonMesh& mesh, const WriteOptions& options);

/// A point cloud: P (#P by 3) and optional normals N (#P by 3, or 0 rows when absent).
struct PointCloud {
  VertexMatrix P;
  VertexMatrix N;
};

/// Values per vertex from values indexed per corner: out.row(v) = values.row(corners[k]) for the
/// corners k of vertex v. False when some corner has no index (-1) or two corners of one vertex
/// have different values; vertices no face uses get zeros. Empty `corners` mean "per vertex"
/// (true when values has #V rows). Exact when `corners` is empty or equals mesh.face_vertices and
/// values has #V rows (the rows are copied).
template <typename Matrix>
bool per_vertex_values(const PolygonMesh& mesh, const Matrix& values,
                       const std::vector<int>& corners, Matrix& out) {
  if (values.rows() == 0) return false;
  if ((corners.empty() || corners == mesh.face_vertices) && values.rows() == mesh.V.rows()) {
    out = values;
    return true;
  }
  if (corners.empty()) return false;
  out = Matrix::Zero(mesh.V.rows(), values.cols());
  std::vector<int> chosen(static_cast<std::size_t>(mesh.V.rows()), -1);
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const int index = corners[k], vertex = mesh.face_vertices[k];
    if (index < 0) return false;
    int& first = chosen[static_cast<std::size_t>(vertex)];
    if (first == -1) {
      first = index;
      out.row(vertex) = values.row(index);
    } else if (first != index && values.row(first) != values.row(index)) {
      return false;
    }
  }
  return true;
}

/// Reads an XYZ file (3 or 6 numbers per line, '#' comments) or a PLY file (x,y,z and optional
/// nx,ny,nz of its vertex element; other elements, faces included, are skipped).
/// \throw InputError as read_mesh, and for XYZ lines whose column count differs from the first.
PointCloud read_points(const std::string& path, Format format = Format::automatic);

/// Writes P (and N when it has rows) as XYZ (ASCII) or PLY (binary by default).
/// \throw InputError when N has rows but not as many as P, for non-finite values, for formats
///        other than XYZ and PLY, or when the file cannot be written.
void write_points(const std::string& path, const PointCloud& points,
                  const WriteOptions& options);

}  // namespace meshsmith::io
