// Polygon File Format (Stanford PLY): ASCII and binary reader and writer.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <utility>

namespace meshsmith::io {

namespace {

enum class Scalar { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

bool scalar_from_name(std::string_view name, Scalar& type) {
  struct Entry { std::string_view name; Scalar type; };
  static constexpr Entry table[] = {
      {"char", Scalar::int8},     {"int8", Scalar::int8},      {"uchar", Scalar::uint8},
      {"uint8", Scalar::uint8},   {"short", Scalar::int16},    {"int16", Scalar::int16},
      {"ushort", Scalar::uint16}, {"uint16", Scalar::uint16},  {"int", Scalar::int32},
      {"int32", Scalar::int32},   {"uint", Scalar::uint32},    {"uint32", Scalar::uint32},
      {"float", Scalar::float32}, {"float32", Scalar::float32}, {"double", Scalar::float64},
      {"float64", Scalar::float64}};
  for (const Entry& entry : table)
    if (entry.name == name) {
      type = entry.type;
      return true;
    }
  return false;
}

std::size_t scalar_size(Scalar type) {
  switch (type) {
    case Scalar::int8: case Scalar::uint8: return 1;
    case Scalar::int16: case Scalar::uint16: return 2;
    case Scalar::int32: case Scalar::uint32: case Scalar::float32: return 4;
    default: return 8;
  }
}

bool is_integral(Scalar type) { return type != Scalar::float32 && type != Scalar::float64; }

/// The value of a binary scalar of `type` at `data`, as a double (exact for every PLY type).
double decode_scalar(Scalar type, const char* data, bool swap) {
  switch (type) {
    case Scalar::int8: return ByteReader::decode<std::int8_t>(data, swap);
    case Scalar::uint8: return ByteReader::decode<std::uint8_t>(data, swap);
    case Scalar::int16: return ByteReader::decode<std::int16_t>(data, swap);
    case Scalar::uint16: return ByteReader::decode<std::uint16_t>(data, swap);
    case Scalar::int32: return ByteReader::decode<std::int32_t>(data, swap);
    case Scalar::uint32: return ByteReader::decode<std::uint32_t>(data, swap);
    case Scalar::float32: return ByteReader::decode<float>(data, swap);
    default: return ByteReader::decode<double>(data, swap);
  }
}

/// What read_mesh does with a property.
enum class Role {
  skip, x, y, z, nx, ny, nz, u, v, red, green, blue, alpha, face_indices, strip_indices, texcoord,
  grid_index,  // a range_grid cell's list of 0 or 1 vertex indices
  count_
};

bool is_color(Role role) { return role >= Role::red && role <= Role::alpha; }

/// The divisor that takes a colour stored as `type` to [0, 1]: 255 for 8-bit and other integer
/// types, 65535 for 16-bit unsigned, 1 for floating point. (A division, not a multiplication by
/// the reciprocal, so that k / 255 reads back as the double the writer tested.)
double color_divisor(Scalar type) {
  if (!is_integral(type)) return 1.0;
  return type == Scalar::uint16 ? 65535.0 : 255.0;
}

struct Property {
  std::string name;
  Scalar type = Scalar::float32;   // the item type for lists
  bool is_list = false;
  Scalar count_type = Scalar::uint8;
  Role role = Role::skip;
};

struct Element {
  std::string name;
  std::int64_t count = 0;
  std::vector<Property> properties;
  std::size_t header_line = 0;

