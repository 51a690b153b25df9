// Needles and caps (degenerate_triangles.h) on the OpenMesh TriMesh: passes over the faces,
// classifying each by its edge lengths and angles, collapsing or flipping where admissible.
#include <meshsmith/core/errors.h>
#include <meshsmith/core/mesh.h>
#include <meshsmith/repair/degenerate_triangles.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace meshsmith::repair {
namespace {

using Vec = Eigen::Vector3d;
using VH = TriMesh::VertexHandle;
using HH = TriMesh::HalfedgeHandle;

Vec position(const TriMesh& mesh, VH v) { return Eigen::Map<const Vec>(mesh.point(v).data()); }

Vec face_normal(const TriMesh& mesh, VH a, VH b, VH c) {
  return (position(mesh, b) - position(mesh, a)).cross(position(mesh, c) - position(mesh, a));
}

/// Largest corner angle of triangle (a, b, c), in radians.
double largest_angle(const Vec& a, const Vec& b, const Vec& c) {
  auto angle = [](const Vec& apex, const Vec& p, const Vec& q) {
    const Vec u = p - apex, w = q - apex;
    return std::atan2(u.cross(w).norm(), u.dot(w));
  };
  return std::max({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

/// Whether collapsing h (from → to, to keeps its position) keeps every face around `from` that
/// survives within 90° of its normal.
bool collapse_keeps_normals(const TriMesh& mesh, HH h) {
  const VH from = mesh.from_vertex_handle(h), to = mesh.to_vertex_handle(h);
  for (auto f : mesh.vf_range(from)) {
    VH corner[3];
    int k = 0;
    bool has_to = false;
    for (auto v : mesh.fv_range(f)) {
      has_to = has_to || v == to;
      corner[k++] = v;
    }
    if (has_to) continue;   // removed by the collapse
    const Vec before = face_normal(mesh, corner[0], corner[1], corner[2]);
    for (auto& v : corner)
      if (v == from) v = to;
    const Vec after = face_normal(mesh, corner[0], corner[1], corner[2]);
    if (!(before.dot(after) > 0.0)) return false;
  }
  return true;
}

bool try_collapse(TriMesh& mesh, HH shortest) {
  for (const HH h : {shortest, mesh.opposite_halfedge_handle(shortest)}) {
    const VH from = mesh.from_vertex_handle(h);
    // A boundary vertex stays on the boundary: it may only move along a boundary edge.
    if (mesh.is_boundary(from) && !mesh.is_boundary(mesh.edge_handle(h))) continue;
    if (!mesh.is_collapse_ok(h) || !collapse_keeps_normals(mesh, h)) continue;
    mesh.collapse(h);
    return true;
  }
  return false;
}

bool try_flip(TriMesh& mesh, HH opposite_big_angle) {
  const auto e = mesh.edge_handle(opposite_big_angle);
  if (mesh.is_boundary(e) || !mesh.is_flip_ok(e)) return false;
  const HH h = opposite_big_angle, g = mesh.opposite_halfedge_handle(h);
  const VH a = mesh.from_vertex_handle(h), b = mesh.to_vertex_handle(h);
  const VH c = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
  const VH d = mesh.to_vertex_handle(mesh.next_halfedge_handle(g));
  const Vec pa = position(mesh, a), pb = position(mesh, b), pc = position(mesh, c), pd = position(mesh, d);
  const Vec old_side = face_normal(mesh, a, b, c) + face_normal(mesh, b, a, d);
  // After the flip: faces (c, a, d) and (d, b, c).
  const Vec n1 = (pa - pc).cross(pd - pc), n2 = (pb - pd).cross(pc - pd);
  if (!(n1.dot(old_side) > 0.0 && n2.dot(old_side) > 0.0)) return false;
  const double before = std::max(largest_angle(pa, pb, pc), largest_angle(pb, pa, pd));
  const double after = std::max(largest_angle(pc, pa, pd), largest_angle(pd, pb, pc));
  if (!(after < before)) return false;
  mesh.flip(e);
  return true;
}

enum class Shape { fine, needle, cap };

/// The face's shape, with its shortest halfedge (for a needle) or the halfedge opposite its
/// largest angle (for a cap).
Shape classify(const TriMesh& mesh, TriMesh::FaceHandle f, const NeedleCapOptions& options, HH& which) {
  HH sides[3];
  double length[3];
  int k = 0;
  for (auto h : mesh.fh_range(f)) {
    sides[k] = h;
    length[k] = (position(mesh, mesh.to_vertex_handle(h)) - position(mesh, mesh.from_vertex_handle(h))).norm();
    ++k;
  }
  const int shortest = static_cast<int>(std::min_element(length, length + 3) - length);
  const int longest = static_cast<int>(std::max_element(length, length + 3) - length);
  if (!(length[shortest] * options.needle_ratio >= length[longest])) {
    which = sides[shortest];
    return Shape::needle;
  }
  // The largest angle is opposite the longest side.
  const VH apex = mesh.to_vertex_handle(mesh.next_halfedge_handle(sides[longest]));
  const Vec p = position(mesh, apex);
  const Vec u = position(mesh, mesh.from_vertex_handle(sides[longest])) - p;
  const Vec w = position(mesh, mesh.to_vertex_handle(sides[longest])) - p;
  if (std::atan2(u.cross(w).norm(), u.dot(w)) * 180.0 / M_PI > options.cap_angle) {
    which = sides[longest];
    return Shape::cap;
  }
  return Shape::fine;
}

}  // namespace

NeedleCapResult remove_needles_and_caps(const VertexRef& V, const FaceRef& F, const NeedleCapOptions& options) {
  if (!(options.needle_ratio > 1.0) || !std::isfinite(options.needle_ratio))
    throw InputError("needle_ratio must be a finite number > 1");
  if (!(options.cap_angle > 90.0 && options.cap_angle < 180.0))
    throw InputError("cap_angle must be in (90, 180) degrees");
  if (options.max_passes < 0) throw InputError("max_passes must be >= 0");
  TriMesh mesh = to_trimesh(V, F);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  auto origin = OpenMesh::FPropHandleT<int>();
  mesh.add_property(origin);
  for (auto f : mesh.faces()) mesh.property(origin, f) = f.idx();

  NeedleCapResult result;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    bool changed = false;
    result.remaining_needles = result.remaining_caps = 0;
    for (auto f : mesh.faces()) {
      if (mesh.status(f).deleted()) continue;
      HH which;
      const Shape shape = classify(mesh, f, options, which);
      if (shape == Shape::needle) {
        if (try_collapse(mesh, which)) { ++result.collapses; changed = true; }
        else ++result.remaining_needles;
      } else if (shape == Shape::cap) {
        if (try_flip(mesh, which)) { ++result.flips; changed = true; }
        else ++result.remaining_caps;
      }
    }
    if (!changed) break;
  }
  if (options.max_passes == 0 || result.collapses || result.flips) {
    // Count what is left on the final mesh.
    result.remaining_needles = result.remaining_caps = 0;
    for (auto f : mesh.faces()) {
      HH which;
      const Shape shape = classify(mesh, f, options, which);
      result.remaining_needles += shape == Shape::needle;
      result.remaining_caps += shape == Shape::cap;
    }
  }

  std::vector<int> new_index(mesh.n_vertices(), -1);
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    new_index[v.idx()] = static_cast<int>(result.vertex_map.size());
    result.vertex_map.push_back(v.idx());
  }
  result.V.resize(static_cast<Eigen::Index>(result.vertex_map.size()), 3);
  for (std::size_t k = 0; k < result.vertex_map.size(); ++k) result.V.row(static_cast<Eigen::Index>(k)) = V.row(result.vertex_map[k]);
  std::vector<std::array<int, 3>> faces;
  for (auto f : mesh.faces()) {
    std::array<int, 3> face{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) face[k++] = new_index[v.idx()];
    faces.push_back(face);
    result.face_map.push_back(mesh.property(origin, f));
  }
  result.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t k = 0; k < faces.size(); ++k)
    result.F.row(static_cast<Eigen::Index>(k)) << faces[k][0], faces[k][1], faces[k][2];
  return result;
}

}  // namespace meshsmith::repair
