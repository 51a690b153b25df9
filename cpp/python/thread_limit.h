#pragma once
// A per-call `threads=` option of the bindings (DESIGN.md, "Threads"): TBB capped for one call.
#include "convert.h"

#include <oneapi/tbb/global_control.h>

#include <cstddef>
#include <memory>

namespace meshsmith::python {

/// run() without the GIL, with TBB capped at `threads` (None: no cap beyond the process-wide one of
/// meshsmith.core.set_num_threads; TBB obeys the smallest active cap). \throw InputError unless
/// threads is None or an integer in [1, 4096].
template <typename Run>
auto with_threads(const py::object& threads, Run&& run) {
  const int thread_count = threads.is_none() ? 0 : integer_argument<int>(threads, "threads", 1, 4096);
  return without_gil([&] {
    std::unique_ptr<tbb::global_control> limit;
    if (thread_count > 0)
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                    static_cast<std::size_t>(thread_count));
    return run();
  });
}

}  // namespace meshsmith::python
