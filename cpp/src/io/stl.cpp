// STL (stereolithography): ASCII and binary reader (with exact vertex merging) and writer.
#include <meshsmith/io/formats.h>
#include <meshsmith/io/parsing.h>

#include <Eigen/Geometry>

#include <climits>
#include <cmath>

namespace meshsmith::io {

namespace {

/// Gives one index per distinct position (exact comparison; -0 equals +0), in order of first
/// appearance: an open-addressing hash table over the positions stored so far.
class VertexWelder {
 public:
  explicit VertexWelder(std::size_t expected_corners) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected_corners) capacity *= 2;
    slots_.assign(capacity, -1);
    positions_.reserve(expected_corners * 3);
  }

  int add(double x, double y, double z) {
    if (x == 0) x = 0;  // -0 → +0 so that equal values hash equally
    if (y == 0) y = 0;
    if (z == 0) z = 0;
    if (2 * (count() + 1) > slots_.size()) grow();
    std::size_t slot = hash(x, y, z) & (slots_.size() - 1);
    while (slots_[slot] != -1) {
      const double* p = &positions_[3 * static_cast<std::size_t>(slots_[slot])];
      if (p[0] == x && p[1] == y && p[2] == z) return slots_[slot];
      slot = (slot + 1) & (slots_.size() - 1);
    }
    const int index = static_cast<int>(count());
    slots_[slot] = index;
    positions_.insert(positions_.end(), {x, y, z});
    return index;
  }

  std::size_t count() const { return positions_.size() / 3; }

  VertexMatrix vertices() const {
    VertexMatrix V(static_cast<Eigen::Index>(count()), 3);
    std::copy(positions_.begin(), positions_.end(), V.data());
    return V;
  }

 private:
  static std::size_t hash(double x, double y, double z) {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (double value : {x, y, z}) {
      std::uint64_t bits;
      std::memcpy(&bits, &value, sizeof bits);
      h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h *= 0xff51afd7ed558ccdull;
      h ^= h >> 33;
    }
    return static_cast<std::size_t>(h);
  }

  void grow() {
    std::vector<int> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, -1);
    for (int index : old) {
      if (index == -1) continue;
      const double* p = &positions_[3 * static_cast<std::size_t>(index)];
      std::size_t slot = hash(p[0], p[1], p[2]) & (slots_.size() - 1);
      while (slots_[slot] != -1) slot = (slot + 1) & (slots_.size() - 1);
      slots_[slot] = index;
    }
  }

  std::vector<int> slots_;
  std::vector<double> positions_;
};

PolygonMesh finish(VertexWelder& welder, std::vector<int>&& corners) {
  PolygonMesh mesh;
  mesh.V = welder.vertices();
  const std::size_t triangles = corners.size() / 3;
  mesh.face_offsets.resize(triangles + 1);
  for (std::size_t t = 0; t <= triangles; ++t) mesh.face_offsets[t] = 3 * static_cast<std::int64_t>(t);
  mesh.face_vertices = std::move(corners);
  return mesh;
}

PolygonMesh parse_binary_stl(const std::string& path, std::string_view bytes, std::size_t triangles) {
  ByteReader in(path, bytes, 84, /*big_endian=*/false);
  VertexWelder welder(3 * triangles);
  std::vector<int> corners;
  corners.reserve(3 * triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    in.skip(12, "a facet normal");
    for (int k = 0; k < 3; ++k) {
      double p[3];
      for (double& value : p) {
        value = in.read<float>("a facet vertex");
        if (!std::isfinite(value))
          in.fail_at(in.offset() - 4, "triangle " + std::to_string(t) + " has a non-finite coordinate");
      }
      corners.push_back(welder.add(p[0], p[1], p[2]));
    }
    in.skip(2, "a facet attribute");
  }
  return finish(welder, std::move(corners));
}

