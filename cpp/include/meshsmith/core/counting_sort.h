#pragma once
/// \file counting_sort.h
/// Stable counting sort of item ids by a small integer key, in parallel by fixed chunks: the
/// building block of the mesh builders' "bucket the half-edges by their smaller vertex" and
/// "order the faces by their first vertex" steps.
#include <meshsmith/core/large_vector.h>

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstddef>

namespace meshsmith {

/// The items of each key, contiguous: items[start[k] .. start[k+1]) are the ids with key k, in
/// increasing order.
struct KeyBuckets {
  LargeVector<int> start;  ///< keys + 1 offsets into items
  LargeVector<int> items;  ///< the ids with a key, sorted by (key, id)
};

/// Sorts the ids 0..n−1 by key_of(id) ∈ [0, keys), or −1 to leave the id out. key_of is called
/// twice per id, from several threads at once. The ids are cut into one chunk per thread (each
/// of 2¹⁶ ids or more), counted and placed in parallel; being stable, the result is the same
/// for any number of chunks. O(n + keys·chunks) time; keys·chunks ints of scratch memory.
template <typename KeyOf>
KeyBuckets bucket_by_key(int n, int keys, const KeyOf& key_of) {
  constexpr int kMinChunk = 1 << 16;
  const int chunks = std::max(1, std::min(tbb::this_task_arena::max_concurrency(), n / kMinChunk));
  const int chunk_size = (n + chunks - 1) / chunks;
  // offset[c·keys + k]: first the count of key k in chunk c, then where chunk c writes its next k.
  LargeVector<int> offset(static_cast<std::size_t>(chunks) * keys, 0);
  tbb::parallel_for(0, chunks, [&](int c) {
    int* count = offset.data() + static_cast<std::size_t>(c) * keys;
    for (int i = c * chunk_size, end = std::min(n, (c + 1) * chunk_size); i < end; ++i) {
      const int k = key_of(i);
      if (k >= 0) ++count[k];
    }
  });
  KeyBuckets result;
  result.start.resize(static_cast<std::size_t>(keys) + 1);
  int running = 0;
  for (int k = 0; k < keys; ++k) {
    result.start[k] = running;
    for (int c = 0; c < chunks; ++c) {
      int& slot = offset[static_cast<std::size_t>(c) * keys + k];
      const int count = slot;
      slot = running;
      running += count;
    }
  }
  result.start[keys] = running;
  result.items.resize(static_cast<std::size_t>(running));
  tbb::parallel_for(0, chunks, [&](int c) {
    int* next = offset.data() + static_cast<std::size_t>(c) * keys;
    for (int i = c * chunk_size, end = std::min(n, (c + 1) * chunk_size); i < end; ++i) {
      const int k = key_of(i);
      if (k >= 0) result.items[next[k]++] = i;
    }
  });
  return result;
}

}  // namespace meshsmith
