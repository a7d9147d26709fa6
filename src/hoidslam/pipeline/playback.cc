#include "hoidslam/pipeline/playback.h"

#include <cmath>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::pipeline {

void Playback::Pause() {
  const std::lock_guard lock(mutex_);
  state_.paused = true;
  steps_ = 0;
  changed_.notify_all();
}

void Playback::Play() {
  const std::lock_guard lock(mutex_);
  state_.paused = false;
  anchored_ = false;  // time runs again from the next frame, not from before the pause
  changed_.notify_all();
}

void Playback::Step() {
  const std::lock_guard lock(mutex_);
  if (state_.paused) ++steps_;
  state_.paused = true;
  changed_.notify_all();
}

void Playback::SetSpeed(double speed) {
  if (!(speed == 0.0 || (speed > 0.0 && speed <= kMaxSpeed))) {
    throw core::InputError::ForParameter("speed", fmt::format("must be 0 (as fast as it goes) or in (0, {}], got {}",
                                                              kMaxSpeed, speed));
  }
  const std::lock_guard lock(mutex_);
  state_.speed = speed;
  anchored_ = false;
  changed_.notify_all();
}

Playback::State Playback::state() const {
  const std::lock_guard lock(mutex_);
  return state_;
}

bool Playback::WaitForTurn(double timestamp, const std::function<bool()>& stop_requested) {
  constexpr auto kPoll = std::chrono::milliseconds(50);
  std::unique_lock lock(mutex_);
  while (true) {
    if (stop_requested && stop_requested()) return false;
    if (state_.paused && steps_ == 0) {
      changed_.wait_for(lock, kPoll);
      continue;
    }
    if (state_.speed > 0.0 && anchored_) {
      const auto due = anchor_wall_ + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>((timestamp - anchor_timestamp_) / state_.speed));
      if (Clock::now() < due) {
        changed_.wait_until(lock, std::min(due, Clock::now() + kPoll));
        continue;
      }
    }
    if (!anchored_) {
      anchored_ = true;
      anchor_wall_ = Clock::now();
      anchor_timestamp_ = timestamp;
    }
    if (state_.paused) {
      --steps_;
      anchored_ = false;  // a step is not a clock: the frame after a resumed play goes at once
    }
    return true;
  }
}

}  // namespace hoidslam::pipeline
