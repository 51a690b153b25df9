#pragma once
// Undirected edge → incident triangles, for the chapter's own 2D code (flips, Voronoi edges).
#include <meshsmith/core/errors.h>

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>

namespace meshsmith::tessellation::detail {

inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

/// The (at most two) triangles of each undirected edge; -1 marks a missing side.
using EdgeFaces = std::unordered_map<std::uint64_t, std::array<int, 2>>;

/// Edge → triangles of F (any (m, 3) int matrix of CCW triangles).
/// \throw InputError if an edge has more than two triangles, or two triangles run through it in
///        the same direction (overlapping or inconsistently oriented triangles).
template <typename Faces>
EdgeFaces build_edge_faces(const Faces& F) {
  EdgeFaces edges;
  edges.reserve(static_cast<std::size_t>(F.rows()) * 2);
  for (int f = 0; f < static_cast<int>(F.rows()); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, c), b = F(f, (c + 1) % 3);
      auto [entry, inserted] = edges.try_emplace(edge_key(a, b), std::array<int, 2>{f, -1});
      if (inserted) continue;
      auto& sides = entry->second;
      if (sides[1] >= 0)
        throw InputError("F: edge (" + std::to_string(a) + ", " + std::to_string(b) +
                         ") belongs to more than two triangles");
      const int g = sides[0];
      for (int k = 0; k < 3; ++k)
        if (F(g, k) == a && F(g, (k + 1) % 3) == b)
          throw InputError("F: triangles " + std::to_string(g) + " and " + std::to_string(f) +
                           " overlap (both run through edge (" + std::to_string(a) + ", " +
                           std::to_string(b) + ") in the same direction)");
      sides[1] = f;
    }
  return edges;
}

}  // namespace meshsmith::tessellation::detail
