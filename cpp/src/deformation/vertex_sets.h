#pragma once
// Internal to the deformation chapter: the checks of the vertex sets (handles, fixed vertices,
// constraints) that every solver of the chapter takes, and the connectivity test that turns a
// singular system into a clear InputError before CHOLMOD sees it.
#include <meshsmith/core/types.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace meshsmith::deformation::detail {

/// \throw InputError "<function>: <what> lists vertex v twice" / "... vertex v, outside [0, n)"
///        / "<what> is empty" (when !allow_empty).
void check_vertex_set(const std::vector<int>& indices, Eigen::Index n, const char* what, const char* function,
                      bool allow_empty = false);

/// \throw InputError naming the first vertex of `second` that is also in `first`.
void check_disjoint(const std::vector<int>& first, const std::vector<int>& second, Eigen::Index n,
                    const char* first_name, const char* second_name, const char* function);

/// \throw InputError "<function>: <name> has r rows, expected n" or as validate_vertices (NaN/Inf).
void check_positions(const VertexRef& X, Eigen::Index rows, const char* name, const char* function);

/// \throw InputError if T (row-major 16 numbers) holds NaN/Inf or its last row is not (0, 0, 0, 1).
void check_affine(const Eigen::Matrix4d& T, const char* function);

/// Every connected component of the graph of the symmetric matrix L (its non-zero off-diagonal
/// entries) among the vertices with used[v] must hold a vertex with constrained[v]; otherwise
/// the system restricted to the unconstrained vertices is singular.
/// \throw InputError naming a vertex of the first component without one and its size.
void check_every_component_constrained(const Eigen::SparseMatrix<double>& L, const std::vector<char>& used,
                                       const std::vector<char>& constrained, const char* system,
                                       const char* function);

}  // namespace meshsmith::deformation::detail
