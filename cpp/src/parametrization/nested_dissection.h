#pragma once
// Internal to the parametrization chapter: a fill-reducing elimination order for the sparse
// Cholesky factorizations of mesh systems (mesh_cholesky.h), found from the vertex positions.
#include <meshsmith/core/types.h>

#include <vector>

namespace meshsmith::parametrization::detail {

/// The adjacency of a symmetric sparse pattern on n variables in compressed form: the
/// neighbours of variable i are neighbours[starts[i] .. starts[i+1]) (entries equal to i are
/// ignored). starts: n+1 offsets, neighbours: indices in [0, n).
struct AdjacencyView {
  const int* starts = nullptr;
  const int* neighbours = nullptr;
};

/// Geometric nested dissection (George 1973; Miller, Teng, Thurston & Vavasis 1998 for the
/// geometric separators of well-shaped meshes): the variables are split at the median of their
/// positions along the widest axis of their bounding box; the variables of the smaller side
/// that have a neighbour on the other side form the separator, eliminated after both sides,
/// which are ordered the same way recursively down to `leaf_size` variables. On a mesh of a
/// surface patch the separators are cuts of length O(√n), which keeps the Cholesky factor's
/// fill O(n log n) and puts most of the work into a few dense separator blocks (large
/// supernodes, so BLAS runs near its peak). Cost O(n log n), no arithmetic on the values.
///
/// points: n×3 positions (row i: variable i; any values — coincident points still give a valid
/// order, only a worse one). graph: the pattern's adjacency as above. leaf_size ≥ 1.
struct DissectionOrder {
  /// The elimination order: entry k is the variable eliminated k-th (a permutation of 0..n−1).
  std::vector<int> order;
  /// The first split: order[0, first_part) and order[first_part, first_part + second_part) are
  /// the two sides (no edge joins them), the rest of `order` is their separator. Both 0 when
  /// n ≤ leaf_size (no split).
  int first_part = 0;
  int second_part = 0;
};

/// The order described above; deterministic.
DissectionOrder nested_dissection_order(const VertexRef& points, const AdjacencyView& graph, int leaf_size = 8);

}  // namespace meshsmith::parametrization::detail
