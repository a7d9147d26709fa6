#include "hoidslam/pipeline/live_pacing.h"

#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::pipeline {
namespace {

using namespace std::chrono_literals;

TEST(NewestArrived, IsTheLastFrameWhoseTimeHasCome) {
  const std::vector<double> t = {10.0, 10.1, 10.2, 10.3};
  EXPECT_EQ(NewestArrived(t, -1.0), 0U);
  EXPECT_EQ(NewestArrived(t, 0.0), 0U);
  EXPECT_EQ(NewestArrived(t, 0.15), 1U);
  EXPECT_EQ(NewestArrived(t, 0.2), 2U);
  EXPECT_EQ(NewestArrived(t, 5.0), 3U);
  EXPECT_EQ(NewestArrived({}, 1.0), 0U);
}

// 20 frames 10 ms apart.
std::vector<double> Frames() {
  std::vector<double> t;
  for (int i = 0; i < 20; ++i) t.push_back(100.0 + 0.01 * i);
  return t;
}

TEST(LivePacing, AFastSystemGetsEveryFrameAtItsTime) {
  LivePacing pacing(Frames());
  const auto start = std::chrono::steady_clock::now();
  std::optional<std::size_t> frame;
  std::vector<std::size_t> got;
  while ((frame = pacing.Next(frame, {}))) got.push_back(*frame);
  // Under a loaded machine a frame may come late and the next one be due already: then frames are skipped.
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back(), 19U);
  EXPECT_EQ(got.size() + pacing.dropped(), 20U);
  EXPECT_GE(std::chrono::steady_clock::now() - start, 190ms);  // the recording lasts 190 ms
}

TEST(LivePacing, FramesArrivingWhileBusyAreDroppedAndCounted) {
  LivePacing pacing(Frames());
  std::optional<std::size_t> frame = pacing.Next(std::nullopt, {});
  ASSERT_EQ(frame, 0U);
  std::this_thread::sleep_for(55ms);  // busy for five frames and a half
  frame = pacing.Next(frame, {});
  ASSERT_TRUE(frame);
  EXPECT_GE(*frame, 5U);
  EXPECT_EQ(pacing.dropped(), *frame - 1);
}

TEST(LivePacing, HoldingTheClockDelaysEveryFrameStillToCome) {
  LivePacing pacing(Frames());
  std::optional<std::size_t> frame = pacing.Next(std::nullopt, {});
  const auto start = std::chrono::steady_clock::now();
  pacing.Hold(100ms);
  frame = pacing.Next(frame, {});
  EXPECT_GE(std::chrono::steady_clock::now() - start, 100ms);  // frame 1 was due 10 ms after frame 0, now 110 ms
  ASSERT_TRUE(frame);
  EXPECT_EQ(pacing.dropped(), *frame - 1);
}

TEST(LivePacing, AStopRequestEndsTheWaitForTheNextFrame) {
  LivePacing pacing({0.0, 3600.0});  // the second frame comes in an hour
  std::optional<std::size_t> frame = pacing.Next(std::nullopt, {});
  const auto start = std::chrono::steady_clock::now();
  int polls = 0;
  frame = pacing.Next(frame, [&] { return ++polls > 2; });
  EXPECT_FALSE(frame);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 10s);
}

}  // namespace
}  // namespace hoidslam::pipeline
