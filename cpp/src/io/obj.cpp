// Wavefront OBJ: reader and writer.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <climits>

namespace meshsmith::io {

namespace {

/// Statements of the OBJ specification that carry nothing a mesh needs (grouping, materials,
/// smoothing groups, display and rendering attributes): skipped silently.
bool is_ignored_statement(std::string_view keyword) {
  static constexpr std::array<std::string_view, 16> ignored = {
      "o", "g", "s", "mg", "usemtl", "mtllib", "lod", "maplib", "usemap", "shadow_obj",
      "trace_obj", "ctech", "stech", "bevel", "c_interp", "d_interp"};
  for (std::string_view word : ignored)
    if (keyword == word) return true;
  return false;
}

/// Statements of the OBJ specification with geometry that a mesh does not hold (points, lines,
/// free-form curves and surfaces): skipped with a warning that counts them.
const char* skipped_geometry(std::string_view keyword) {
  if (keyword == "p") return "points";
  if (keyword == "l") return "polylines";
  static constexpr std::array<std::string_view, 15> free_form = {
      "vp", "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole",
      "scrv", "sp", "end", "con"};
  for (std::string_view word : free_form)
    if (keyword == word) return "free-form geometry";
  return nullptr;
}

/// Counts of the statements a parse skipped with a warning, by kind: at most `limit` kinds are
/// named (in order of first appearance), the rest are only counted, so that a file of garbage
/// costs no more than a file of faces.
struct SkippedStatements {
  static constexpr std::size_t limit = 16;
  std::vector<std::pair<std::string, std::int64_t>> kinds;
  std::int64_t others = 0;

