#pragma once
// Pause, step and speed of a recording that RunSequence plays as fast as it goes (not paced): what a viewer's
// controls set. The controls may be set from any thread; the run waits for each frame's turn in WaitForTurn. A run
// without a Playback is not slowed at all.

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>

namespace hoidslam::pipeline {

class Playback {
 public:
  struct State {
    bool paused = false;
    double speed = 0.0;  // 0: as fast as it goes; else a multiple of the recorded rate
  };

  // The largest speed taken: beyond it a recording goes as fast as it goes anyway.
  static constexpr double kMaxSpeed = 64.0;

  void Pause();
  void Play();
  // While paused, lets one more frame go; while playing, pauses.
  void Step();
  // Throws InputError naming `speed` unless it is 0 or in (0, kMaxSpeed].
  void SetSpeed(double speed);
  State state() const;

  // Waits until the frame recorded at `timestamp` (seconds) may go: the run is not paused (or a step lets it) and,
  // at a speed, its time has come, reckoned from the first frame played since the speed was set or play resumed.
  // Returns false as soon as `stop_requested` says so (polled every 50 ms while waiting).
  bool WaitForTurn(double timestamp, const std::function<bool()>& stop_requested);

 private:
  using Clock = std::chrono::steady_clock;

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  State state_;
  int steps_ = 0;            // frames a step has let go while paused
  bool anchored_ = false;    // the next frame to go sets the anchor
  Clock::time_point anchor_wall_;
  double anchor_timestamp_ = 0.0;
};

}  // namespace hoidslam::pipeline
