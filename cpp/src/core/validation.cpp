#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace meshsmith {

void validate_vertices(const VertexRef& V, const char* name) {
  if (V.rows() == 0) throw InputError(std::string(name) + " is empty: expected at least one vertex");
  const double* data = V.data();
  const Eigen::Index count = V.size();
  for (Eigen::Index k = 0; k < count; ++k) {
    if (!std::isfinite(data[k])) {
      std::ostringstream message;
      message << name << "[" << k / 3 << ", " << k % 3 << "] is " << data[k]
              << ": vertex coordinates must be finite";
      throw InputError(message.str());
    }
  }
}

void validate_mesh(const VertexRef& V, const FaceRef& F, bool allow_empty_faces) {
  validate_vertices(V, "V");
  if (F.rows() == 0 && !allow_empty_faces) throw InputError("F is empty: expected at least one triangle");
  const int n = static_cast<int>(V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int index = F(f, c);
      if (index < 0 || index >= n) {
        std::ostringstream message;
        message << "F[" << f << "] = (" << F(f, 0) << ", " << F(f, 1) << ", " << F(f, 2)
                << ") indexes vertex " << index << ", outside [0, " << n << ")";
        throw InputError(message.str());
      }
    }
  }
}

std::string MeshDefects::summary() const {
  std::ostringstream out;
  auto line = [&](const std::vector<int>& items, const char* what) {
    if (!items.empty()) out << items.size() << " " << what << " (first: " << items.front() << ")\n";
  };
  line(degenerate_faces, "degenerate faces with a repeated vertex");
  line(zero_area_faces, "zero-area faces");
  line(duplicate_faces, "duplicate faces");
  line(unreferenced_vertices, "unreferenced vertices");
  return out.str();
}

MeshDefects find_mesh_defects(const VertexRef& V, const FaceRef& F, double area_tolerance) {
  MeshDefects defects;
  const Eigen::Index m = F.rows();
  std::vector<char> referenced(V.rows(), 0);
  std::vector<std::pair<std::array<int, 3>, int>> sorted_faces;
  sorted_faces.reserve(m);
  for (Eigen::Index f = 0; f < m; ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    referenced[a] = referenced[b] = referenced[c] = 1;
    if (a == b || b == c || a == c) {
      defects.degenerate_faces.push_back(static_cast<int>(f));
      continue;
    }
    const Eigen::Vector3d e1 = V.row(b) - V.row(a), e2 = V.row(c) - V.row(a);
    if (0.5 * e1.cross(e2).norm() <= area_tolerance) defects.zero_area_faces.push_back(static_cast<int>(f));
    std::array<int, 3> key{a, b, c};
    std::sort(key.begin(), key.end());
    sorted_faces.push_back({key, static_cast<int>(f)});
  }
  std::sort(sorted_faces.begin(), sorted_faces.end());
  for (size_t k = 1; k < sorted_faces.size(); ++k) {
    if (sorted_faces[k].first == sorted_faces[k - 1].first) defects.duplicate_faces.push_back(sorted_faces[k].second);
  }
  std::sort(defects.duplicate_faces.begin(), defects.duplicate_faces.end());
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!referenced[v]) defects.unreferenced_vertices.push_back(static_cast<int>(v));
  }
  return defects;
}

}  // namespace meshsmith
