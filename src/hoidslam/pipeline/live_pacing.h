#pragma once
// Plays a recorded sequence as a live camera delivers it (`hoidslam run --pace`): frame i arrives
// timestamps[i] − timestamps[0] seconds after the first. Like a camera driver with a one-frame buffer, the newest
// frame that has arrived is the one handed out next; the frames it replaced while the system was busy are dropped
// and counted.

#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace hoidslam::pipeline {

// The newest of `timestamps` (increasing) to have arrived `elapsed` seconds after the first (0 for any elapsed < 0).
std::size_t NewestArrived(std::span<const double> timestamps, double elapsed);

class LivePacing {
 public:
  // `timestamps`: the frames to play, in order (seconds).
  explicit LivePacing(std::vector<double> timestamps);

  // The frame to process after frame `previous` (nullopt: the first; the camera starts then): the newest frame
  // that has arrived, or the next one to arrive after waiting for it. nullopt when the sequence is over, or when
  // `stop_requested` says so while waiting.
  std::optional<std::size_t> Next(std::optional<std::size_t> previous, const std::function<bool()>& stop_requested);

  // Stops the clock for `duration`: every frame still to come arrives that much later. A replay decoding its next
  // frames holds the clock, as a live camera has its frames decoded when it hands them out.
  void Hold(std::chrono::steady_clock::duration duration);

  std::size_t dropped() const { return dropped_; }

 private:
  std::vector<double> timestamps_;
  std::optional<std::chrono::steady_clock::time_point> start_;
  std::size_t dropped_ = 0;
};

}  // namespace hoidslam::pipeline
