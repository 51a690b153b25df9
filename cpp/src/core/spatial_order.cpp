#include <meshsmith/core/spatial_order.h>

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace meshsmith {
namespace {

/// Spreads the low 21 bits of x so that bit i lands on bit 3i.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

LargeVector<int> morton_order(const VertexRef& P) {
  const Eigen::Index n = P.rows();
  Eigen::RowVector3d low = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::RowVector3d high = -low;
  for (Eigen::Index i = 0; i < n; ++i)
    if (P.row(i).allFinite()) {
      low = low.cwiseMin(P.row(i));
      high = high.cwiseMax(P.row(i));
    }
  const double extent = (high - low).maxCoeff();
  const double scale = (extent > 0 && std::isfinite(extent)) ? ((1 << 21) - 1) / extent : 0.0;

  // (code, index) pairs: the index in the low bits breaks ties by input order.
  struct Keyed { std::uint64_t code; int index; };
  LargeVector<Keyed> keyed(static_cast<std::size_t>(n));
  tbb::parallel_for(Eigen::Index(0), n, [&](Eigen::Index i) {
    std::uint64_t code = 0;
    if (scale > 0 && P.row(i).allFinite())
      for (int k = 0; k < 3; ++k) {
        const auto cell = static_cast<std::uint64_t>((P(i, k) - low[k]) * scale);
        code |= spread_bits(cell) << k;
      }
    keyed[i] = {code, static_cast<int>(i)};
  });
  tbb::parallel_sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    return a.code != b.code ? a.code < b.code : a.index < b.index;
  });
  LargeVector<int> order(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) order[i] = keyed[i].index;
  return order;
}

}  // namespace meshsmith
