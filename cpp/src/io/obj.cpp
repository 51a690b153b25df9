// Wavefront OBJ: reader and writer.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

#include <array>
#include <climits>

namespace meshsmith::io {

namespace {

/// Statements of the OBJ specification that carry nothing read_mesh returns.
bool is_ignored_statement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 33> ignored = {
      "o", "g", "s", "mg", "usemtl", "mtllib", "l", "p", "vp", "cstype", "deg", "bmat",
      "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con",
      "bevel", "c_interp", "d_interp", "lod", "maplib", "usemap", "shadow_obj", "trace_obj",
      "ctech", "stech"};
  for (std::string_view word : ignored)
    if (keyword == word) return true;
  return false;
}

/// Turns a 1-based (or negative, relative) OBJ index into a 0-based one; remembers the largest
/// forward reference so that it can be checked once every element has been read.
struct IndexResolver {
  const char* name;
  std::int64_t largest = -1;
  std::size_t largest_line = 0;

  int resolve(const LineReader& lines, std::int64_t index, std::int64_t defined) {
    if (index > 0) {
      if (index > INT_MAX) lines.fail(std::string(name) + " index " + std::to_string(index) + " is too large");
      if (index - 1 > largest) {
        largest = index - 1;
        largest_line = lines.line_number();
      }
      return static_cast<int>(index - 1);
    }
    if (index == 0) lines.fail(std::string(name) + " index 0 (OBJ indices start at 1)");
    if (defined + index < 0)
      lines.fail(std::string(name) + " index " + std::to_string(index) + " refers before the first " +
                 name + " (" + std::to_string(defined) + " defined so far)");
    return static_cast<int>(defined + index);
  }

  void check(const std::string& path, std::int64_t defined) const {
    if (largest >= defined)
      throw InputError(path + ": line " + std::to_string(largest_line) + ": " + name + " index " +
                       std::to_string(largest + 1) + " out of range (the file has " +
                       std::to_string(defined) + " " + name + "s)");
  }
};

/// Parses the numbers of a v/vt/vn statement into `out` (at least `minimum`, at most `maximum`
/// values; `store` of them are appended, missing ones as 0).
void parse_numbers(const LineReader& lines, Tokens& tokens, const char* keyword, int minimum,
                   int maximum, int store, std::vector<double>& out) {
  std::string_view token;
  int count = 0;
  double value;
  while (tokens.next(token)) {
    if (!parse_double(token, value))
      lines.fail(quoted(token) + " is not a finite number in a '" +
                 keyword + "' statement");
    if (count < store) out.push_back(value);
    if (++count > maximum)
      lines.fail(std::string("too many values in a '") + keyword + "' statement");
  }
  if (count < minimum)
    lines.fail(std::string("'") + keyword + "' needs at least " + std::to_string(minimum) +
               " numbers, found " + std::to_string(count));
  for (; count < store; ++count) out.push_back(0.0);
}

template <typename Matrix>
Matrix to_matrix(const std::vector<double>& values) {
  Matrix matrix(static_cast<Eigen::Index>(values.size() / Matrix::ColsAtCompileTime),
                Matrix::ColsAtCompileTime);
  std::copy(values.begin(), values.end(), matrix.data());
  return matrix;
}

}  // namespace

