// Object File Format (Geomview OFF): ASCII and binary reader and writer, with the [ST][C][N]
// prefixes (per-vertex texture coordinates, colours, normals) and per-face colours.
//
// Binary OFF exists in two byte orders: Geomview's specification says big-endian, with a colour
// count (and colours) after each face's indices; the PMP library and others write the machine's
// order (little-endian) and no colour count. The reader tries the layouts in that order of
// likelihood and takes the first whose header counts are plausible and whose records end exactly
// at the end of the file (trailing white space allowed).
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <optional>

namespace meshsmith::io {

namespace {

/// What the header keyword announces: [ST][C][N]OFF.
struct OffFields {
  bool texture = false, colors = false, normals = false;
};

/// Parses the header keyword; false when it is not an OFF keyword.
/// \throw InputError (via `lines`) for 4OFF and nOFF (other dimensions are not supported).
bool parse_off_keyword(std::string_view keyword, const LineReader& lines, OffFields& fields) {
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF") return false;
  std::string_view prefix = keyword.substr(0, keyword.size() - 3);
  if (prefix.substr(0, 2) == "ST") {
    fields.texture = true;
    prefix.remove_prefix(2);
  }
  if (!prefix.empty() && prefix[0] == 'C') {
    fields.colors = true;
    prefix.remove_prefix(1);
  }
  if (!prefix.empty() && prefix[0] == 'N') {
    fields.normals = true;
    prefix.remove_prefix(1);
  }
  if (!prefix.empty() && (prefix[0] == '4' || prefix[0] == 'n'))
    lines.fail(quoted(keyword) + ": only 3D OFF files are supported");
  return prefix.empty();
}

/// \throw InputError (via `fail`) unless counts are non-negative and the remaining `bytes` can
/// hold that many vertices and faces of at least the given sizes.
template <typename Fail>
void check_counts(std::int64_t vertices, std::int64_t faces, std::size_t bytes,
                  std::int64_t vertex_bytes, std::int64_t face_bytes, Fail fail) {
  if (vertices < 0 || faces < 0)
    fail("negative count in the header (" + std::to_string(vertices) + " vertices, " +
         std::to_string(faces) + " faces)");
  const auto available = static_cast<std::int64_t>(bytes) + 1;
  if (vertices > available / vertex_bytes || faces > available / face_bytes ||
      vertices * vertex_bytes + faces * face_bytes > available)
    fail("the header announces " + std::to_string(vertices) + " vertices and " +
         std::to_string(faces) + " faces, more than the " + std::to_string(bytes) +
         " remaining bytes can hold");
  if (vertices == 0) fail("the header announces no vertices");
  if (vertices > INT_MAX) fail("too many vertices");
}

/// Colour values of a file as read: RGBA rows (alpha NaN, then 1, where 3 were given), scaled to [0, 1] at
/// the end. Geomview allows integers 0..255 as well as floats 0..1; like the PMP library (which
/// decides per vertex), a set of colours with a component above 1 is taken as 0..255 (decided
/// per set, so that dark 0..255 colours are not read as 0..1).
struct ColorSet {
  std::vector<double> rgba;
  std::int64_t given = 0;  // rows with colours
  bool alpha = false;
  double largest = 0.0;

  void add(const double* values, int count) {
    rgba.insert(rgba.end(), values, values + 3);
    rgba.push_back(count == 4 ? values[3] : std::numeric_limits<double>::quiet_NaN());  // 1 once scaled
    alpha |= count == 4;
    for (int c = 0; c < count; ++c) largest = std::max(largest, values[c]);
    ++given;
  }

