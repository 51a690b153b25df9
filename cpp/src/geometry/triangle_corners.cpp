#include "triangle_corners.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace meshsmith::geometry::detail {

void validate_surface(const VertexRef& V, const FaceRef& F) {
  validate_mesh(V, F);
  const double entries = 6.0 * static_cast<double>(F.rows()) + static_cast<double>(V.rows());
  if (entries >= static_cast<double>(std::numeric_limits<int>::max())) {
    throw InputError("mesh too large: " + std::to_string(F.rows()) +
                     " faces exceed the 32-bit sparse matrix indices");
  }
}

VertexCorners vertex_corners(const FaceRef& F, Eigen::Index n) {
  VertexCorners result;
  result.offsets.assign(n + 1, 0);
  const Eigen::Index m = F.rows();
  const int* faces = F.data();  // row-major: corner k of the flat array is 3·f + c
  for (Eigen::Index k = 0; k < 3 * m; ++k) ++result.offsets[faces[k] + 1];
  for (Eigen::Index v = 0; v < n; ++v) result.offsets[v + 1] += result.offsets[v];
  result.corners.resize(3 * m);
  std::vector<std::int64_t> cursor(result.offsets.begin(), result.offsets.end() - 1);
  for (Eigen::Index k = 0; k < 3 * m; ++k) result.corners[cursor[faces[k]]++] = static_cast<int>(k);
  return result;
}

Triangle triangle(const VertexRef& V, const FaceRef& F, Eigen::Index f) {
  Triangle t;
  for (int c = 0; c < 3; ++c) t.p[c] = V.row(F(f, c)).transpose();
  t.cross = (t.p[1] - t.p[0]).cross(t.p[2] - t.p[0]);
  t.double_area = t.cross.norm();
  double longest = 0.0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::Vector3d& here = t.p[c];
    const Eigen::Vector3d& next = t.p[(c + 1) % 3];
    const Eigen::Vector3d& prev = t.p[(c + 2) % 3];
    t.dot[c] = (next - here).dot(prev - here);
    t.squared_edge[c] = (prev - next).squaredNorm();
    longest = std::max(longest, t.squared_edge[c]);
  }
  t.degenerate = !(t.double_area > 8.0 * std::numeric_limits<double>::epsilon() * longest);
  return t;
}

CornerMatrix half_cotangents(const VertexRef& V, const FaceRef& F) {
  CornerMatrix C(F.rows(), 3);
  parallel_for(F.rows(), [&](Eigen::Index f) {
    const Triangle t = triangle(V, F, f);
    for (int c = 0; c < 3; ++c) C(f, c) = t.degenerate ? 0.0 : 0.5 * t.dot[c] / t.double_area;
  });
  return C;
}

CornerMatrix corner_angles(const VertexRef& V, const FaceRef& F) {
  CornerMatrix A(F.rows(), 3);
  parallel_for(F.rows(), [&](Eigen::Index f) {
    const Triangle t = triangle(V, F, f);
    for (int c = 0; c < 3; ++c) A(f, c) = corner_angle(t, c);
  });
  return A;
}

CornerMatrix corner_areas(const VertexRef& V, const FaceRef& F, CornerAreaRule rule) {
  CornerMatrix A(F.rows(), 3);
  parallel_for(F.rows(), [&](Eigen::Index f) {
    const Triangle t = triangle(V, F, f);
    const double area = 0.5 * t.double_area;
    if (rule == CornerAreaRule::barycentric) {
      A.row(f).setConstant(area / 3.0);
      return;
    }
    if (t.degenerate) {  // no circumcentre; the area is (numerically) zero anyway
      A.row(f).setConstant(area / 3.0);
      return;
    }
    int obtuse = -1;
    for (int c = 0; c < 3; ++c) {
      if (t.dot[c] < 0.0) obtuse = c;
    }
    if (obtuse >= 0) {
      for (int c = 0; c < 3; ++c) A(f, c) = c == obtuse ? 0.5 * area : 0.25 * area;
      return;
    }
    // Voronoi cell of corner c inside the triangle: (|e_next|² cot θ_next + |e_prev|² cot θ_prev) / 8,
    // e_k the edge opposite corner k, cot θ_k = dot_k / (2·area).
    for (int c = 0; c < 3; ++c) {
      const int next = (c + 1) % 3, prev = (c + 2) % 3;
      A(f, c) = (t.squared_edge[next] * t.dot[next] + t.squared_edge[prev] * t.dot[prev]) /
                (8.0 * t.double_area);
    }
  });
  return A;
}

