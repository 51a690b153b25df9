#include <meshsmith/core/errors.h>
#include <meshsmith/core/progress.h>

#include <algorithm>

namespace meshsmith {

Progress::Progress(ProgressCallback callback, std::chrono::milliseconds min_interval)
    : callback_(std::move(callback)), min_interval_(min_interval) {}

void Progress::report(double fraction, const char* stage) const {
  if (!callback_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool final_call = fraction >= 1.0;
  if (called_ && !final_call && now - last_call_ < min_interval_) return;
  called_ = true;
  last_call_ = now;
  const double clamped = std::clamp(fraction, 0.0, 1.0);
  if (!callback_(begin_ + (end_ - begin_) * clamped, stage)) {
    throw Cancelled(std::string("cancelled by the progress callback during '") + stage + "'");
  }
}

Progress Progress::subrange(double begin, double end) const {
  Progress child(callback_, min_interval_);
  child.begin_ = begin_ + (end_ - begin_) * begin;
  child.end_ = begin_ + (end_ - begin_) * end;
  return child;
}

}  // namespace meshsmith