  /// The rows as a matrix (3 or 4 columns) when all `rows` have colours; else empty, with a
  /// warning for `mesh` when only some have.
  ColorMatrix finish(std::int64_t rows, const char* what, PolygonMesh& mesh) const {
    ColorMatrix out;
    if (given == 0) return out;
    if (given != rows) {
      mesh.warnings.push_back("only " + std::to_string(given) + " of " + std::to_string(rows) +
                              " " + what + " have colours: colours not read");
      return out;
    }
    const double divisor = largest > 1.0 ? 255.0 : 1.0;
    out.resize(rows, alpha ? 4 : 3);
    for (std::int64_t r = 0; r < rows; ++r)
      for (Eigen::Index c = 0; c < out.cols(); ++c)
        out(r, c) = std::isnan(rgba[4 * r + c]) ? 1.0 : rgba[4 * r + c] / divisor;
    return out;
  }
};

/// Per-vertex normals and UVs indexed by the corners' vertices, the colours scaled, and a
/// warning for faces that name a colour-map entry (Geomview's colour maps are not read).
void finish_attributes(PolygonMesh& mesh, const ColorSet& vertex_colors, const ColorSet& face_colors,
                       std::int64_t colormap_faces) {
  if (mesh.N.rows() > 0) mesh.face_normals = mesh.face_vertices;
  if (mesh.UV.rows() > 0) mesh.face_uvs = mesh.face_vertices;
  mesh.colors = vertex_colors.finish(mesh.V.rows(), "vertices", mesh);
  mesh.face_colors = face_colors.finish(mesh.face_count(), "faces", mesh);
  if (colormap_faces > 0)
    mesh.warnings.push_back(std::to_string(colormap_faces) +
                            " faces give a colour-map index instead of a colour: not read");
}

/// One binary layout to try: byte order, coordinate type, and whether faces carry a colour count.
struct BinaryLayout {
  bool big_endian;
  bool face_color_count;
  bool doubles;
  const char* name;
};

constexpr BinaryLayout binary_layouts[] = {
    {true, true, false, "big-endian float32 with face colour counts (Geomview)"},
    {false, false, false, "little-endian float32 without face colour counts (PMP)"},
    {false, true, false, "little-endian float32 with face colour counts"},
    {true, false, false, "big-endian float32 without face colour counts"},
    {false, false, true, "little-endian float64 without face colour counts (PMP, 64-bit)"},
    {true, true, true, "big-endian float64 with face colour counts"},
};

/// Counts the unknowns of a binary parse that failed, to choose which error to report.
struct BinaryAttempt {
  bool plausible_counts = false;
  std::optional<InputError> error;
};

PolygonMesh parse_binary_off(const std::string& path, std::string_view bytes, std::size_t start,
                             const OffFields& fields, const BinaryLayout& layout,
                             BinaryAttempt& attempt) {
  ByteReader in(path, bytes, start, layout.big_endian);
  const std::int64_t vertex_count = in.read<std::int32_t>("the vertex count");
  const std::int64_t face_count = in.read<std::int32_t>("the face count");
  in.read<std::int32_t>("the edge count");
  const int per_vertex = 3 + (fields.normals ? 3 : 0) + (fields.colors ? 4 : 0) + (fields.texture ? 2 : 0);
  const std::int64_t scalar = layout.doubles ? 8 : 4;
  check_counts(vertex_count, face_count, in.remaining_bytes(), per_vertex * scalar,
               layout.face_color_count ? 8 : 4, [&](const std::string& message) { in.fail(message); });
  attempt.plausible_counts = true;
  PolygonMesh mesh;
  mesh.V.resize(vertex_count, 3);
  if (fields.normals) mesh.N.resize(vertex_count, 3);
  if (fields.texture) mesh.UV.resize(vertex_count, 2);
  ColorSet vertex_colors, face_colors;
  double values[12];
  in.require(static_cast<std::size_t>(vertex_count * per_vertex * scalar), "vertex records");
  for (std::int64_t i = 0; i < vertex_count; ++i) {
    for (int k = 0; k < per_vertex; ++k) {
      values[k] = layout.doubles ? in.read<double>("vertex records")
                                 : static_cast<double>(in.read<float>("vertex records"));
      if (!std::isfinite(values[k]))
        in.fail_at(in.offset() - scalar, "vertex " + std::to_string(i) + " has a non-finite value");
    }
    int k = 0;
    for (int c = 0; c < 3; ++c) mesh.V(i, c) = values[k++];
    if (fields.normals)
      for (int c = 0; c < 3; ++c) mesh.N(i, c) = values[k++];
    if (fields.colors) {
      vertex_colors.add(values + k, 4);
      k += 4;
    }
    if (fields.texture)
      for (int c = 0; c < 2; ++c) mesh.UV(i, c) = values[k++];
  }
  mesh.face_offsets.reserve(face_count + 1);
  mesh.face_vertices.reserve(std::min<std::size_t>(face_count * 3, in.remaining_bytes() / 4));
  std::int64_t colormap_faces = 0;
  for (std::int64_t f = 0; f < face_count; ++f) {
    const std::size_t face_start = in.offset();
    const std::int32_t size = in.read<std::int32_t>("a face size");
    if (size < 3)
      in.fail_at(face_start, "face " + std::to_string(f) + " has " + std::to_string(size) + " corners (at least 3 needed)");
    in.require(static_cast<std::size_t>(size) * 4, "face indices");
    for (std::int32_t k = 0; k < size; ++k) {
      const std::int32_t index = in.read<std::int32_t>("face indices");
      if (index < 0 || index >= vertex_count)
        in.fail_at(in.offset() - 4, "face " + std::to_string(f) + " has vertex index " + std::to_string(index) +
                   " outside [0, " + std::to_string(vertex_count) + ")");
      mesh.face_vertices.push_back(index);
    }
    mesh.face_offsets.push_back(mesh.face_offsets.back() + size);
    if (!layout.face_color_count) continue;
    const std::int32_t colors = in.read<std::int32_t>("a face colour count");
    if (colors < 0 || colors > 4) in.fail_at(in.offset() - 4, "face " + std::to_string(f) + " has " + std::to_string(colors) + " colour components (0 to 4 allowed)");
    for (std::int32_t c = 0; c < colors; ++c) values[c] = in.read<float>("a face colour");
    if (colors >= 3) face_colors.add(values, colors);
    colormap_faces += colors == 1;
  }
  for (std::size_t rest = in.offset(); rest < bytes.size(); ++rest)
    if (!is_blank(bytes[rest]) && bytes[rest] != '\n' && bytes[rest] != '\0')
      in.fail("the records end " + std::to_string(bytes.size() - in.offset()) +
              " bytes before the end of the file");
  finish_attributes(mesh, vertex_colors, face_colors, colormap_faces);
  return mesh;
}

/// Binary OFF in whichever layout of binary_layouts fits the file.
PolygonMesh parse_binary_off(const std::string& path, std::string_view bytes, std::size_t start,
                             const OffFields& fields) {
  BinaryAttempt attempts[std::size(binary_layouts)];
  for (std::size_t k = 0; k < std::size(binary_layouts); ++k) {
    try {
      return parse_binary_off(path, bytes, start, fields, binary_layouts[k], attempts[k]);
    } catch (const InputError& error) {
      attempts[k].error = error;
    }
  }
  // No layout fits: report the error of the first layout whose counts were plausible.
  for (std::size_t k = 0; k < std::size(binary_layouts); ++k)
    if (attempts[k].plausible_counts)
      throw InputError(std::string(attempts[k].error->what()) + " (read as " +
                       binary_layouts[k].name + "; no other binary OFF layout fits the file either)");
  throw *attempts[0].error;
}

/// The numbers of a line (up to a '#' comment) into `values`; returns how many.
/// \throw InputError (via `lines`) for a token that is not a number or more than `capacity`.
int line_numbers(const LineReader& lines, Tokens& tokens, double* values, int capacity) {
  std::string_view token;
  int count = 0;
  while (tokens.next(token)) {
    if (token[0] == '#') break;
    if (count == capacity) lines.fail("more than " + std::to_string(capacity) + " values on the line");
    if (!parse_double(token, values[count])) lines.fail(quoted(token) + " is not a finite number");
    ++count;
  }
  return count;
}

}  // namespace

PolygonMesh parse_off(const std::string& path, std::string_view text) {
  LineReader lines(path, text);
  std::string_view line, token;
  if (!lines.next_content(line)) throw InputError(path + ": no OFF header (the file has only blanks or comments)");
  Tokens header(line);
  header.next(token);
  OffFields fields;
  if (!parse_off_keyword(token, lines, fields)) lines.fail("the file does not start with an OFF header");
  std::string_view counts_line;
  Tokens after_keyword = header;
  if (after_keyword.next(token) && token == "BINARY") return parse_binary_off(path, text, lines.offset(), fields);
  if (header.empty()) {
    if (!lines.next_content(counts_line)) lines.fail("missing the vertex and face counts");
  } else {
    counts_line = header.rest();
  }
  Tokens counts(counts_line);
  std::int64_t vertex_count = 0, face_count = 0, edge_count = 0;
  if (!counts.next(token) || !parse_integer(token, vertex_count) || !counts.next(token) ||
      !parse_integer(token, face_count))
    lines.fail("expected the vertex and face counts");
  if (counts.next(token) && !parse_integer(token, edge_count)) lines.fail("the edge count is not an integer");
  if (!counts.empty()) lines.fail("unexpected values after the counts");
  check_counts(vertex_count, face_count, lines.remaining_bytes(), 4, 4,
               [&](const std::string& message) { lines.fail(message); });

  PolygonMesh mesh;
  mesh.V.resize(vertex_count, 3);
  if (fields.normals) mesh.N.resize(vertex_count, 3);
  if (fields.texture) mesh.UV.resize(vertex_count, 2);
  ColorSet vertex_colors, face_colors;
  const int fixed = 3 + (fields.normals ? 3 : 0) + (fields.texture ? 2 : 0);
  constexpr int capacity = 64;
  double values[capacity];
  std::int64_t extra_vertex_values = 0, extra_face_values = 0, colormap_faces = 0;
  for (std::int64_t i = 0; i < vertex_count; ++i) {
    if (!lines.next_content(line))
      lines.fail("unexpected end of file: " + std::to_string(i) + " of " + std::to_string(vertex_count) + " vertices read");
    Tokens tokens(line);
    const int count = line_numbers(lines, tokens, values, capacity);
    if (count < 3) lines.fail("vertex " + std::to_string(i) + " has fewer than 3 coordinates");
    if (count < fixed)
      lines.fail("vertex " + std::to_string(i) + " has " + std::to_string(count) + " values; the " +
                 std::string(fields.texture ? "ST" : "") + (fields.normals ? "N" : "") +
                 "OFF header needs " + std::to_string(fixed));
    // x y z [nx ny nz] [r g b [a]] [s t], in that order.
    int k = 0;
    for (int c = 0; c < 3; ++c) mesh.V(i, c) = values[k++];
    if (fields.normals)
      for (int c = 0; c < 3; ++c) mesh.N(i, c) = values[k++];
    const int rest = count - fixed;
    if (fields.colors) {
      if (rest != 3 && rest != 4)
        lines.fail("vertex " + std::to_string(i) + " has " + std::to_string(rest) +
                   " colour values (3 or 4 expected after a C prefix)");
      vertex_colors.add(values + k, rest);
      k += rest;
    } else if (rest > 0) {
      ++extra_vertex_values;
    }
    if (fields.texture)
      for (int c = 0; c < 2; ++c) mesh.UV(i, c) = values[k++];
  }
  mesh.face_offsets.reserve(face_count + 1);
  mesh.face_vertices.reserve(face_count * 3);
  for (std::int64_t f = 0; f < face_count; ++f) {
    if (!lines.next_content(line))
      lines.fail("unexpected end of file: " + std::to_string(f) + " of " + std::to_string(face_count) + " faces read");
    Tokens tokens(line);
    std::int64_t size = 0, index = 0;
    if (!tokens.next(token) || !parse_integer(token, size))
      lines.fail(quoted(token) + " is not a face size");
    if (size < 3) lines.fail("face " + std::to_string(f) + " has " + std::to_string(size) + " corners (at least 3 needed)");
    for (std::int64_t k = 0; k < size; ++k) {
      if (!tokens.next(token)) lines.fail("face " + std::to_string(f) + " has fewer than the " + std::to_string(size) + " indices it announces");
      if (!parse_integer(token, index)) lines.fail(quoted(token) + " is not a vertex index");
      if (index < 0 || index >= vertex_count)
        lines.fail("face " + std::to_string(f) + " has vertex index " + std::to_string(index) +
                   " outside [0, " + std::to_string(vertex_count) + ")");
      mesh.face_vertices.push_back(static_cast<int>(index));
    }
    // The face's colour: nothing, a colour-map index, or 3 / 4 components.
    const int count = line_numbers(lines, tokens, values, capacity);
    if (count == 3 || count == 4) face_colors.add(values, count);
    else if (count == 1) ++colormap_faces;
    else if (count > 0) ++extra_face_values;
    mesh.face_offsets.push_back(mesh.face_offsets.back() + size);
  }
  finish_attributes(mesh, vertex_colors, face_colors, colormap_faces);
  if (extra_vertex_values > 0)
    mesh.warnings.push_back(std::to_string(extra_vertex_values) +
                            " vertex lines have values beyond those the header announces: not read");
  if (extra_face_values > 0)
    mesh.warnings.push_back(std::to_string(extra_face_values) +
                            " face lines end with values that are not a colour: not read");
  return mesh;
}

std::string format_off(const PolygonMesh& mesh, bool binary) {
  OutputBuffer out;
  const auto vertex_count = static_cast<std::int32_t>(mesh.V.rows());
  const auto face_count = static_cast<std::int32_t>(mesh.face_count());
  // check_format_holds made sure that normals and UVs are per vertex.
  VertexMatrix normals;
  UVMatrix uvs;
  const bool with_normals = per_vertex_values(mesh, mesh.N, mesh.face_normals, normals);
  const bool with_uvs = per_vertex_values(mesh, mesh.UV, mesh.face_uvs, uvs);
  const bool with_colors = mesh.colors.rows() > 0, with_face_colors = mesh.face_colors.rows() > 0;
  if (with_uvs) out.text("ST");
  if (with_colors) out.text("C");
  if (with_normals) out.text("N");
  if (binary) {
    out.reserve(24 + mesh.V.rows() * 48 + mesh.face_count() * 24 + mesh.face_vertices.size() * 4);
    out.text("OFF BINARY\n");
    out.binary<std::int32_t>(vertex_count, true);
    out.binary<std::int32_t>(face_count, true);
    out.binary<std::int32_t>(0, true);
    auto value = [&](double v) { out.binary<float>(static_cast<float>(v), true); };
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
      for (int c = 0; c < 3; ++c) value(mesh.V(i, c));
      if (with_normals)
        for (int c = 0; c < 3; ++c) value(normals(i, c));
      if (with_colors)  // binary OFF colours are 4 floats, RGBA
        for (int c = 0; c < 4; ++c) value(c < mesh.colors.cols() ? mesh.colors(i, c) : 1.0);
      if (with_uvs)
        for (int c = 0; c < 2; ++c) value(uvs(i, c));
    }
    for (std::int64_t f = 0; f < mesh.face_count(); ++f) {
      const std::int64_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
      out.binary<std::int32_t>(static_cast<std::int32_t>(end - begin), true);
      for (std::int64_t k = begin; k < end; ++k) out.binary<std::int32_t>(mesh.face_vertices[k], true);
      const auto colors = static_cast<std::int32_t>(with_face_colors ? mesh.face_colors.cols() : 0);
      out.binary<std::int32_t>(colors, true);
      for (std::int32_t c = 0; c < colors; ++c) value(mesh.face_colors(f, c));
    }
    return out.take();
  }
  out.reserve(static_cast<std::size_t>(mesh.V.rows()) * 60 + mesh.face_vertices.size() * 10);
  out.text("OFF\n");
  out.number(vertex_count); out.character(' ');
  out.number(face_count); out.text(" 0\n");
  auto row = [&](const auto& matrix, Eigen::Index i) {
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
      out.character(' ');
      out.number(matrix(i, c));
    }
  };
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    out.number(mesh.V(i, 0)); out.character(' ');
    out.number(mesh.V(i, 1)); out.character(' ');
    out.number(mesh.V(i, 2));
    if (with_normals) row(normals, i);
    if (with_colors) row(mesh.colors, i);
    if (with_uvs) row(uvs, i);
    out.character('\n');
  }
  append_face_lines(out, mesh, with_face_colors ? &mesh.face_colors : nullptr);
  return out.take();
}

}  // namespace meshsmith::io
