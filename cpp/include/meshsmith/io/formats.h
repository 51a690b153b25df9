#pragma once
/// \file formats.h
/// One reader and one writer per file format, on in-memory contents. read_mesh / write_mesh /
/// read_points / write_points (mesh_io.h) choose among them by Format; call these directly to
/// parse a buffer you already hold. `path` only names the file in error messages.
/// Every reader throws InputError "<path>: line <n>: ..." (text) or "<path>: byte <k>: ..."
/// (binary) for malformed contents, and checks every face index against the vertex count.
#include <meshsmith/io/mesh_io.h>

#include <string>
#include <string_view>

namespace meshsmith::io {

/// OBJ: v (x y z, x y z w with w ignored, x y z r g b or x y z r g b a: colours kept when every
/// vertex has them, else a warning), vt, vn, f with v, v/vt, v//vn or v/vt/vn corners (negative
/// indices count back from the last element). Grouping, material and display statements (o, g,
/// s, usemtl, mtllib, ...) are skipped silently; points (p), polylines (l), free-form geometry and
/// unknown statements are skipped with one warning per kind that counts them.
PolygonMesh parse_obj(const std::string& path, std::string_view text, const ReadOptions& options);
/// OBJ text of `mesh`: v (with r g b when it has colours), then vt / vn when the mesh has them,
/// then f (1-based).
std::string format_obj(const PolygonMesh& mesh);

/// OFF with optional [ST][C][N] prefixes (per-vertex texture coordinates, colours of 3 or 4
/// components, normals) and colours after a face's indices, or binary OFF ("[ST][C][N]OFF BINARY",
/// float32 values) in the layout that fits the file: Geomview's big-endian one with a colour count
/// after each face, or the little-endian one of the PMP library without (and two more
/// combinations). A set of colours with a component above 1 is read as 0..255.
PolygonMesh parse_off(const std::string& path, std::string_view text);
/// ASCII OFF, or binary OFF (Geomview's layout, float32 values, colours as 4 floats) when
/// `binary`, with the prefixes of the per-vertex attributes the mesh has and face colours.
std::string format_off(const PolygonMesh& mesh, bool binary);

/// PLY, ASCII or binary of either endianness. The `vertex` element gives V (x, y, z), N (nx, ny,
/// nz), UV (u, v / s, t / texture_u, texture_v) and colours (red green blue [alpha], integers
/// scaled from 0..255, or 0..65535 for ushort); `face` (list vertex_indices or vertex_index)
/// gives polygons, their colours and per-corner UVs (a `texcoord` list of u v pairs, which wins
/// over per-vertex UVs), and `tristrips` (list vertex_indices, -1 restarts a strip) gives triangles,
/// alternating orientation along the strip and dropping degenerate ones. Every other element
/// and property, lists included, is skipped by its declared type. With `read_faces` false the
/// faces are checked but not stored.
PolygonMesh parse_ply(const std::string& path, std::string_view bytes, bool read_faces);
/// PLY with double x, y, z (and nx ny nz, texture_u texture_v, red green blue [alpha] for the
/// per-vertex attributes the mesh has) and, when the mesh has faces, a face element with a
/// `list uchar int vertex_indices` (int count when a face has > 255 corners), colours and a
/// `texcoord` list when the UVs are per corner. Colours are uchar when all are k / 255, else
/// double.
std::string format_ply(const PolygonMesh& mesh, bool binary, bool big_endian);

/// STL, binary (chosen when the size is exactly 84 + 50 × the triangle count at byte 80) or
/// ASCII (starts with "solid"). Corners with exactly equal coordinates become one vertex.
PolygonMesh parse_stl(const std::string& path, std::string_view bytes);
/// STL of the fan triangulation of `mesh`, with facet normals; binary stores float32.
std::string format_stl(const PolygonMesh& mesh, bool binary);

/// XYZ point file: lines of 3 (x y z) or 6 (x y z nx ny nz) numbers, '#' comments, blank lines.
PointCloud parse_xyz(const std::string& path, std::string_view text);
/// XYZ text of `points` (6 columns when N has rows).
std::string format_xyz(const PointCloud& points);

}  // namespace meshsmith::io