  void add(std::string_view keyword, std::int64_t count) {
    for (auto& [kind, total] : kinds)
      if (kind == keyword) {
        total += count;
        return;
      }
    if (kinds.size() < limit) kinds.emplace_back(std::string(keyword), count);
    else others += count;
  }
};

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

/// Parses the numbers of a vt/vn statement into `out` (at least `minimum`, at most `maximum`
/// values; `store` of them are appended, missing ones as 0). Returns how many there were; `last`
/// gets the last one.
int parse_numbers(const LineReader& lines, Tokens& tokens, const char* keyword, int minimum,
                  int maximum, int store, std::vector<double>& out, double& last) {
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
    last = value;
  }
  if (count < minimum)
    lines.fail(std::string("'") + keyword + "' needs at least " + std::to_string(minimum) +
               " numbers, found " + std::to_string(count));
  for (int k = count; k < store; ++k) out.push_back(0.0);
  return count;
}

/// Parses the 3 to 7 numbers of a 'v' statement into `values`; returns how many there were.
int parse_vertex(const LineReader& lines, Tokens& tokens, double* values) {
  std::string_view token;
  int count = 0;
  while (tokens.next(token)) {
    if (count == 7) lines.fail("too many values in a 'v' statement");
    if (!parse_double(token, values[count]))
      lines.fail(quoted(token) + " is not a finite number in a 'v' statement");
    ++count;
  }
  if (count < 3) lines.fail("'v' needs at least 3 numbers, found " + std::to_string(count));
  return count;
}

/// Thrown by a chunk of a parallel parse that cannot be parsed on its own (a relative index).
struct NeedsWholeFile {};

/// What one run of lines holds, before the pieces of several runs are joined.
struct ObjPiece {
  std::vector<double> positions, uvs, normals;
  std::vector<double> colors;  // 4 per vertex with colour (alpha 1 when 3 were given)
  std::int64_t colored = 0;    // vertices with colours ('v x y z r g b [a]')
  std::int64_t uv_with_w = 0;  // 'vt u v w' with w != 0 (3D texture coordinates)
  bool any_alpha = false;
  SkippedStatements skipped;
  std::vector<std::int64_t> face_offsets{0};  // local: start at 0
  std::vector<int> corners, corner_uvs, corner_normals;
  std::int64_t uv_count = 0, normal_count = 0;
  bool any_uv = false, any_normal = false;
  IndexResolver vertex_index{"vertex"}, uv_index{"texture coordinate"}, normal_index{"normal"};
};

/// Parses the lines of `text` (`first_line` numbers its first line). With `whole_file` false
/// the piece is one chunk of a larger file: a relative (negative) index throws NeedsWholeFile.
ObjPiece parse_obj_piece(const std::string& path, std::string_view text, const ReadOptions& options,
                         bool whole_file) {
  ObjPiece piece;
  LineReader lines(path, text);
  std::string_view line, keyword, corner;
  auto index = [&](IndexResolver& resolver, std::int64_t value, std::int64_t defined) {
    if (value < 0 && !whole_file) throw NeedsWholeFile{};
    return resolver.resolve(lines, value, defined);
  };
  while (lines.next(line)) {
    Tokens tokens(line);
    if (!tokens.next(keyword) || keyword[0] == '#') continue;
    if (keyword == "v") {
      // x y z, x y z w (w ignored), x y z r g b or x y z r g b a.
      double values[7];
      const int given = parse_vertex(lines, tokens, values);
      piece.positions.push_back(values[0]);
      piece.positions.push_back(values[1]);
      piece.positions.push_back(values[2]);
      if (given >= 6) {
        ++piece.colored;
        if (options.with_colors) {
          piece.colors.insert(piece.colors.end(), values + 3, values + 6);
          piece.colors.push_back(given == 7 ? values[6] : 1.0);
          piece.any_alpha |= given == 7;
        }
      }
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
        piece.corners.push_back(
            index(piece.vertex_index, value, static_cast<std::int64_t>(piece.positions.size() / 3)));
        int uv = -1, normal = -1;
        if (part_count > 1 && !parts[1].empty()) {
          if (!parse_integer(parts[1], value))
            lines.fail(quoted(corner) + " has a texture coordinate index that is not an integer");
          uv = index(piece.uv_index, value, piece.uv_count);
          piece.any_uv = true;
        }
        if (part_count > 2 && !parts[2].empty()) {
          if (!parse_integer(parts[2], value))
            lines.fail(quoted(corner) + " has a normal index that is not an integer");
          normal = index(piece.normal_index, value, piece.normal_count);
          piece.any_normal = true;
        }
        if (options.with_uv) piece.corner_uvs.push_back(uv);
        if (options.with_normals) piece.corner_normals.push_back(normal);
        ++corners;
      }
      if (corners < 3)
        lines.fail("face with " + std::to_string(corners) + " corners (at least 3 needed)");
      piece.face_offsets.push_back(piece.face_offsets.back() + corners);
    } else if (keyword == "vt") {
      ++piece.uv_count;
      double w = 0.0;
      if (parse_numbers(lines, tokens, "vt", 1, 3, options.with_uv ? 2 : 0, piece.uvs, w) == 3 && w != 0.0)
        ++piece.uv_with_w;
    } else if (keyword == "vn") {
      ++piece.normal_count;
      double last;
      parse_numbers(lines, tokens, "vn", 3, 3, options.with_normals ? 3 : 0, piece.normals, last);
    } else if (!is_ignored_statement(keyword)) {
      piece.skipped.add(keyword, 1);
    }
  }
  return piece;
}

/// Splits `text` at line ends into about `count` pieces, parses them in parallel and joins
/// them. Empty when a piece cannot stand alone or holds an error (the caller then parses the
/// whole file in one piece, which reports the error with its true line number).
std::vector<ObjPiece> parse_obj_in_parallel(const std::string& path, std::string_view text,
                                            const ReadOptions& options, std::size_t count) {
  std::vector<std::string_view> chunks;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= count && begin < text.size(); ++k) {
    std::size_t end = k == count ? text.size() : std::max(begin, text.size() * k / count);
    while (end < text.size() && text[end] != '\n') ++end;
    end = std::min(text.size(), end + 1);
    chunks.push_back(text.substr(begin, end - begin));
    begin = end;
  }
  std::vector<ObjPiece> pieces(chunks.size());
  std::atomic<bool> failed{false};
  tbb::parallel_for(std::size_t(0), chunks.size(), [&](std::size_t k) {
    if (failed) return;
    try {
      pieces[k] = parse_obj_piece(path, chunks[k], options, false);
    } catch (const NeedsWholeFile&) {
      failed = true;
    } catch (const InputError&) {
      failed = true;
    }
  });
  if (failed) return {};
  return pieces;
}

