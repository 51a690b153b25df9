#pragma once
/// \file progress.h
/// Progress reporting and cancellation for long-running algorithms (DESIGN.md, "Long work").
#include <chrono>
#include <functional>
#include <string>

namespace meshsmith {

/// Receives (fraction in [0, 1], stage name); returns false to cancel.
using ProgressCallback = std::function<bool(double fraction, const std::string& stage)>;

/// Passed by const reference into long algorithms, which call report() from their main loop
/// (never from inside a parallel region). Calls to the callback are throttled to one every
/// `min_interval`, except the first and the final (fraction 1) one, so report() is cheap enough
/// to call once per element. An empty Progress does nothing.
/// \throw Cancelled when the callback returns false; whatever the callback throws (e.g. the
///        Python binding's KeyboardInterrupt on Ctrl-C) propagates unchanged.
class Progress {
 public:
  Progress() = default;
  explicit Progress(ProgressCallback callback,
                    std::chrono::milliseconds min_interval = std::chrono::milliseconds(50));

  /// Report that `fraction` of the work of `stage` is done.
  void report(double fraction, const char* stage) const;

  /// A Progress for a sub-range [begin, end] of the overall fraction, so a stage that calls
  /// another long algorithm maps its child's [0, 1] onto its own share.
  Progress subrange(double begin, double end) const;

  explicit operator bool() const { return static_cast<bool>(callback_); }

 private:
  ProgressCallback callback_;
  std::chrono::milliseconds min_interval_{50};
  double begin_ = 0.0, end_ = 1.0;
  mutable std::chrono::steady_clock::time_point last_call_{};
  mutable bool called_ = false;
};

}  // namespace meshsmith
