#include "hoidslam/pipeline/detector_thread.h"

#include <algorithm>
#include <exception>
#include <utility>

#include <opencv2/core/utility.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::pipeline {

OpenCvThreadLimit::OpenCvThreadLimit() : previous_(cv::getNumThreads()) {
  cv::setNumThreads(std::max(1, cv::getNumberOfCPUs() - 1));
}

OpenCvThreadLimit::~OpenCvThreadLimit() { cv::setNumThreads(previous_); }

DetectorThread::DetectorThread(detect::Detector& detector, double min_milliseconds)
    : detector_(detector),
      min_duration_(min_milliseconds),
      thread_([this](std::stop_token stop) { Loop(std::move(stop)); }) {}

void DetectorThread::Submit(std::size_t index, double timestamp, const cv::Mat& bgr) {
  // The detector thread gets an image of its own: the caller's buffer is reused or freed on the caller's thread
  // (a camera's, an API caller's), and one shared through OpenCV's reference count would be freed on whichever
  // thread lets go last.
  Request request{index, timestamp, bgr.clone(), std::chrono::steady_clock::now()};
  {
    std::lock_guard lock(mutex_);
    waiting_ = std::move(request);
  }
  wake_.notify_one();
}

std::optional<DetectorResult> DetectorThread::TakeNewest() {
  std::lock_guard lock(mutex_);
  return std::exchange(newest_, std::nullopt);
}

DetectorResult DetectorThread::WaitForNext() {
  std::unique_lock lock(mutex_);
  if (!newest_ && !waiting_ && !busy_) throw core::Error("DetectorThread::WaitForNext: no frame is being detected");
  result_.wait(lock, [this] { return newest_.has_value(); });
  return *std::exchange(newest_, std::nullopt);
}

void DetectorThread::Loop(std::stop_token stop) {
  std::unique_lock lock(mutex_);
  while (true) {
    if (!wake_.wait(lock, stop, [this] { return waiting_.has_value(); })) return;  // stop requested
    Request request = std::move(*waiting_);
    waiting_.reset();
    busy_ = true;
    lock.unlock();
    const auto started = std::chrono::steady_clock::now();

    DetectorResult result{.frame = request.index, .timestamp = request.timestamp, .detections = {},
                          .error = std::nullopt, .milliseconds = 0.0};
    try {
      result.detections = detector_.Detect(request.timestamp, request.bgr);
    } catch (const std::exception& e) {
      result.error = e.what();  // one bad frame must not end a run: the caller keeps the previous detections
    }
    request.bgr.release();
    const auto ready = started + std::chrono::duration_cast<std::chrono::steady_clock::duration>(min_duration_);

    lock.lock();
    // The simulated latency: sleep out the rest of it, unless asked to stop (wake_ listens to the stop token).
    wake_.wait_until(lock, stop, ready, [] { return false; });
    result.milliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - request.submitted).count();
    newest_ = std::move(result);
    busy_ = false;
    result_.notify_all();
  }
}

}  // namespace hoidslam::pipeline