template <typename T>
std::vector<T> join(std::vector<ObjPiece>& pieces, std::vector<T> ObjPiece::*member) {
  if (pieces.size() == 1) return std::move(pieces[0].*member);
  std::vector<std::size_t> starts(pieces.size() + 1, 0);
  for (std::size_t k = 0; k < pieces.size(); ++k) starts[k + 1] = starts[k] + (pieces[k].*member).size();
  std::vector<T> joined(starts.back());
  tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t k) {
    std::copy((pieces[k].*member).begin(), (pieces[k].*member).end(), joined.begin() + starts[k]);
    std::vector<T>().swap(pieces[k].*member);
  });
  return joined;
}

template <typename Matrix>
Matrix to_matrix(const std::vector<double>& values) {
  Matrix matrix(static_cast<Eigen::Index>(values.size() / Matrix::ColsAtCompileTime),
                Matrix::ColsAtCompileTime);
  std::copy(values.begin(), values.end(), matrix.data());
  return matrix;
}

PolygonMesh parse_obj_text(const std::string& path, std::string_view text,
                           const ReadOptions& options, bool allow_parallel) {
  // Large files are parsed in pieces on all cores; small ones, files with relative indices and
  // files with errors in one piece (which gives the true line numbers).
  constexpr std::size_t piece_bytes = 1 << 20;
  std::vector<ObjPiece> pieces;
  const std::size_t threads = static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
  if (allow_parallel && text.size() >= 4 * piece_bytes && threads > 1)
    pieces = parse_obj_in_parallel(path, text, options, std::min(text.size() / piece_bytes, 8 * threads));
  if (pieces.empty()) pieces.push_back(parse_obj_piece(path, text, options, true));

  std::int64_t vertex_count = 0, uv_count = 0, normal_count = 0, corner_count = 0;
  bool any_uv = false, any_normal = false;
  for (const ObjPiece& piece : pieces) {
    vertex_count += static_cast<std::int64_t>(piece.positions.size() / 3);
    uv_count += piece.uv_count;
    normal_count += piece.normal_count;
    any_uv |= piece.any_uv;
    any_normal |= piece.any_normal;
  }
  if (vertex_count > INT_MAX) throw InputError(path + ": too many vertices");
  if (vertex_count == 0) throw InputError(path + ": no vertices ('v' statements) in the file");
  for (const ObjPiece& piece : pieces)
    if (piece.vertex_index.largest >= vertex_count || piece.uv_index.largest >= uv_count ||
        piece.normal_index.largest >= normal_count) {
      if (pieces.size() > 1) return parse_obj_text(path, text, options, false);  // true line numbers
      piece.vertex_index.check(path, vertex_count);
      piece.uv_index.check(path, uv_count);
      piece.normal_index.check(path, normal_count);
    }

  PolygonMesh mesh;
  std::size_t face_count = 0;
  for (const ObjPiece& piece : pieces) face_count += piece.face_offsets.size() - 1;
  mesh.face_offsets.resize(face_count + 1);
  std::size_t face = 0;
  for (const ObjPiece& piece : pieces) {
    for (std::size_t f = 1; f < piece.face_offsets.size(); ++f)
      mesh.face_offsets[++face] = corner_count + piece.face_offsets[f];
    corner_count += piece.face_offsets.back();
  }
  mesh.V = to_matrix<VertexMatrix>(join(pieces, &ObjPiece::positions));
  mesh.face_vertices = join(pieces, &ObjPiece::corners);
  if (options.with_uv && any_uv) {
    mesh.UV = to_matrix<UVMatrix>(join(pieces, &ObjPiece::uvs));
    mesh.face_uvs = join(pieces, &ObjPiece::corner_uvs);
  }
  if (options.with_normals && any_normal) {
    mesh.N = to_matrix<VertexMatrix>(join(pieces, &ObjPiece::normals));
    mesh.face_normals = join(pieces, &ObjPiece::corner_normals);
  }
  std::int64_t colored = 0, uv_with_w = 0;
  bool any_alpha = false;
  SkippedStatements skipped;
  for (const ObjPiece& piece : pieces) {
    colored += piece.colored;
    uv_with_w += piece.uv_with_w;
    any_alpha |= piece.any_alpha;
    for (const auto& [keyword, count] : piece.skipped.kinds) skipped.add(keyword, count);
    skipped.others += piece.skipped.others;
  }
  if (options.with_colors && colored == vertex_count) {
    const std::vector<double> rgba = join(pieces, &ObjPiece::colors);
    mesh.colors.resize(vertex_count, any_alpha ? 4 : 3);
    for (std::int64_t i = 0; i < vertex_count; ++i)
      for (Eigen::Index c = 0; c < mesh.colors.cols(); ++c) mesh.colors(i, c) = rgba[4 * i + c];
  } else if (options.with_colors && colored > 0) {
    mesh.warnings.push_back("only " + std::to_string(colored) + " of " +
                            std::to_string(vertex_count) +
                            " vertices have colours ('v x y z r g b'): colours not read");
  }
  if (options.with_uv && uv_with_w > 0)
    mesh.warnings.push_back(std::to_string(uv_with_w) +
                            " texture coordinates have a third component w (3D textures): not read");
  for (const auto& [keyword, count] : skipped.kinds) {
    const char* geometry = skipped_geometry(keyword);
    mesh.warnings.push_back("skipped " + std::to_string(count) + " " +
                            (geometry ? "" : "unknown ") + printable(quoted(keyword)) +
                            (count == 1 ? " statement" : " statements") +
                            (geometry ? std::string(" (") + geometry + ": a mesh holds faces)" : ""));
  }
  if (skipped.others > 0)
    mesh.warnings.push_back("skipped " + std::to_string(skipped.others) +
                            " more statements of other unknown kinds");
  return mesh;
}

}  // namespace

