#include "hoidslam/pipeline/detector_thread.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::pipeline {
namespace {

using namespace std::chrono_literals;

// Finds one person whose label says which frame (by timestamp) it was found on; takes `delay` a frame and fails
// on the timestamps given.
class FakeDetector final : public detect::Detector {
 public:
  explicit FakeDetector(std::chrono::milliseconds delay, std::vector<double> failing = {})
      : delay_(delay), failing_(std::move(failing)) {}
  std::vector<core::Detection> Detect(double timestamp, const cv::Mat& /*bgr*/) override {
    ++calls;
    std::this_thread::sleep_for(delay_);
    for (const double t : failing_) {
      if (t == timestamp) throw core::InputError("no detections at " + std::to_string(timestamp));
    }
    return {core::Detection{.class_id = 0, .label = std::to_string(timestamp), .score = 1.0F, .box = {0, 0, 10, 10}}};
  }
  std::string Name() const override { return "fake"; }

  std::atomic<int> calls = 0;

 private:
  std::chrono::milliseconds delay_;
  std::vector<double> failing_;
};

TEST(DetectorThread, WaitingForEachFrameGivesEveryFramesOwnDetections) {
  FakeDetector detector(0ms);
  DetectorThread thread(detector);
  for (std::size_t frame = 0; frame < 20; ++frame) {
    thread.Submit(frame, static_cast<double>(frame), cv::Mat());
    const DetectorResult result = thread.WaitForNext();
    EXPECT_EQ(result.frame, frame);
    ASSERT_EQ(result.detections.size(), 1U);
    EXPECT_EQ(result.detections[0].label, std::to_string(static_cast<double>(frame)));
  }
}

TEST(DetectorThread, ABusyDetectorGetsTheNewestFrameAndNeverHoldsUpTheCaller) {
  FakeDetector detector(30ms);
  DetectorThread thread(detector);
  thread.Submit(0, 0.0, cv::Mat());
  EXPECT_EQ(thread.WaitForNext().frame, 0U);
  // Frames handed over faster than the detector can go: those waiting are replaced by newer ones.
  std::vector<std::size_t> seen;
  for (std::size_t frame = 1; frame <= 40; ++frame) {
    thread.Submit(frame, static_cast<double>(frame), cv::Mat());
    if (const auto result = thread.TakeNewest()) seen.push_back(result->frame);
    std::this_thread::sleep_for(2ms);
  }
  // The last frame handed over is detected in the end (after any result finished but not yet taken).
  DetectorResult last = thread.WaitForNext();
  while (last.frame != 40) last = thread.WaitForNext();
  EXPECT_LT(detector.calls.load(), 30);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);  // newest first, never older
}

TEST(DetectorThread, ASimulatedLatencyDelaysEveryResult) {
  FakeDetector detector(0ms);
  DetectorThread thread(detector, 40.0);
  for (std::size_t frame = 0; frame < 3; ++frame) {
    const auto handed_over = std::chrono::steady_clock::now();
    thread.Submit(frame, 0.0, cv::Mat());
    const DetectorResult result = thread.WaitForNext();
    EXPECT_GE(std::chrono::steady_clock::now() - handed_over, 40ms);
    EXPECT_GE(result.milliseconds, 40.0);
  }
}

TEST(DetectorThread, AFailedFrameComesBackAsAnError) {
  FakeDetector detector(0ms, {1.0});
  DetectorThread thread(detector);
  thread.Submit(1, 1.0, cv::Mat());
  const DetectorResult result = thread.WaitForNext();
  ASSERT_TRUE(result.error);
  EXPECT_NE(result.error->find("no detections at 1"), std::string::npos);
  EXPECT_TRUE(result.detections.empty());
  thread.Submit(2, 2.0, cv::Mat());
  EXPECT_FALSE(thread.WaitForNext().error);  // and the thread goes on
}

TEST(DetectorThread, WaitingWithNothingHandedOverIsAnError) {
  FakeDetector detector(0ms);
  DetectorThread thread(detector);
  EXPECT_THROW(thread.WaitForNext(), core::Error);
}

TEST(DetectorThread, StopsPromptlyWhileDetectingOrSleepingOutALatency) {
  FakeDetector detector(20ms);
  const auto start = std::chrono::steady_clock::now();
  {
    DetectorThread thread(detector, 60000.0);  // a minute's latency: the destructor must not sit it out
    thread.Submit(0, 0.0, cv::Mat());
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, 10s);
  {
    DetectorThread idle(detector);  // never handed a frame
  }
}

TEST(OpenCvThreadLimit, LeavesACoreToTrackingAndRestoresThePool) {
  const int before = cv::getNumThreads();
  {
    const OpenCvThreadLimit limit;
    EXPECT_EQ(cv::getNumThreads(), std::max(1, cv::getNumberOfCPUs() - 1));
  }
  EXPECT_EQ(cv::getNumThreads(), before);
}

}  // namespace
}  // namespace hoidslam::pipeline