  /// Fewest bytes one record can take: binary sizes (lists empty), or for ASCII one character
  /// and one separator per property; at least 1 so that a count is always bounded by the file.
  std::size_t minimum_record_bytes(bool binary) const {
    std::size_t bytes = 0;
    for (const Property& property : properties)
      bytes += binary ? scalar_size(property.is_list ? property.count_type : property.type) : 2;
    return bytes > 0 ? bytes : 1;
  }
};

enum class Encoding { ascii, binary_little_endian, binary_big_endian };

struct Header {
  Encoding encoding = Encoding::ascii;
  std::vector<Element> elements;
  std::size_t body_offset = 0;  // first byte after end_header's line
  std::size_t body_line = 0;    // line number of the first body line (ASCII)
  std::int64_t grid_rows = -1, grid_cols = -1;  // obj_info num_rows / num_cols (range scans), -1: not given
};

/// red, green, blue, alpha (and the diffuse_ names of older Stanford files).
Role color_role(std::string_view name) {
  if (name.substr(0, 8) == "diffuse_") name.remove_prefix(8);
  if (name == "red") return Role::red;
  if (name == "green") return Role::green;
  if (name == "blue") return Role::blue;
  if (name == "alpha") return Role::alpha;
  return Role::skip;
}

Role vertex_role(std::string_view name) {
  if (name == "x") return Role::x;
  if (name == "y") return Role::y;
  if (name == "z") return Role::z;
  if (name == "nx") return Role::nx;
  if (name == "ny") return Role::ny;
  if (name == "nz") return Role::nz;
  if (name == "u" || name == "s" || name == "texture_u" || name == "texture_s") return Role::u;
  if (name == "v" || name == "t" || name == "texture_v" || name == "texture_t") return Role::v;
  return color_role(name);
}

Header parse_header(const std::string& path, std::string_view bytes) {
  LineReader lines(path, bytes);
  std::string_view line, token;
  if (!lines.next(line) || line != "ply") lines.fail("not a PLY file (the first line is not 'ply')");
  Header header;
  bool have_format = false, have_end = false;
  while (!have_end && lines.next(line)) {
    Tokens tokens(line);
    if (!tokens.next(token)) continue;
    if (token == "comment") continue;
    if (token == "obj_info") {  // free text; a range scan's grid size is read from it
      std::string_view key, value;
      std::int64_t number = 0;
      if (tokens.next(key) && (key == "num_rows" || key == "num_cols") && tokens.next(value) &&
          tokens.empty() && parse_integer(value, number) && number >= 0)
        (key == "num_rows" ? header.grid_rows : header.grid_cols) = number;
      continue;
    }
    if (token == "format") {
      std::string_view encoding, version;
      if (!tokens.next(encoding) || !tokens.next(version) || !tokens.empty())
        lines.fail("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
      if (encoding == "ascii") header.encoding = Encoding::ascii;
      else if (encoding == "binary_little_endian") header.encoding = Encoding::binary_little_endian;
      else if (encoding == "binary_big_endian") header.encoding = Encoding::binary_big_endian;
      else lines.fail("unknown PLY format " + quoted(encoding));
      have_format = true;
    } else if (token == "element") {
      Element element;
      std::string_view name, count;
      if (!tokens.next(name) || !tokens.next(count) || !tokens.empty())
        lines.fail("expected 'element <name> <count>'");
      element.name = std::string(name);
      if (!parse_integer(count, element.count))
        lines.fail("element count " + quoted(count) + " is not an integer");
      if (element.count < 0)
        lines.fail("negative element count " + std::to_string(element.count));
      element.header_line = lines.line_number();
      if (element.name == "vertex")
        for (const Element& earlier : header.elements)
          if (earlier.name == "vertex") lines.fail("a second 'vertex' element");
      header.elements.push_back(std::move(element));
    } else if (token == "property") {
      if (header.elements.empty()) lines.fail("'property' before any 'element'");
      Property property;
      std::string_view type, name;
      if (!tokens.next(type)) lines.fail("expected a property type");
      if (type == "list") {
        std::string_view count_type;
        property.is_list = true;
        if (!tokens.next(count_type) || !tokens.next(type) || !tokens.next(name) || !tokens.empty())
          lines.fail("expected 'property list <count type> <item type> <name>'");
        if (!scalar_from_name(count_type, property.count_type))
          lines.fail("unknown PLY type " + quoted(count_type));
        if (!is_integral(property.count_type)) lines.fail("a list count must have an integer type");
      } else if (!tokens.next(name) || !tokens.empty()) {
        lines.fail("expected 'property <type> <name>'");
      }
      if (!scalar_from_name(type, property.type))
        lines.fail("unknown PLY type " + quoted(type));
      property.name = std::string(name);
      Element& element = header.elements.back();
      if (element.name == "vertex" && !property.is_list) {
        property.role = vertex_role(name);
      } else if (element.name == "face" && !property.is_list) {
        property.role = color_role(name);
      } else if (element.name == "face" && property.is_list && name == "texcoord") {
        property.role = Role::texcoord;
      } else if (property.is_list && (name == "vertex_indices" || name == "vertex_index")) {
        if (element.name == "face") property.role = Role::face_indices;
        if (element.name == "tristrips") property.role = Role::strip_indices;
        if (element.name == "range_grid") property.role = Role::grid_index;
        if (property.role != Role::skip && !is_integral(property.type))
          lines.fail("vertex indices must have an integer type");
      }
      element.properties.push_back(std::move(property));
    } else if (token == "end_header") {
      have_end = true;
    } else {
      lines.fail("unknown PLY header keyword " + quoted(token));
    }
  }
  if (!have_end) lines.fail("the header has no 'end_header'");
  if (!have_format) lines.fail("the header has no 'format' line");
  header.body_offset = lines.offset();
  header.body_line = lines.line_number() + 1;
  // Every element's count must fit in the body: bound before allocating anything.
  const bool binary = header.encoding != Encoding::ascii;
  const std::size_t body = bytes.size() - header.body_offset;
  std::size_t needed = 0;
  for (const Element& element : header.elements) {
    const std::size_t record = element.minimum_record_bytes(binary);
    if (static_cast<std::uint64_t>(element.count) > (body + 1) / record ||
        needed + element.count * record > body + 1 + header.elements.size())
      throw InputError(path + ": line " + std::to_string(element.header_line) + ": element '" +
                       printable(element.name) + "' announces " + std::to_string(element.count) +
                       " records, more than the " + std::to_string(body) +
                       " bytes after the header can hold");
    needed += element.count * record;
  }
  return header;
}

/// Which of the optional roles an element declares.
struct RoleSet {
  bool present[static_cast<int>(Role::count_)] = {};
  explicit RoleSet(const Element& element) {
    for (const Property& property : element.properties) present[static_cast<int>(property.role)] = true;
  }
  bool operator[](Role role) const { return present[static_cast<int>(role)]; }
  bool colors() const { return (*this)[Role::red] && (*this)[Role::green] && (*this)[Role::blue]; }
};

/// Receives the values of the roles that read_mesh keeps, whatever the encoding.
class MeshBuilder {
 public:
  MeshBuilder(const std::string& path, bool read_faces) : path_(path), read_faces_(read_faces) {}

  void begin_vertices(const Element& element) {
    has_vertices_ = true;
    vertex_count_ = element.count;
    vertex_limit_ = static_cast<double>(element.count);
    if (vertex_count_ > INT_MAX) throw InputError(path_ + ": too many vertices");
    const RoleSet roles(element);
    if (!roles[Role::x] || !roles[Role::y] || !roles[Role::z])
      throw InputError(path_ + ": line " + std::to_string(element.header_line) +
                       ": the vertex element lacks an x, y or z property");
    has_normals_ = roles[Role::nx] && roles[Role::ny] && roles[Role::nz];
    has_uv_ = roles[Role::u] && roles[Role::v];
    has_colors_ = read_faces_ && roles.colors();
    mesh.V.resize(vertex_count_, 3);
    if (has_normals_) mesh.N.resize(vertex_count_, 3);
    if (has_uv_) mesh.UV.resize(vertex_count_, 2);
    if (has_colors_) {
      mesh.colors.setOnes(vertex_count_, 4);  // alpha 1 unless the file gives it
      alpha_ = roles[Role::alpha];
    }
    for (const Property& property : element.properties)
      if (is_color(property.role)) vertex_color_divisor_[color_channel(property.role)] = color_divisor(property.type);
  }

  /// Where the values of `role` go: a column of V, N, UV or the colours (pointer to row 0, row
  /// stride, and the divisor to apply), or nullptr when the role is not kept.
  struct Destination { double* data; Eigen::Index stride; double divisor; };
  Destination destination(Role role) {
    const int r = static_cast<int>(role);
    if (role == Role::x || role == Role::y || role == Role::z) return {mesh.V.data() + (r - int(Role::x)), 3, 1.0};
    if (has_normals_ && (role == Role::nx || role == Role::ny || role == Role::nz))
      return {mesh.N.data() + (r - int(Role::nx)), 3, 1.0};
    if (has_uv_ && (role == Role::u || role == Role::v)) return {mesh.UV.data() + (r - int(Role::u)), 2, 1.0};
    if (has_colors_ && is_color(role))
      return {mesh.colors.data() + color_channel(role), 4, vertex_color_divisor_[color_channel(role)]};
    return {nullptr, 0, 1.0};
  }

  bool reads_faces() const { return read_faces_; }

  /// Stores `value` of vertex `i`; false when the value is not finite where it matters.
  bool vertex_value(std::int64_t i, Role role, double value) {
    const Destination to = destination(role);
    if (to.data) to.data[i * to.stride] = value / to.divisor;
    return role == Role::skip || std::isfinite(value);
  }

  /// Declares the face element: its colour and texcoord properties.
  void begin_faces(const Element& element) {
    if (!read_faces_) return;
    const RoleSet roles(element);
    face_colors_ = roles.colors();
    face_texcoords_ = roles[Role::texcoord];
    face_alpha_ = roles[Role::alpha];
    for (const Property& property : element.properties)
      if (is_color(property.role)) face_color_divisor_[color_channel(property.role)] = color_divisor(property.type);
    if (face_colors_) face_rgba_.reserve(4 * static_cast<std::size_t>(element.count));
  }

  /// Stores the scalar `value` of `role` for the current face record; false when not finite.
  bool face_value(Role role, double value) {
    if (!is_color(role)) return true;
    if (!std::isfinite(value)) return false;
    if (face_colors_) record_rgba_[color_channel(role)] = value / face_color_divisor_[color_channel(role)];
    return true;
  }

  /// Ends face record `r`: stores its colour and pairs its texcoord list with its corners.
  /// "" or an error message.
  std::string end_face_record() {
    if (!read_faces_) return {};
    if (face_colors_) {
      face_rgba_.insert(face_rgba_.end(), record_rgba_, record_rgba_ + 4);
      record_rgba_[3] = 1.0;
    }
    if (!face_texcoords_) return {};
    const std::size_t corners = mesh.face_vertices.size() - mesh.face_uvs.size();
    if (record_uv_.empty()) {
      mesh.face_uvs.insert(mesh.face_uvs.end(), corners, -1);
    } else if (record_uv_.size() == 2 * corners) {
      for (std::size_t k = 0; k < corners; ++k) mesh.face_uvs.push_back(static_cast<int>(uv_values_.size() / 2 + k));
      uv_values_.insert(uv_values_.end(), record_uv_.begin(), record_uv_.end());
    } else {
      const std::size_t given = record_uv_.size();
      record_uv_.clear();
      return "texcoord list of " + std::to_string(given) + " values for " + std::to_string(corners) +
             " corners (2 per corner, or none)";
    }
    record_uv_.clear();
    return {};
  }

  /// Reserves room for `faces` more faces of about `corners` corners in all.
  void reserve_faces(std::size_t faces, std::size_t corners) {
    if (!read_faces_) return;
    mesh.face_offsets.reserve(mesh.face_offsets.size() + faces);
    mesh.face_vertices.reserve(mesh.face_vertices.size() + corners);
  }

  /// Starts a list of `count` values of a face, strip or texcoord property; "" or an error.
  std::string begin_list(Role role, std::int64_t count) {
    role_ = role;
    list_.clear();
    if (role == Role::face_indices && count < 3)
      return "face with " + std::to_string(count) + " corners (at least 3 needed)";
    if (role == Role::grid_index && count > 1)
      return "range grid cell with " + std::to_string(count) + " vertex indices (0 or 1 expected)";
    return {};
  }

  /// Adds a value to the current list; false when it is out of range or not finite (see
  /// index_error).
  bool add_index(double value) {
    if (role_ == Role::texcoord) {
      if (!std::isfinite(value)) return false;
      if (read_faces_) record_uv_.push_back(value);
      return true;
    }
    if (role_ == Role::grid_index) {
      if (!(value >= 0 && value < vertex_limit_)) return false;
      list_.push_back(static_cast<int>(value));
      return true;
    }
    if (role_ == Role::strip_indices) {
      if (value == -1) {
        list_.push_back(-1);
        return true;
      }
      if (!(value >= 0 && value < vertex_limit_)) return false;
      list_.push_back(static_cast<int>(value));
      return true;
    }
    if (!(value >= 0 && value < vertex_limit_)) return false;
    if (read_faces_) mesh.face_vertices.push_back(static_cast<int>(value));
    return true;
  }

  /// Adds a face of `size` 32-bit indices at `data` (int32 or uint32: both are in range only
  /// when below the vertex count as unsigned); false, adding nothing, if one is out of range.
  bool add_face(const char* data, int size, bool swap) {
    const std::size_t first = mesh.face_vertices.size();
    for (int k = 0; k < size; ++k) {
      const std::uint32_t index = ByteReader::decode<std::uint32_t>(data + 4 * k, swap);
      if (index >= static_cast<std::uint64_t>(vertex_count_)) {
        if (read_faces_) mesh.face_vertices.resize(first);
        return false;
      }
      if (read_faces_) mesh.face_vertices.push_back(static_cast<int>(index));
    }
    if (read_faces_) mesh.face_offsets.push_back(mesh.face_vertices.size());
    return true;
  }

  std::int64_t vertex_count() const { return vertex_count_; }

  std::string index_error(double value) const {
    if (role_ == Role::texcoord) return "a texture coordinate is not finite";
    OutputBuffer text;  // exact for integers, and no out-of-range cast for huge ASCII values
    text.number(value);
    return "vertex index " + std::string(text.contents()) + " outside [0, " +
           std::to_string(vertex_count_) + ")";
  }

  /// Ends the current list.
  void end_list() {
    if (!read_faces_) return;
    if (role_ == Role::face_indices) mesh.face_offsets.push_back(mesh.face_vertices.size());
    else if (role_ == Role::strip_indices) add_strips();
    else if (role_ == Role::grid_index) mesh.range_grid.push_back(list_.empty() ? -1 : list_.front());
  }

  /// Keeps the range grid when the header gave its size and the cell count matches it; else a
  /// warning and no grid.
  void finish_grid(const Header& header) {
    if (!read_faces_) return;
    bool declared = false;
    for (const Element& element : header.elements)
      if (element.name == "range_grid") declared = RoleSet(element)[Role::grid_index];
    if (!declared) return;
    const auto cells = static_cast<std::int64_t>(mesh.range_grid.size());
    if (header.grid_rows < 0 || header.grid_cols < 0) {
      mesh.warnings.push_back("the range_grid element is not kept: the header gives no 'obj_info num_rows' and 'obj_info num_cols'");
      mesh.range_grid.clear();
    } else if (header.grid_rows == 0 ? cells != 0
                                     : cells % header.grid_rows != 0 || cells / header.grid_rows != header.grid_cols) {
      mesh.warnings.push_back("the range_grid element is not kept: " + std::to_string(cells) + " cells, not num_rows × num_cols = " +
                              std::to_string(header.grid_rows) + " × " + std::to_string(header.grid_cols));
      mesh.range_grid.clear();
    } else {
      mesh.range_grid_rows = header.grid_rows;
      mesh.range_grid_cols = header.grid_cols;
    }
  }

  bool needs_vertex_count() const { return !has_vertices_; }

  /// The mesh with its attributes in their final form: per-vertex normals and UVs indexed by
  /// the corners' vertices, per-corner UVs from texcoord lists (they win over per-vertex ones),
  /// colours with 3 columns when the file gives no alpha.
  PolygonMesh finish() {
    if (!read_faces_) return std::move(mesh);
    if (mesh.N.rows() > 0) mesh.face_normals = mesh.face_vertices;
    const bool per_corner_uv = face_texcoords_ && !uv_values_.empty();
    if (per_corner_uv) {
      if (mesh.UV.rows() > 0)
        mesh.warnings.push_back("the faces' texcoord lists are read; the vertices' texture coordinates are not");
      mesh.UV.resize(static_cast<Eigen::Index>(uv_values_.size() / 2), 2);
      std::copy(uv_values_.begin(), uv_values_.end(), mesh.UV.data());
      if (mesh.face_uvs.size() != mesh.face_vertices.size())  // strips: corners without texcoords
        mesh.face_uvs.resize(mesh.face_vertices.size(), -1);
    } else {
      mesh.face_uvs.clear();
      if (mesh.UV.rows() > 0) mesh.face_uvs = mesh.face_vertices;
    }
    if (has_colors_ && !alpha_) mesh.colors = ColorMatrix(mesh.colors.leftCols(3));
    if (face_colors_) {
      const auto faces = static_cast<Eigen::Index>(face_rgba_.size() / 4);
      if (faces != mesh.face_count()) {
        mesh.warnings.push_back("the face colours are not read: tristrips add faces that have none");
      } else {
        mesh.face_colors.resize(faces, face_alpha_ ? 4 : 3);
        for (Eigen::Index f = 0; f < faces; ++f)
          for (Eigen::Index c = 0; c < mesh.face_colors.cols(); ++c) mesh.face_colors(f, c) = face_rgba_[4 * f + c];
      }
    }
    return std::move(mesh);
  }

  PolygonMesh mesh;

 private:
  static int color_channel(Role role) { return static_cast<int>(role) - static_cast<int>(Role::red); }

  /// Triangles of a strip (v0 v1 v2 ...; -1 restarts): (a, b, c) with a, b swapped on odd
  /// positions so that all triangles keep the first one's orientation; degenerate ones dropped.
  void add_strips() {
    std::size_t start = 0;
    for (std::size_t k = 0; k <= list_.size(); ++k) {
      if (k < list_.size() && list_[k] != -1) continue;
      for (std::size_t i = start; i + 2 < k; ++i) {
        int a = list_[i], b = list_[i + 1];
        const int c = list_[i + 2];
        if ((i - start) % 2 == 1) std::swap(a, b);
        if (a == b || b == c || a == c) continue;
        mesh.face_vertices.insert(mesh.face_vertices.end(), {a, b, c});
        mesh.face_offsets.push_back(mesh.face_vertices.size());
      }
      start = k + 1;
    }
  }

  const std::string& path_;
  bool read_faces_;
  bool has_vertices_ = false, has_normals_ = false, has_uv_ = false, has_colors_ = false, alpha_ = false;
  bool face_colors_ = false, face_texcoords_ = false, face_alpha_ = false;
  double vertex_color_divisor_[4] = {1, 1, 1, 1}, face_color_divisor_[4] = {1, 1, 1, 1};
  double record_rgba_[4] = {0, 0, 0, 1};
  std::vector<double> face_rgba_, record_uv_, uv_values_;
  std::int64_t vertex_count_ = 0;
  double vertex_limit_ = 0;
  Role role_ = Role::skip;
  std::vector<int> list_;
};

/// The vertex element when all its properties have fixed sizes: decode only the kept ones at
/// their offsets in each record.
void parse_fixed_vertices(ByteReader& in, const Element& element, MeshBuilder& builder) {
  struct Field { std::size_t offset; const Property* property; MeshBuilder::Destination to; };
  std::vector<Field> fields;
  std::size_t record = 0;
  for (const Property& property : element.properties) {
    if (property.role != Role::skip) fields.push_back({record, &property, builder.destination(property.role)});
    record += scalar_size(property.type);
  }
  in.require(record * element.count, "the vertex element");
  const char* base = in.here();
  const bool swap = in.swap();
  for (const Field& field : fields) {
    const char* data = base + field.offset;
    double* out = field.to.data;
    const Eigen::Index stride = field.to.stride;
    const double divisor = field.to.divisor;
    const Scalar type = field.property->type;
    for (std::int64_t r = 0; r < element.count; ++r, data += record) {
      const double value = type == Scalar::float32 ? ByteReader::decode<float>(data, swap)
                           : type == Scalar::float64 ? ByteReader::decode<double>(data, swap)
                                                     : decode_scalar(type, data, swap);
      if (!std::isfinite(value))
        in.fail_at(in.offset() + r * record + field.offset,
                   "vertex " + std::to_string(r) + " has a non-finite " + field.property->name);
      if (out) out[r * stride] = divisor == 1.0 ? value : value / divisor;
    }
  }
  in.skip(record * element.count, "the vertex element");
}

/// Faces that are all triangles of 32-bit indices (13-byte records): decoded in one tight loop.
/// False, with nothing consumed or stored, when they are not, or when an index is out of range
/// (the caller's per-face loop then reports it).
bool parse_uniform_triangles(ByteReader& in, std::int64_t count, bool swap, MeshBuilder& builder) {
  constexpr std::size_t record = 13;
  if (in.remaining_bytes() / record < static_cast<std::uint64_t>(count)) return false;
  const char* base = in.here();
  for (std::int64_t r = 0; r < count; ++r)
    if (base[r * record] != 3) return false;
  const auto limit = static_cast<std::uint32_t>(builder.vertex_count());
  bool out_of_range = false;
  if (builder.reads_faces()) {
    auto& corners = builder.mesh.face_vertices;
    auto& offsets = builder.mesh.face_offsets;
    const std::size_t first_corner = corners.size(), first_face = offsets.size();
    corners.resize(first_corner + 3 * count);
    offsets.resize(first_face + count);
    int* out = corners.data() + first_corner;
    std::int64_t* ends = offsets.data() + first_face;
    const std::int64_t start = static_cast<std::int64_t>(first_corner);
    for (std::int64_t r = 0; r < count; ++r) {
      const char* data = base + r * record + 1;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t index = ByteReader::decode<std::uint32_t>(data + 4 * k, swap);
        out_of_range |= index >= limit;
        out[3 * r + k] = static_cast<int>(index);
      }
      ends[r] = start + 3 * (r + 1);
    }
    if (out_of_range) {
      corners.resize(first_corner);
      offsets.resize(first_face);
    }
  } else {
    for (std::int64_t r = 0; r < count; ++r)
      for (int k = 0; k < 3; ++k)
        out_of_range |= ByteReader::decode<std::uint32_t>(base + r * record + 1 + 4 * k, swap) >= limit;
  }
  if (out_of_range) return false;
  in.skip(record * count, "faces");
  return true;
}

/// The common face element (only `list uchar int|uint vertex_indices`): a tight loop that
/// writes the indices straight into the mesh.
bool parse_simple_faces(ByteReader& in, const Element& element, MeshBuilder& builder) {
  if (element.properties.size() != 1) return false;
  const Property& property = element.properties[0];
  if (property.role != Role::face_indices || scalar_size(property.count_type) != 1 ||
      (property.type != Scalar::int32 && property.type != Scalar::uint32))
    return false;
  const bool swap = in.swap();
  const bool signed_count = property.count_type == Scalar::int8;
  if (parse_uniform_triangles(in, element.count, swap, builder)) return true;
  for (std::int64_t r = 0; r < element.count; ++r) {
    const std::size_t start = in.offset();
    in.require(1, "a face size");
    const int size = signed_count ? static_cast<int>(static_cast<std::int8_t>(*in.here()))
                                  : static_cast<int>(static_cast<std::uint8_t>(*in.here()));
    const std::string error = size < 3 ? builder.begin_list(Role::face_indices, size) : std::string();
    if (!error.empty()) in.fail_at(start, "face " + std::to_string(r) + ": " + error);
    in.skip(1, "a face size");
    in.require(4 * static_cast<std::size_t>(size), "face indices");
    const char* data = in.here();
    if (!builder.add_face(data, size, swap)) {
      for (int k = 0; k < size; ++k) {
        const std::uint32_t index = ByteReader::decode<std::uint32_t>(data + 4 * k, swap);
        const double value = property.type == Scalar::int32 ? static_cast<double>(static_cast<std::int32_t>(index)) : index;
        if (!(value >= 0 && value < static_cast<double>(builder.vertex_count())))
          in.fail_at(in.offset() + 4 * k, "face " + std::to_string(r) + ": " + builder.index_error(value));
      }
    }
    in.skip(4 * static_cast<std::size_t>(size), "face indices");
  }
  return true;
}

void parse_binary_body(const std::string& path, std::string_view bytes, const Header& header,
                       MeshBuilder& builder) {
  ByteReader in(path, bytes, header.body_offset, header.encoding == Encoding::binary_big_endian);
  const bool swap = in.swap();
  for (const Element& element : header.elements) {
    const bool is_vertex = element.name == "vertex";
    bool has_role = false, all_fixed = true;
    std::size_t fixed_size = 0;
    for (const Property& property : element.properties) {
      has_role |= property.role != Role::skip;
      all_fixed &= !property.is_list;
      fixed_size += scalar_size(property.type);
    }
    if (!has_role && all_fixed) {  // nothing to keep: skip the whole element at once
      in.skip(fixed_size * element.count, ("element '" + element.name + "'").c_str());
      continue;
    }
    if (is_vertex && all_fixed) {
      parse_fixed_vertices(in, element, builder);
      continue;
    }
    const bool is_face = element.name == "face";
    if (is_face) {
      builder.begin_faces(element);
      builder.reserve_faces(element.count, std::min<std::size_t>(3 * element.count, in.remaining_bytes() / 4));
      if (parse_simple_faces(in, element, builder)) continue;
    }
    for (std::int64_t r = 0; r < element.count; ++r) {
      const std::size_t record_start = in.offset();
      for (const Property& property : element.properties) {
        if (!property.is_list) {
          const std::size_t size = scalar_size(property.type);
          in.require(size, property.name.c_str());
          if (property.role != Role::skip) {
            const double value = decode_scalar(property.type, in.here(), swap);
            if (is_vertex ? !builder.vertex_value(r, property.role, value)
                          : !builder.face_value(property.role, value))
              in.fail(element.name + " " + std::to_string(r) + " has a non-finite " + property.name);
          }
          in.skip(size, property.name.c_str());
          continue;
        }
        const std::size_t list_start = in.offset();
        const std::size_t count_size = scalar_size(property.count_type);
        in.require(count_size, property.name.c_str());
        const double count = decode_scalar(property.count_type, in.here(), swap);
        if (count < 0) in.fail("negative list length " + std::to_string(static_cast<std::int64_t>(count)));
        in.skip(count_size, property.name.c_str());
        const std::size_t item_size = scalar_size(property.type);
        const auto items = static_cast<std::size_t>(count);
        in.require(items * item_size, property.name.c_str());
        if (property.role == Role::skip) {
          in.skip(items * item_size, property.name.c_str());
          continue;
        }
        std::string error = builder.begin_list(property.role, static_cast<std::int64_t>(items));
        if (!error.empty()) in.fail_at(list_start, element.name + " " + std::to_string(r) + ": " + error);
        const char* data = in.here();
        for (std::size_t k = 0; k < items; ++k) {
          const double index = decode_scalar(property.type, data + k * item_size, swap);
          if (!builder.add_index(index))
            in.fail_at(in.offset() + k * item_size,
                       element.name + " " + std::to_string(r) + ": " + builder.index_error(index));
        }
        in.skip(items * item_size, property.name.c_str());
        builder.end_list();
      }
      if (is_face) {
        const std::string error = builder.end_face_record();
        if (!error.empty()) in.fail_at(record_start, "face " + std::to_string(r) + ": " + error);
      }
    }
  }
}

void parse_ascii_body(const std::string& path, std::string_view bytes, const Header& header,
                      MeshBuilder& builder) {
  LineReader lines(path, bytes.substr(header.body_offset), header.body_line);
  std::string_view line, token;
  auto next_value = [&](Tokens& tokens, const Property& property, const Element& element,
                        std::int64_t r) {
    if (!tokens.next(token))
      lines.fail(element.name + " " + std::to_string(r) + ": missing a value for '" + property.name + "'");
    return token;
  };
  for (const Element& element : header.elements) {
    if (element.properties.empty()) continue;
    const bool is_vertex = element.name == "vertex", is_face = element.name == "face";
    if (is_face) builder.begin_faces(element);
    for (const Property& property : element.properties)
      if (property.role == Role::face_indices)
        builder.reserve_faces(element.count, std::min<std::size_t>(3 * element.count, lines.remaining_bytes() / 2));
    for (std::int64_t r = 0; r < element.count; ++r) {
      if (!lines.next_content(line, '\0'))
        lines.fail("unexpected end of file in element '" + element.name + "' (" + std::to_string(r) +
                   " of " + std::to_string(element.count) + " records read)");
      Tokens tokens(line);
      for (const Property& property : element.properties) {
        if (!property.is_list) {
          std::string_view value_token = next_value(tokens, property, element, r);
          double value;
          if (!parse_double(value_token, value))
            lines.fail(quoted(value_token) + " is not a finite number");
          if (property.role != Role::skip) {
            if (is_vertex) builder.vertex_value(r, property.role, value);
            else builder.face_value(property.role, value);
          }
          continue;
        }
        std::string_view count_token = next_value(tokens, property, element, r);
        std::int64_t count;
        if (!parse_integer(count_token, count) || count < 0)
          lines.fail(quoted(count_token) + " is not a list length");
        if (property.role != Role::skip) {
          std::string error = builder.begin_list(property.role, count);
          if (!error.empty()) lines.fail(element.name + " " + std::to_string(r) + ": " + error);
        }
        for (std::int64_t k = 0; k < count; ++k) {
          std::string_view item = next_value(tokens, property, element, r);
          double value;
          if (!parse_double(item, value))
            lines.fail(quoted(item) + " is not a finite number");
          if (property.role == Role::skip) continue;
          if (property.role != Role::texcoord && value != std::floor(value))
            lines.fail("vertex index " + quoted(item) + " is not an integer");
          if (!builder.add_index(value))
            lines.fail(element.name + " " + std::to_string(r) + ": " + builder.index_error(value));
        }
        if (property.role != Role::skip) builder.end_list();
      }
      if (!tokens.empty())
        lines.fail(element.name + " " + std::to_string(r) + ": more values than the header declares");
      if (is_face) {
        const std::string error = builder.end_face_record();
        if (!error.empty()) lines.fail("face " + std::to_string(r) + ": " + error);
      }
    }
  }
}

}  // namespace

PolygonMesh parse_ply(const std::string& path, std::string_view bytes, bool read_faces) {
  const Header header = parse_header(path, bytes);
  MeshBuilder builder(path, read_faces);
  // The vertex count is needed to check indices, whichever element comes first.
  for (const Element& element : header.elements)
    if (element.name == "vertex" && builder.needs_vertex_count()) builder.begin_vertices(element);
  if (builder.needs_vertex_count()) throw InputError(path + ": the PLY header has no 'vertex' element");
  if (header.encoding == Encoding::ascii) parse_ascii_body(path, bytes, header, builder);
  else parse_binary_body(path, bytes, header, builder);
  if (builder.mesh.V.rows() == 0) throw InputError(path + ": the PLY file has no vertices");
  builder.finish_grid(header);
  return builder.finish();
}

namespace {

/// True when every value is k / 255 for an integer k (what 8-bit colours read back as).
bool is_8bit(const ColorMatrix& colors) {
  for (Eigen::Index r = 0; r < colors.rows(); ++r)
    for (Eigen::Index c = 0; c < colors.cols(); ++c)
      if (std::round(colors(r, c) * 255.0) / 255.0 != colors(r, c)) return false;
  return true;
}

/// Writes PLY values one after another, as text (space-separated) or binary.
class PlyRecords {
 public:
  PlyRecords(OutputBuffer& out, bool binary, bool big_endian)
      : out_(out), binary_(binary), big_endian_(big_endian) {}
  void real(double value) {
    if (binary_) out_.binary<double>(value, big_endian_);
    else separate(), out_.number(value);
  }
  void integer(std::int32_t value, bool as_byte) {
    if (binary_ && as_byte) out_.binary<std::uint8_t>(static_cast<std::uint8_t>(value), big_endian_);
    else if (binary_) out_.binary<std::int32_t>(value, big_endian_);
    else separate(), out_.number(value);
  }
  void color(double value, bool as_byte) {
    if (as_byte) integer(static_cast<std::int32_t>(std::round(value * 255.0)), true);
    else real(value);
  }
  void end_record() {
    if (!binary_) out_.character('\n');
    first_ = true;
  }

