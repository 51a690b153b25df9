// Object File Format (Geomview OFF): ASCII and binary reader and writer.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

#include <climits>
#include <cmath>

namespace meshsmith::io {

namespace {

/// The header keyword: [ST][C][N]OFF (4OFF and nOFF, other dimensions, are not supported).
bool is_off_keyword(std::string_view keyword, const LineReader& lines) {
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF") return false;
  std::string_view prefix = keyword.substr(0, keyword.size() - 3);
  if (prefix.substr(0, 2) == "ST") prefix.remove_prefix(2);
  if (!prefix.empty() && prefix[0] == 'C') prefix.remove_prefix(1);
  if (!prefix.empty() && prefix[0] == 'N') prefix.remove_prefix(1);
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

PolygonMesh parse_binary_off(const std::string& path, std::string_view bytes, std::size_t start) {
  ByteReader in(path, bytes, start, /*big_endian=*/true);
  const std::int64_t vertex_count = in.read<std::int32_t>("the vertex count");
  const std::int64_t face_count = in.read<std::int32_t>("the face count");
  in.read<std::int32_t>("the edge count");
  check_counts(vertex_count, face_count, in.remaining_bytes(), 12, 4,
               [&](const std::string& message) { in.fail(message); });
  PolygonMesh mesh;
  mesh.V.resize(vertex_count, 3);
  for (std::int64_t i = 0; i < vertex_count; ++i)
    for (int c = 0; c < 3; ++c) {
      const float value = in.read<float>("vertex coordinates");
      if (!std::isfinite(value)) in.fail_at(in.offset() - 4, "vertex " + std::to_string(i) + " has a non-finite coordinate");
      mesh.V(i, c) = value;
    }
  mesh.face_offsets.reserve(face_count + 1);
  mesh.face_vertices.reserve(face_count * 3);
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
    const std::int32_t colors = in.read<std::int32_t>("a face colour count");
    if (colors < 0 || colors > 4) in.fail_at(in.offset() - 4, "face " + std::to_string(f) + " has " + std::to_string(colors) + " colour components (0 to 4 allowed)");
    in.skip(static_cast<std::size_t>(colors) * 4, "a face colour");
  }
  return mesh;
}

/// \throw InputError unless every remaining token of the line is a number (colours etc.).
void check_trailing_numbers(const LineReader& lines, Tokens& tokens) {
  std::string_view token;
  double ignored;
  while (tokens.next(token)) {
    if (token[0] == '#') return;  // a comment ends the line
    if (!parse_double(token, ignored))
      lines.fail(quoted(token) + " is not a number");
  }
}

}  // namespace

PolygonMesh parse_off(const std::string& path, std::string_view text) {
  LineReader lines(path, text);
  std::string_view line, token;
  if (!lines.next_content(line)) throw InputError(path + ": no OFF header (the file has only blanks or comments)");
  Tokens header(line);
  header.next(token);
  if (!is_off_keyword(token, lines)) lines.fail("the file does not start with an OFF header");
  std::string_view counts_line;
  Tokens after_keyword = header;
  if (after_keyword.next(token) && token == "BINARY") return parse_binary_off(path, text, lines.offset());
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
  for (std::int64_t i = 0; i < vertex_count; ++i) {
    if (!lines.next_content(line))
      lines.fail("unexpected end of file: " + std::to_string(i) + " of " + std::to_string(vertex_count) + " vertices read");
    Tokens tokens(line);
    for (int c = 0; c < 3; ++c) {
      if (!tokens.next(token)) lines.fail("vertex " + std::to_string(i) + " has fewer than 3 coordinates");
      if (!parse_double(token, mesh.V(i, c)))
        lines.fail(quoted(token) + " is not a finite number");
    }
    check_trailing_numbers(lines, tokens);
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
    check_trailing_numbers(lines, tokens);
    mesh.face_offsets.push_back(mesh.face_offsets.back() + size);
  }
  return mesh;
}

std::string format_off(const PolygonMesh& mesh, bool binary) {
  OutputBuffer out;
  const auto vertex_count = static_cast<std::int32_t>(mesh.V.rows());
  const auto face_count = static_cast<std::int32_t>(mesh.face_count());
  if (binary) {
    out.reserve(11 + 12 + mesh.V.rows() * 12 + mesh.face_count() * 8 + mesh.face_vertices.size() * 4);
    out.text("OFF BINARY\n");
    out.binary<std::int32_t>(vertex_count, true);
    out.binary<std::int32_t>(face_count, true);
    out.binary<std::int32_t>(0, true);
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      for (int c = 0; c < 3; ++c) out.binary<float>(static_cast<float>(mesh.V(i, c)), true);
    for (std::int64_t f = 0; f < mesh.face_count(); ++f) {
      const std::int64_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
      out.binary<std::int32_t>(static_cast<std::int32_t>(end - begin), true);
      for (std::int64_t k = begin; k < end; ++k) out.binary<std::int32_t>(mesh.face_vertices[k], true);
      out.binary<std::int32_t>(0, true);
    }
    return out.take();
  }
  out.reserve(static_cast<std::size_t>(mesh.V.rows()) * 60 + mesh.face_vertices.size() * 10);
  out.text("OFF\n");
  out.number(vertex_count); out.character(' ');
  out.number(face_count); out.text(" 0\n");
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    out.number(mesh.V(i, 0)); out.character(' ');
    out.number(mesh.V(i, 1)); out.character(' ');
    out.number(mesh.V(i, 2)); out.character('\n');
  }
  append_face_lines(out, mesh);
  return out.take();
}

}  // namespace meshsmith::io