PolygonMesh parse_obj(const std::string& path, std::string_view text, const ReadOptions& options) {
  std::vector<double> positions, uvs, normals;
  PolygonMesh mesh;
  LineReader lines(path, text);
  IndexResolver vertex_index{"vertex"}, uv_index{"texture coordinate"}, normal_index{"normal"};
  std::int64_t uv_count = 0, normal_count = 0;
  bool any_uv = false, any_normal = false;
  std::string_view line, keyword, corner;
  while (lines.next(line)) {
    Tokens tokens(line);
    if (!tokens.next(keyword) || keyword[0] == '#') continue;
    if (keyword == "v") {
      parse_numbers(lines, tokens, "v", 3, 7, 3, positions);
    } else if (keyword == "f" || keyword == "fo") {
      std::int64_t corners = 0;
      while (tokens.next(corner)) {
        std::string_view parts[3];
        int part_count = 0;
        std::size_t start = 0;
        for (std::size_t i = 0; i <= corner.size(); ++i) {
          if (i == corner.size() || corner[i] == '/') {
            if (part_count == 3) lines.fail("face corner " + quoted(corner) + " has more than 3 parts");
            parts[part_count++] = corner.substr(start, i - start);
            start = i + 1;
          }
        }
        std::int64_t value;
        if (!parse_integer(parts[0], value))
          lines.fail(quoted(corner) + " is not a face corner (v, v/vt, v//vn or v/vt/vn)");
        mesh.face_vertices.push_back(
            vertex_index.resolve(lines, value, static_cast<std::int64_t>(positions.size() / 3)));
        int uv = -1, normal = -1;
        if (part_count > 1 && !parts[1].empty()) {
          if (!parse_integer(parts[1], value))
            lines.fail(quoted(corner) + " has a texture coordinate index that is not an integer");
          uv = uv_index.resolve(lines, value, uv_count);
          any_uv = true;
        }
        if (part_count > 2 && !parts[2].empty()) {
          if (!parse_integer(parts[2], value))
            lines.fail(quoted(corner) + " has a normal index that is not an integer");
          normal = normal_index.resolve(lines, value, normal_count);
          any_normal = true;
        }
        if (options.with_uv) mesh.face_uvs.push_back(uv);
        if (options.with_normals) mesh.face_normals.push_back(normal);
        ++corners;
      }
      if (corners < 3)
        lines.fail("face with " + std::to_string(corners) + " corners (at least 3 needed)");
      mesh.face_offsets.push_back(mesh.face_offsets.back() + corners);
    } else if (keyword == "vt") {
      ++uv_count;
      parse_numbers(lines, tokens, "vt", 1, 3, options.with_uv ? 2 : 0, uvs);
    } else if (keyword == "vn") {
      ++normal_count;
      parse_numbers(lines, tokens, "vn", 3, 3, options.with_normals ? 3 : 0, normals);
    } else if (!is_ignored_statement(keyword)) {
      lines.fail("unknown OBJ statement " + quoted(keyword));
    }
  }
  const std::int64_t vertex_count = static_cast<std::int64_t>(positions.size() / 3);
  if (vertex_count > INT_MAX) throw InputError(path + ": too many vertices");
  if (vertex_count == 0) throw InputError(path + ": no vertices ('v' statements) in the file");
  vertex_index.check(path, vertex_count);
  uv_index.check(path, uv_count);
  normal_index.check(path, normal_count);
  mesh.V = to_matrix<VertexMatrix>(positions);
  if (options.with_uv && any_uv) mesh.UV = to_matrix<UVMatrix>(uvs);
  else mesh.face_uvs.clear();
  if (options.with_normals && any_normal) mesh.N = to_matrix<VertexMatrix>(normals);
  else mesh.face_normals.clear();
  return mesh;
}

std::string format_obj(const PolygonMesh& mesh) {
  OutputBuffer out;
  out.reserve(static_cast<std::size_t>(mesh.V.rows()) * 60 + mesh.face_vertices.size() * 12);
  out.text("# written by meshsmith\n");
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    out.text("v ");
    out.number(mesh.V(i, 0)); out.character(' ');
    out.number(mesh.V(i, 1)); out.character(' ');
    out.number(mesh.V(i, 2)); out.character('\n');
  }
  const bool with_uv = mesh.UV.rows() > 0 && !mesh.face_uvs.empty();
  const bool with_normals = mesh.N.rows() > 0 && !mesh.face_normals.empty();
  if (with_uv)
    for (Eigen::Index i = 0; i < mesh.UV.rows(); ++i) {
      out.text("vt ");
      out.number(mesh.UV(i, 0)); out.character(' ');
      out.number(mesh.UV(i, 1)); out.character('\n');
    }
  if (with_normals)
    for (Eigen::Index i = 0; i < mesh.N.rows(); ++i) {
      out.text("vn ");
      out.number(mesh.N(i, 0)); out.character(' ');
      out.number(mesh.N(i, 1)); out.character(' ');
      out.number(mesh.N(i, 2)); out.character('\n');
    }
  for (std::int64_t f = 0; f < mesh.face_count(); ++f) {
    const std::int64_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    // A face carries vt / vn only when all its corners have one (OBJ cannot mix within a face).
    bool face_uv = with_uv, face_normal = with_normals;
    for (std::int64_t k = begin; k < end; ++k) {
      if (face_uv && mesh.face_uvs[k] < 0) face_uv = false;
      if (face_normal && mesh.face_normals[k] < 0) face_normal = false;
    }
    out.character('f');
    for (std::int64_t k = begin; k < end; ++k) {
      out.character(' ');
      out.number(mesh.face_vertices[k] + 1);
      if (face_uv || face_normal) {
        out.character('/');
        if (face_uv) out.number(mesh.face_uvs[k] + 1);
        if (face_normal) {
          out.character('/');
          out.number(mesh.face_normals[k] + 1);
        }
      }
    }
    out.character('\n');
  }
  return out.take();
}

}  // namespace meshsmith::io
