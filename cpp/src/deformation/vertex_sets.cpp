#include "vertex_sets.h"

#include <meshsmith/core/errors.h>
#include <meshsmith/core/validation.h>

#include <cmath>
#include <string>

namespace meshsmith::deformation::detail {

void check_vertex_set(const std::vector<int>& indices, Eigen::Index n, const char* what, const char* function,
                      bool allow_empty) {
  const std::string prefix = std::string(function) + ": ";
  if (indices.empty() && !allow_empty) throw InputError(prefix + what + " is empty: give at least one vertex");
  std::vector<char> seen(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const int v = indices[k];
    if (v < 0 || v >= n) {
      throw InputError(prefix + what + "[" + std::to_string(k) + "] = " + std::to_string(v) + " is outside [0, " +
                       std::to_string(n) + ")");
    }
    if (seen[v]) throw InputError(prefix + what + " lists vertex " + std::to_string(v) + " twice");
    seen[v] = 1;
  }
}

void check_disjoint(const std::vector<int>& first, const std::vector<int>& second, Eigen::Index n,
                    const char* first_name, const char* second_name, const char* function) {
  std::vector<char> in_first(static_cast<std::size_t>(n), 0);
  for (int v : first) in_first[v] = 1;
  for (int v : second) {
    if (in_first[v]) {
      throw InputError(std::string(function) + ": vertex " + std::to_string(v) + " is both in " + first_name +
                       " and in " + second_name + "; a vertex can only be one of them");
    }
  }
}

void check_positions(const VertexRef& X, Eigen::Index rows, const char* name, const char* function) {
  if (X.rows() != rows) {
    throw InputError(std::string(function) + ": " + name + " has " + std::to_string(X.rows()) + " rows, expected " +
                     std::to_string(rows));
  }
  validate_vertices(X, name);
}

void check_affine(const Eigen::Matrix4d& T, const char* function) {
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(T(r, c))) {
        throw InputError(std::string(function) + ": T[" + std::to_string(r) + ", " + std::to_string(c) + "] is " +
                         number_text(T(r, c)) + "; the transform must be finite");
      }
    }
  }
  if (T(3, 0) != 0.0 || T(3, 1) != 0.0 || T(3, 2) != 0.0 || T(3, 3) != 1.0) {
    throw InputError(std::string(function) + ": T's last row is (" + number_text(T(3, 0)) + ", " +
                     number_text(T(3, 1)) + ", " + number_text(T(3, 2)) + ", " + number_text(T(3, 3)) +
                     "), not (0, 0, 0, 1): the transform must be affine");
  }
}

void check_every_component_constrained(const Eigen::SparseMatrix<double>& L, const std::vector<char>& used,
                                       const std::vector<char>& constrained, const char* system,
                                       const char* function) {
  const Eigen::Index n = L.cols();
  std::vector<char> reached(static_cast<std::size_t>(n), 0);
  std::vector<int> stack;
  // Marks the component of `seed` (through non-zero weights, among used vertices); returns its size.
  const auto flood = [&](Eigen::Index seed) {
    long long size = 0;
    reached[seed] = 1;
    stack.assign(1, static_cast<int>(seed));
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      ++size;
      for (Eigen::SparseMatrix<double>::InnerIterator it(L, v); it; ++it) {
        const Eigen::Index u = it.row();
        if (u == v || it.value() == 0.0 || reached[u] || !used[u]) continue;
        reached[u] = 1;
        stack.push_back(static_cast<int>(u));
      }
    }
    return size;
  };
  for (Eigen::Index s = 0; s < n; ++s)
    if (constrained[s] && used[s] && !reached[s]) flood(s);
  for (Eigen::Index s = 0; s < n; ++s) {
    if (!used[s] || reached[s]) continue;
    const long long size = flood(s);
    throw InputError(std::string(function) + ": vertex " + std::to_string(s) + " is in a connected part of " +
                     std::to_string(size) + " vertices with no held (handle, fixed or boundary) vertex: the " + system +
                     " is singular there (hold a vertex of that part, or remove it)");
  }
}

}  // namespace meshsmith::deformation::detail
