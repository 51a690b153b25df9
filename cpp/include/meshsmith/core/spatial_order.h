#pragma once
/// \file spatial_order.h
/// Orders points along a space-filling curve so that points close in space get close indices:
/// algorithms that walk a mesh locally (decimation, traversals) then touch memory that is
/// already in cache.
#include <meshsmith/core/large_vector.h>
#include <meshsmith/core/types.h>

namespace meshsmith {

/// The permutation that sorts the rows of P (n×3) by the Morton (Z-order) code of their cell in
/// a 2²¹-per-axis grid over the bounding box; order[k] is the row that goes to position k. Ties
/// (same cell) keep their input order, so the result is deterministic. Codes are computed in
/// parallel. Non-finite rows are placed as if at the box's minimum corner.
/// O(n log n) time, 16 bytes per point of scratch memory.
LargeVector<int> morton_order(const VertexRef& P);

}  // namespace meshsmith
