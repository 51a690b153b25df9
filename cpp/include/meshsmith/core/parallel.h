#pragma once
/// \file parallel.h
/// Parallel loops that report progress (DESIGN.md, "Long work" and "Speed"): the work runs in
/// blocks of 65,536 items, each block in parallel with TBB, and Progress is reported between
/// blocks from the calling thread (never from inside a parallel region). Results do not depend
/// on the thread count as long as the body writes only to item-owned slots.
#include <meshsmith/core/progress.h>

#include <Eigen/Core>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>

namespace meshsmith {

/// range_body(begin, end) over sub-ranges of [0, n), in parallel; `grain` is TBB's grain size.
/// \throw Cancelled (through `progress`) between blocks; whatever range_body throws.
template <typename RangeBody>
void parallel_ranges_with_progress(Eigen::Index n, const Progress& progress, const char* stage,
                                   const RangeBody& range_body, Eigen::Index grain = 256) {
  constexpr Eigen::Index block = Eigen::Index(1) << 16;
  for (Eigen::Index begin = 0; begin < n; begin += block) {
    progress.report(static_cast<double>(begin) / static_cast<double>(n), stage);
    const Eigen::Index end = std::min(n, begin + block);
    tbb::parallel_for(tbb::blocked_range<Eigen::Index>(begin, end, grain),
                      [&](const tbb::blocked_range<Eigen::Index>& range) { range_body(range.begin(), range.end()); });
  }
  progress.report(1.0, stage);
}

/// body(i) for every i in [0, n), in parallel, as parallel_ranges_with_progress.
template <typename Body>
void parallel_for_with_progress(Eigen::Index n, const Progress& progress, const char* stage, const Body& body,
                                Eigen::Index grain = 256) {
  parallel_ranges_with_progress(n, progress, stage, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) body(i);
  }, grain);
}

}  // namespace meshsmith
