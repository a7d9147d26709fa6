#include "hoidslam/pipeline/playback.h"

#include <atomic>
#include <cmath>
#include <chrono>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::pipeline {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using ::testing::HasSubstr;

TEST(Playback, GoesAsFastAsItGoesUntilTold) {
  Playback playback;
  const auto start = Clock::now();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(playback.WaitForTurn(100.0 + i, {}));  // 100 s of recording
  EXPECT_LT(Clock::now() - start, 5s);
  EXPECT_FALSE(playback.state().paused);
  EXPECT_EQ(playback.state().speed, 0.0);
}

TEST(Playback, HoldsAPausedRunUntilPlayAndLetsOneFrameGoPerStep) {
  Playback playback;
  playback.Pause();
  std::atomic<int> frames{0};
  std::thread run([&] {
    for (int i = 0; i < 5; ++i) {
      if (!playback.WaitForTurn(i * 0.1, {})) return;
      ++frames;
    }
  });
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(frames.load(), 0);
  playback.Step();
  playback.Step();
  for (auto deadline = Clock::now() + 10s; frames.load() < 2 && Clock::now() < deadline;) std::this_thread::sleep_for(5ms);
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(frames.load(), 2);  // two steps, two frames, still paused
  EXPECT_TRUE(playback.state().paused);
  playback.Play();
  run.join();
  EXPECT_EQ(frames.load(), 5);
}

TEST(Playback, AtASpeedAFrameWaitsForItsRecordedTime) {
  Playback playback;
  playback.SetSpeed(2.0);
  const auto start = Clock::now();
  ASSERT_TRUE(playback.WaitForTurn(10.0, {}));  // the first frame goes at once and sets the clock
  ASSERT_TRUE(playback.WaitForTurn(10.4, {}));  // 0.4 s of recording at twice its rate: not before 0.2 s
  EXPECT_GE(Clock::now() - start, 200ms);
}

TEST(Playback, StopsWaitingWhenTheRunIsStopped) {
  Playback playback;
  playback.Pause();
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    std::this_thread::sleep_for(50ms);
    stop = true;
  });
  EXPECT_FALSE(playback.WaitForTurn(0.0, [&] { return stop.load(); }));
  stopper.join();
}

TEST(Playback, RefusesASpeedOutOfRangeNamingIt) {
  Playback playback;
  for (const double speed : {-1.0, 65.0, std::nan("")}) {
    try {
      playback.SetSpeed(speed);
      ADD_FAILURE() << "speed " << speed << " taken";
    } catch (const core::InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("speed"));
    }
  }
  playback.SetSpeed(0.5);
  EXPECT_EQ(playback.state().speed, 0.5);
}

}  // namespace
}  // namespace hoidslam::pipeline