 private:
  void separate() {
    if (!first_) out_.character(' ');
    first_ = false;
  }
  OutputBuffer& out_;
  bool binary_, big_endian_, first_ = true;
};

}  // namespace

std::string format_ply(const PolygonMesh& mesh, bool binary, bool big_endian) {
  // check_format_holds made sure that normals are per vertex; UVs that agree at every vertex are
  // written per vertex, others as per-corner texcoord lists on the faces.
  VertexMatrix normals;
  UVMatrix vertex_uvs;
  const bool with_normals = per_vertex_values(mesh, mesh.N, mesh.face_normals, normals);
  const bool uv_per_vertex = per_vertex_values(mesh, mesh.UV, mesh.face_uvs, vertex_uvs);
  const bool uv_per_corner = mesh.UV.rows() > 0 && !uv_per_vertex;
  const bool colors = mesh.colors.rows() > 0, face_colors = mesh.face_colors.rows() > 0;
  const bool byte_colors = colors && is_8bit(mesh.colors);
  const bool byte_face_colors = face_colors && is_8bit(mesh.face_colors);
  std::int64_t largest_face = 0;
  for (std::int64_t f = 0; f < mesh.face_count(); ++f)
    largest_face = std::max(largest_face, mesh.face_offsets[f + 1] - mesh.face_offsets[f]);
  const bool wide_counts = largest_face > 255;
  const bool wide_texcoord_counts = 2 * largest_face > 255;

  OutputBuffer out;
  out.reserve(512 + mesh.V.rows() * (24 + (with_normals ? 24 : 0) + (uv_per_vertex ? 16 : 0) + (colors ? 32 : 0)) +
              mesh.face_count() * (1 + (face_colors ? 32 : 0)) + mesh.face_vertices.size() * (uv_per_corner ? 20 : 4));
  out.text("ply\nformat ");
  out.text(!binary ? "ascii" : big_endian ? "binary_big_endian" : "binary_little_endian");
  out.text(" 1.0\ncomment written by meshsmith\nelement vertex ");
  out.number(static_cast<std::int64_t>(mesh.V.rows()));
  out.text("\nproperty double x\nproperty double y\nproperty double z\n");
  if (with_normals) out.text("property double nx\nproperty double ny\nproperty double nz\n");
  if (uv_per_vertex) out.text("property double texture_u\nproperty double texture_v\n");
  static const char* const channels[] = {"red", "green", "blue", "alpha"};
  auto color_properties = [&](const ColorMatrix& matrix, bool as_bytes) {
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
      out.text(as_bytes ? "property uchar " : "property double ");
      out.text(channels[c]);
      out.character('\n');
    }
  };
  if (colors) color_properties(mesh.colors, byte_colors);
  if (mesh.face_count() > 0) {
    out.text("element face ");
    out.number(mesh.face_count());
    out.text(wide_counts ? "\nproperty list int int vertex_indices\n"
                         : "\nproperty list uchar int vertex_indices\n");
    if (face_colors) color_properties(mesh.face_colors, byte_face_colors);
    if (uv_per_corner)
      out.text(wide_texcoord_counts ? "property list int double texcoord\n" : "property list uchar double texcoord\n");
  }
  out.text("end_header\n");