PolygonMesh parse_ascii_stl(const std::string& path, std::string_view text) {
  LineReader lines(path, text);
  VertexWelder welder(text.size() / 64);
  std::vector<int> corners;
  std::string_view line, keyword, token;
  int loop_corners = -1;  // -1: outside "outer loop"
  bool in_solid = false;
  std::size_t solids = 0;
  while (lines.next_content(line, '\0')) {
    Tokens tokens(line);
    tokens.next(keyword);
    if (keyword == "vertex") {
      if (loop_corners < 0) lines.fail("'vertex' outside an 'outer loop'");
      if (++loop_corners > 3) lines.fail("a facet with more than 3 vertices");
      double p[3];
      for (double& value : p)
        if (!tokens.next(token) || !parse_double(token, value))
          lines.fail("'vertex' needs 3 finite numbers");
      if (!tokens.empty()) lines.fail("more than 3 numbers after 'vertex'");
      if (welder.count() >= static_cast<std::size_t>(INT_MAX)) lines.fail("too many vertices");
      corners.push_back(welder.add(p[0], p[1], p[2]));
    } else if (keyword == "facet") {
      if (!in_solid) lines.fail("'facet' outside a 'solid'");
    } else if (keyword == "outer") {
      if (!in_solid) lines.fail("'outer loop' outside a 'solid'");
      if (loop_corners >= 0) lines.fail("'outer loop' inside another loop");
      loop_corners = 0;
    } else if (keyword == "endloop") {
      if (loop_corners != 3)
        lines.fail("a facet with " + std::to_string(std::max(loop_corners, 0)) + " vertices (STL facets are triangles)");
      loop_corners = -1;
    } else if (keyword == "endfacet") {
      if (loop_corners >= 0) lines.fail("'endfacet' before 'endloop'");
    } else if (keyword == "solid") {
      if (in_solid) lines.fail("'solid' inside another solid");
      in_solid = true;
      ++solids;
    } else if (keyword == "endsolid") {
      if (!in_solid || loop_corners >= 0) lines.fail("'endsolid' without a matching 'solid'");
      in_solid = false;
    } else {
      lines.fail("unknown ASCII STL keyword " + quoted(keyword));
    }
  }
  if (loop_corners >= 0 || in_solid) lines.fail("unexpected end of file inside a solid");
  if (solids == 0 || corners.empty()) throw InputError(path + ": the STL file has no triangles");
  return finish(welder, std::move(corners));
}

}  // namespace

PolygonMesh parse_stl(const std::string& path, std::string_view bytes) {
  if (bytes.size() >= 84) {
    const std::uint32_t triangles = ByteReader::decode<std::uint32_t>(bytes.data() + 80, ByteReader::host_is_big_endian());
    if (bytes.size() == 84 + 50 * static_cast<std::uint64_t>(triangles)) {
      if (triangles == 0) throw InputError(path + ": byte 80: the binary STL file has no triangles");
      return parse_binary_stl(path, bytes, triangles);
    }
  }
  std::size_t i = 0;
  while (i < bytes.size() && (is_blank(bytes[i]) || bytes[i] == '\n')) ++i;
  if (bytes.substr(i, 5) == "solid") return parse_ascii_stl(path, bytes);
  if (bytes.size() < 84) throw InputError(path + ": byte 0: too short for a binary STL file and not ASCII STL");
  const std::uint32_t triangles = ByteReader::decode<std::uint32_t>(bytes.data() + 80, ByteReader::host_is_big_endian());
  throw InputError(path + ": byte 80: the binary STL header announces " + std::to_string(triangles) +
                   " triangles (" + std::to_string(84 + 50 * static_cast<std::uint64_t>(triangles)) +
                   " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
}

std::string format_stl(const PolygonMesh& mesh, bool binary) {
  const FaceMatrix F = triangulate_fan(mesh.face_offsets, mesh.face_vertices);
  OutputBuffer out;
  auto normal_of = [&](Eigen::Index t) {
    const Eigen::Vector3d a = mesh.V.row(F(t, 0)), b = mesh.V.row(F(t, 1)), c = mesh.V.row(F(t, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double length = n.norm();
    return length > 0 && std::isfinite(length) ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
  };
  if (binary) {
    out.reserve(84 + 50 * F.rows());
    std::string header = "binary STL written by meshsmith";
    header.resize(80, ' ');
    out.text(header);
    out.binary<std::uint32_t>(static_cast<std::uint32_t>(F.rows()), false);
    for (Eigen::Index t = 0; t < F.rows(); ++t) {
      const Eigen::Vector3d n = normal_of(t);
      for (int c = 0; c < 3; ++c) out.binary<float>(static_cast<float>(n[c]), false);
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) out.binary<float>(static_cast<float>(mesh.V(F(t, k), c)), false);
      out.binary<std::uint16_t>(0, false);
    }
    return out.take();
  }
  out.reserve(32 + F.rows() * 250);
  out.text("solid meshsmith\n");
  for (Eigen::Index t = 0; t < F.rows(); ++t) {
    const Eigen::Vector3d n = normal_of(t);
    out.text("facet normal ");
    out.number(n[0]); out.character(' ');
    out.number(n[1]); out.character(' ');
    out.number(n[2]);
    out.text("\n outer loop\n");
    for (int k = 0; k < 3; ++k) {
      out.text("  vertex ");
      out.number(mesh.V(F(t, k), 0)); out.character(' ');
      out.number(mesh.V(F(t, k), 1)); out.character(' ');
      out.number(mesh.V(F(t, k), 2)); out.character('\n');
    }
    out.text(" endloop\nendfacet\n");
  }
  out.text("endsolid meshsmith\n");
  return out.take();
}

}  // namespace meshsmith::io