PolygonMesh parse_obj(const std::string& path, std::string_view text, const ReadOptions& options) {
  return parse_obj_text(path, text, options, true);
}

std::string format_obj(const PolygonMesh& mesh) {
  OutputBuffer out;
  out.reserve(static_cast<std::size_t>(mesh.V.rows()) * 60 + mesh.face_vertices.size() * 12);
  out.text("# written by meshsmith\n");
  const bool colors = mesh.colors.rows() > 0;  // r g b (check_format_holds: alpha is 1)
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
    out.text("v ");
    out.number(mesh.V(i, 0)); out.character(' ');
    out.number(mesh.V(i, 1)); out.character(' ');
    out.number(mesh.V(i, 2));
    if (colors)
      for (int c = 0; c < 3; ++c) {
        out.character(' ');
        out.number(mesh.colors(i, c));
      }
    out.character('\n');
  }
  const bool with_uv = mesh.UV.rows() > 0;
  const bool with_normals = mesh.N.rows() > 0;
  // Without corner indices the attributes are per vertex: the corner's vertex indexes them.
  const std::vector<int>& face_uvs = mesh.face_uvs.empty() ? mesh.face_vertices : mesh.face_uvs;
  const std::vector<int>& face_normals =
      mesh.face_normals.empty() ? mesh.face_vertices : mesh.face_normals;
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
      if (face_uv && face_uvs[k] < 0) face_uv = false;
      if (face_normal && face_normals[k] < 0) face_normal = false;
    }
    out.character('f');
    for (std::int64_t k = begin; k < end; ++k) {
      out.character(' ');
      out.number(mesh.face_vertices[k] + 1);
      if (face_uv || face_normal) {
        out.character('/');
        if (face_uv) out.number(face_uvs[k] + 1);
        if (face_normal) {
          out.character('/');
          out.number(face_normals[k] + 1);
        }
      }
    }
    out.character('\n');
  }
  return out.take();
}

}  // namespace meshsmith::io
