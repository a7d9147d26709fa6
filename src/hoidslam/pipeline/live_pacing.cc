#include "hoidslam/pipeline/live_pacing.h"

#include <algorithm>
#include <thread>

namespace hoidslam::pipeline {

std::size_t NewestArrived(std::span<const double> timestamps, double elapsed) {
  if (timestamps.empty()) return 0;
  const double now = timestamps.front() + elapsed;
  const auto after = std::upper_bound(timestamps.begin(), timestamps.end(), now);
  return after == timestamps.begin() ? 0 : static_cast<std::size_t>(after - timestamps.begin()) - 1;
}

LivePacing::LivePacing(std::vector<double> timestamps) : timestamps_(std::move(timestamps)) {}

std::optional<std::size_t> LivePacing::Next(std::optional<std::size_t> previous,
                                            const std::function<bool()>& stop_requested) {
  using Clock = std::chrono::steady_clock;
  const std::size_t next = previous ? *previous + 1 : 0;
  if (next >= timestamps_.size()) return std::nullopt;
  if (!start_) start_ = Clock::now();
  const auto arrival = *start_ + std::chrono::duration_cast<Clock::duration>(
                                     std::chrono::duration<double>(timestamps_[next] - timestamps_.front()));
  // Waits in short steps, so that Ctrl-C is heard during a long gap in the recording.
  constexpr auto kStep = std::chrono::milliseconds(50);
  for (auto now = Clock::now(); now < arrival; now = Clock::now()) {
    if (stop_requested && stop_requested()) return std::nullopt;
    std::this_thread::sleep_until(std::min(arrival, now + kStep));
  }
  const double elapsed = std::chrono::duration<double>(Clock::now() - *start_).count();
  const std::size_t newest = std::max(next, NewestArrived(timestamps_, elapsed));
  dropped_ += newest - next;
  return newest;
}

void LivePacing::Hold(std::chrono::steady_clock::duration duration) {
  if (start_) *start_ += duration;
}

}  // namespace hoidslam::pipeline