  if (binary && !with_normals && !uv_per_vertex && !colors) {
    // The common case: x y z doubles laid out in place, a block at a time.
    const bool swap = big_endian != ByteReader::host_is_big_endian();
    char* at = out.extend(static_cast<std::size_t>(mesh.V.rows()) * 24);
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      for (int c = 0; c < 3; ++c, at += 8) {
        const double value = mesh.V(i, c);
        std::memcpy(at, &value, 8);
        if (swap) std::reverse(at, at + 8);
      }
  } else {
    PlyRecords records(out, binary, big_endian);
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i) {
      for (int c = 0; c < 3; ++c) records.real(mesh.V(i, c));
      if (with_normals)
        for (int c = 0; c < 3; ++c) records.real(normals(i, c));
      if (uv_per_vertex)
        for (int c = 0; c < 2; ++c) records.real(vertex_uvs(i, c));
      if (colors)
        for (Eigen::Index c = 0; c < mesh.colors.cols(); ++c) records.color(mesh.colors(i, c), byte_colors);
      records.end_record();
    }
  }
  if (!binary && !face_colors && !uv_per_corner) {
    append_face_lines(out, mesh);
    return out.take();
  }
  if (binary && !face_colors && !uv_per_corner) {
    // Face records laid out in place.
    const bool swap = big_endian != ByteReader::host_is_big_endian();
    const std::size_t count_bytes = wide_counts ? 4 : 1;
    char* at = out.extend(mesh.face_count() * count_bytes + mesh.face_vertices.size() * 4);
    for (std::int64_t f = 0; f < mesh.face_count(); ++f) {
      const std::int64_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
      const auto size = static_cast<std::int32_t>(end - begin);
      if (wide_counts) {
        std::memcpy(at, &size, 4);
        if (swap) std::reverse(at, at + 4);
      } else {
        *at = static_cast<char>(static_cast<std::uint8_t>(size));
      }
      at += count_bytes;
      std::memcpy(at, mesh.face_vertices.data() + begin, 4 * static_cast<std::size_t>(size));
      if (swap)
        for (std::int32_t k = 0; k < size; ++k) std::reverse(at + 4 * k, at + 4 * k + 4);
      at += 4 * static_cast<std::size_t>(size);
    }
    return out.take();
  }
  PlyRecords records(out, binary, big_endian);
  for (std::int64_t f = 0; f < mesh.face_count(); ++f) {
    const std::int64_t begin = mesh.face_offsets[f], end = mesh.face_offsets[f + 1];
    records.integer(static_cast<std::int32_t>(end - begin), !wide_counts);
    for (std::int64_t k = begin; k < end; ++k) records.integer(mesh.face_vertices[k], false);
    if (face_colors)
      for (Eigen::Index c = 0; c < mesh.face_colors.cols(); ++c) records.color(mesh.face_colors(f, c), byte_face_colors);
    if (uv_per_corner) {
      // A face with a corner without texture coordinates gets an empty list.
      bool complete = true;
      for (std::int64_t k = begin; k < end; ++k) complete &= mesh.face_uvs[k] >= 0;
      records.integer(complete ? static_cast<std::int32_t>(2 * (end - begin)) : 0, !wide_texcoord_counts);
      if (complete)
        for (std::int64_t k = begin; k < end; ++k)
          for (int c = 0; c < 2; ++c) records.real(mesh.UV(mesh.face_uvs[k], c));
    }
    records.end_record();
  }
  return out.take();
}

}  // namespace meshsmith::io