Eigen::VectorXd sum_at_vertices(const VertexCorners& corners, const CornerMatrix& values) {
  const Eigen::Index n = static_cast<Eigen::Index>(corners.offsets.size()) - 1;
  Eigen::VectorXd sums(n);
  const double* flat = values.data();
  parallel_for(n, [&](Eigen::Index v) {
    double sum = 0.0;
    for (auto k = corners.begin(v); k < corners.end(v); ++k) sum += flat[corners.corners[k]];
    sums[v] = sum;
  });
  return sums;
}

namespace {

using Entry = std::pair<int, double>;  // (row, value)

// Sorts a column's entries by row, keeping the gather order among equal rows (so sums are
// deterministic), and merges equal rows. Returns the merged count.
std::size_t sort_and_merge(std::vector<Entry>& entries, bool unit_weights) {
  if (entries.size() <= 32) {
    for (std::size_t i = 1; i < entries.size(); ++i) {
      Entry item = entries[i];
      std::size_t j = i;
      for (; j > 0 && entries[j - 1].first > item.first; --j) entries[j] = entries[j - 1];
      entries[j] = item;
    }
  } else {
    std::stable_sort(entries.begin(), entries.end(),
                     [](const Entry& a, const Entry& b) { return a.first < b.first; });
  }
  std::size_t out = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (out > 0 && entries[out - 1].first == entries[i].first) {
      if (!unit_weights) entries[out - 1].second += entries[i].second;
    } else {
      entries[out++] = entries[i];
    }
  }
  return out;
}

}  // namespace

Eigen::SparseMatrix<double> assemble_laplacian(const FaceRef& F, const VertexCorners& corners,
                                               const DirectedWeights* weights) {
  const Eigen::Index n = static_cast<Eigen::Index>(corners.offsets.size()) - 1;
  // Column j has at most 2 entries per corner around j plus its diagonal: scratch slot
  // [2·offsets[j] + j, 2·offsets[j+1] + j + 1). Columns are built independently, then compacted.
  const std::size_t capacity = 2 * corners.corners.size() + static_cast<std::size_t>(n);
  std::vector<int> scratch_rows(capacity);
  std::vector<double> scratch_values(capacity);
  std::vector<int> counts(n);
  const bool unit = weights == nullptr;
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, n, 1024),
                    [&](const tbb::blocked_range<Eigen::Index>& range) {
    std::vector<Entry> entries;
    for (Eigen::Index j = range.begin(); j != range.end(); ++j) {
      entries.clear();
      double diagonal = 0.0;
      for (auto k = corners.begin(j); k < corners.end(j); ++k) {
        const int corner = corners.corners[k];
        const int f = corner / 3, c = corner % 3;
        const int next = (c + 1) % 3, prev = (c + 2) % 3;
        const int a = F(f, next), b = F(f, prev);
        // A face with a repeated index (a == j or b == j) has no edge there; its weights are 0.
        if (unit) {
          if (a != j) entries.emplace_back(a, 1.0);
          if (b != j) entries.emplace_back(b, 1.0);
        } else {
          const auto w = weights->row(f);
          if (a != j) entries.emplace_back(a, w(2 * next + 1));  // next vertex towards j (its previous)
          if (b != j) entries.emplace_back(b, w(2 * prev));      // previous vertex towards j (its next)
          diagonal -= w(2 * c) + w(2 * c + 1);                   // j towards both
        }
      }
      std::size_t count = sort_and_merge(entries, unit);
      if (unit) diagonal = -static_cast<double>(count);
      // Insert the diagonal at its sorted place (a face never lists j as its own neighbour).
      const std::int64_t base = 2 * corners.begin(j) + j;
      std::size_t out = 0;
      bool placed = false;
      for (std::size_t i = 0; i < count; ++i) {
        if (!placed && entries[i].first > j) {
          scratch_rows[base + out] = static_cast<int>(j);
          scratch_values[base + out++] = diagonal;
          placed = true;
        }
        scratch_rows[base + out] = entries[i].first;
        scratch_values[base + out++] = entries[i].second;
      }
      if (!placed) {
        scratch_rows[base + out] = static_cast<int>(j);
        scratch_values[base + out++] = diagonal;
      }
      counts[j] = static_cast<int>(out);
    }
  });
  Eigen::SparseMatrix<double> L(n, n);
  int* outer = L.outerIndexPtr();
  outer[0] = 0;
  for (Eigen::Index j = 0; j < n; ++j) outer[j + 1] = outer[j] + counts[j];
  L.resizeNonZeros(outer[n]);
  int* inner = L.innerIndexPtr();
  double* values = L.valuePtr();
  parallel_for(n, [&](Eigen::Index j) {
    const std::int64_t base = 2 * corners.begin(j) + j;
    std::copy_n(scratch_rows.begin() + base, counts[j], inner + outer[j]);
    std::copy_n(scratch_values.begin() + base, counts[j], values + outer[j]);
  }, 1024);
  return L;
}

}  // namespace meshsmith::geometry::detail
