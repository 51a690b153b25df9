#pragma once
// Internal to the points chapter: a parallel loop over [0, n) in blocks, reporting progress
// between blocks from the calling thread (Progress must not be called from a parallel region).
#include <meshsmith/core/progress.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Core>

#include <algorithm>

namespace meshsmith::points::detail {

template <typename Body>
void parallel_for_in_blocks(Eigen::Index n, const Progress& progress, const char* stage,
                            const Body& body) {
  constexpr Eigen::Index block = Eigen::Index(1) << 16;
  for (Eigen::Index begin = 0; begin < n; begin += block) {
    progress.report(static_cast<double>(begin) / static_cast<double>(n), stage);
    const Eigen::Index end = std::min(n, begin + block);
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(begin, end, 512),
                      [&](const tbb::blocked_range<Eigen::Index>& range) {
                        for (Eigen::Index i = range.begin(); i != range.end(); ++i) body(i);
                      });
  }
  progress.report(1.0, stage);
}

}  // namespace meshsmith::points::detail
