#pragma once
/// \file mesh_io.h
/// Reading and writing meshes and point clouds: OBJ, OFF (ASCII and binary), PLY (ASCII and
/// binary, both endiannesses), STL (ASCII and binary) and XYZ point files.
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
/// .obj .off .ply .stl .xyz).
enum class Format { automatic, obj, off, ply, stl, xyz };

/// The format named by `name` ("obj", "OFF", "ply", ...).
/// \throw InputError for a name that is not one of the formats.
Format format_from_name(const std::string& name);

/// The format of `path` from its extension when `requested` is automatic, else `requested`.
/// \throw InputError (naming the file) for an unknown or missing extension.
Format resolve_format(const std::string& path, Format requested);

/// #UV by 2 texture coordinates.
using UVMatrix = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// A polygon mesh with optional per-corner attributes, as read from a file.
///
/// Faces are stored compressed: face f has the corners face_offsets[f] .. face_offsets[f+1]-1
/// of face_vertices (zero-based rows of V). face_offsets has #F+1 entries and starts at 0.
/// UV (#UV by 2) and N (#N by 3) are texture coordinates and normals; face_uvs / face_normals,
/// when not empty, hold one index per corner (same layout as face_vertices) into UV / N, or -1
/// where that face gave none. OBJ fills them from `f v/vt/vn`; PLY fills UV and N from per-vertex
/// properties (u,v / s,t / texture_u,texture_v and nx,ny,nz) with the corner indices equal to the
/// vertex indices. Every polygon has at least 3 corners.
struct PolygonMesh {
  VertexMatrix V;
  std::vector<std::int64_t> face_offsets{0};
  std::vector<int> face_vertices;
  UVMatrix UV;
  std::vector<int> face_uvs;
  VertexMatrix N;
  std::vector<int> face_normals;

  std::int64_t face_count() const { return static_cast<std::int64_t>(face_offsets.size()) - 1; }
};

/// What read_mesh keeps beyond V and the faces.
struct ReadOptions {
  Format format = Format::automatic;
  bool with_uv = false;       ///< keep texture coordinates (UV, face_uvs)
  bool with_normals = false;  ///< keep normals (N, face_normals)
};

/// Reads the mesh of an OBJ, OFF, PLY or STL file. Polygons are kept as they are (see
/// triangulate_fan). STL vertices that have exactly the same coordinates are merged so the result
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

/// Writes a mesh. Coordinates in text formats are printed in the shortest form that reads back
/// to the same double (exact round trip); binary PLY stores doubles (exact); binary OFF and
/// binary STL store float32, as those formats prescribe. OBJ writes UV / N with `f v/vt/vn` when
/// the mesh has them (and face_uvs / face_normals); PLY writes per-vertex N as nx,ny,nz when N
/// has #V rows. STL gets fan-triangulated polygons and per-facet normals.
/// \throw InputError for unknown formats, indices out of range, non-finite coordinates, faces
///        with fewer than 3 corners, or a file that cannot be written.
void write_mesh(const std::string& path, const PolygonMesh& mesh, const WriteOptions& options);

/// A point cloud: P (#P by 3) and optional normals N (#P by 3, or 0 rows when absent).
struct PointCloud {
  VertexMatrix P;
  VertexMatrix N;
};

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
