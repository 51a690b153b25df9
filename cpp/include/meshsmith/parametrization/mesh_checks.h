#pragma once
/// \file mesh_checks.h
/// The checks every map of the parametrization chapter — and the quadrangulation chapter built
/// on it — runs on its input before it builds a linear system, so that bad input gives a clear
/// InputError instead of a singular matrix, a hang or silent garbage. (Namespace `detail`: a
/// building block for the chapters above, not part of the Python API.)
#include <meshsmith/core/normalization.h>
#include <meshsmith/core/types.h>
#include <meshsmith/topology/edge_incidence.h>

#include <vector>

namespace meshsmith::parametrization::detail {

/// The vertices in normalized coordinates (core/normalization.h) and their frame. Every map of
/// the chapter is scale-invariant (uniform, cotangent and mean-value weights, conformal energy,
/// angles), so each runs on these: inputs of 1e-300 or 1e300 give the answer of 1e0 (zero-area
/// tests, squared lengths and areas would underflow or overflow otherwise); outputs in length
/// units (LSCM's default pins, ABF's and spectral LSCM's area scaling) are mapped back with the
/// frame.
struct NormalizedVertices {
  VertexMatrix V;
  CoordinateFrame frame;
};
/// \throw InputError if V is empty or not finite (validate_vertices, on the input's values).
NormalizedVertices normalized(const VertexRef& V);

/// What the checks learned about a valid mesh, reused by the caller.
struct CheckedMesh {
  topology::EdgeIncidence incidence;
  std::vector<std::vector<int>> boundary_loops;  ///< longest first (topology::boundary_loops)
  long long euler_characteristic = 0;
  bool is_disk() const { return boundary_loops.size() == 1 && euler_characteristic == 1; }
};

/// What the caller needs of the mesh beyond being a clean, connected, oriented 2-manifold.
enum class Requirement {
  any,           ///< closed or not, any genus (cut_to_disk)
  has_boundary,  ///< at least one boundary loop (LSCM with user pins, spectral LSCM)
  disk,          ///< exactly one boundary loop and χ = 1 (the default boundary / pins)
};

/// Checks (V, F) for parametrization: validate_mesh; no face with a repeated vertex or zero area
/// (exactly: its corners are collinear); every vertex used by a face; manifold and oriented; one
/// connected component; then `requirement`. `function` prefixes the messages.
/// \throw InputError naming the first offending face, vertex or edge, or the topology found
///        (and that cut_to_disk makes a disk of a closed or higher-genus mesh).
CheckedMesh check_mesh(const VertexRef& V, const FaceRef& F, Requirement requirement,
                       const char* function);

/// Checks a list of distinct vertex indices in [0, n) (`what`: "boundary", "pinned") and their
/// #b×2 finite positions.
/// \throw InputError naming the offending entry.
void check_constrained_vertices(const std::vector<int>& indices, const Eigen::Ref<const Eigen::MatrixX2d>& uv,
                                Eigen::Index n, const char* what, const char* function);

}  // namespace meshsmith::parametrization::detail
