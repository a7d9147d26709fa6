#pragma once
// The detector in its own thread, for the real-time mode: tracking hands it frames and takes the newest
// detections there are, and never waits for it (but for the first frame's, so that the map does not start on the
// people in view). One frame waits at most: a frame handed over while the detector is busy replaces the one
// waiting, since detections of the newest frame are what tracking wants next. The thread is owned by the
// DetectorThread: it starts in the constructor, and the destructor lets the detection in progress finish (a
// simulated latency is cut short) and joins it.

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/detect/detector.h"

namespace hoidslam::pipeline {

// While it lives, OpenCV's thread pool (which runs cv::dnn's layers) has one thread fewer than the machine has
// cores, at least one: in the real-time mode the detector must leave a core to tracking and local mapping, or
// every frame's tracking waits on the scheduler instead of the detector. The pool size is process-wide: one
// limit at a time, and the earlier size comes back on destruction.
class OpenCvThreadLimit {
 public:
  OpenCvThreadLimit();
  ~OpenCvThreadLimit();
  OpenCvThreadLimit(const OpenCvThreadLimit&) = delete;
  OpenCvThreadLimit& operator=(const OpenCvThreadLimit&) = delete;

 private:
  int previous_;
};

// The detections of one frame, as the detector thread delivers them.
struct DetectorResult {
  std::size_t frame = 0;     // index of the frame the detections are of
  double timestamp = 0.0;    // and its timestamp
  std::vector<core::Detection> detections;
  std::optional<std::string> error;  // the detector failed on that frame (detections empty)
  double milliseconds = 0.0;  // from the frame's handover to its result, waiting included
};

class DetectorThread {
 public:
  // `detector` is used by the thread only, until the DetectorThread is destroyed. Every detection takes at least
  // `min_milliseconds` (a simulated network latency for a detector that replays a file; 0: as long as it takes).
  explicit DetectorThread(detect::Detector& detector, double min_milliseconds = 0.0);
  DetectorThread(const DetectorThread&) = delete;
  DetectorThread& operator=(const DetectorThread&) = delete;

  // Hands frame `index` over, a copy of `bgr` its own (about 0.1 ms for 640×480); never waits for the detector.
  void Submit(std::size_t index, double timestamp, const cv::Mat& bgr);
  // The newest result finished since the last call (older unclaimed ones are passed over), if any.
  std::optional<DetectorResult> TakeNewest();
  // Waits for the next result (and returns it), e.g. the first frame's. Throws core::Error when nothing was
  // submitted that has no result yet.
  DetectorResult WaitForNext();

 private:
  struct Request {
    std::size_t index = 0;
    double timestamp = 0.0;
    cv::Mat bgr;
    std::chrono::steady_clock::time_point submitted;
  };
  void Loop(std::stop_token stop);

  detect::Detector& detector_;
  std::chrono::duration<double, std::milli> min_duration_;
  std::mutex mutex_;
  std::condition_variable_any wake_;    // the thread: a request came, or stop
  std::condition_variable_any result_;  // the caller: a result came
  std::optional<Request> waiting_;
  std::optional<DetectorResult> newest_;
  bool busy_ = false;  // a request is being detected
  // Declared last: it starts once the members it uses exist, and its destructor (asking it to stop, then joining)
  // runs first.
  std::jthread thread_;
};

}  // namespace hoidslam::pipeline
