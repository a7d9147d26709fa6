// Relocalisation after a loss, through System::Track: a map of 20 frames of the sliding wall
// (tests/support/sliding_wall.h), tracked in the deterministic mode; the camera is lost on a frame of another wall,
// and half a second after the last tracked frame (beyond the motion model's max_motion_gap, set to 0.1 s here) comes
//   - BM_RelocalizeMappedPlace: the view of frame 5 again, which is relocalised (found by its words, its pose by
//     PnP, confirmed against the local map; provisional until the frames after it confirm it);
//   - BM_RelocalizeUnknownPlace: a view of the other wall, which is not.
// Only that Track call is timed. The system is built again, timing paused, before each one, so every call starts
// from the same map and the same loss; the frame's features are extracted outside the timing too. The counters: the
// inliers of the timed frame, and whether it became a keyframe (then the deterministic mode's local mapping would
// run inside the call; it does not here).
// Run: slam_bench --benchmark_filter=Reloc
#include <memory>
#include <string>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "hoidslam/slam/system.h"
#include "support/sliding_wall.h"

namespace hoidslam::slam {
namespace {

using testing::wall::MakeFrame;
using testing::wall::MakeTexture;

constexpr int kMappedFrames = 20;
constexpr double kLossSeconds = 0.5;  // from the last tracked frame to the timed one

SystemOptions Options() {
  SystemOptions options;
  options.deterministic = true;             // the same map on every build
  options.tracking.max_motion_gap = 0.1;    // s: the timed frame comes too late for the motion model
  return options;
}

// The two walls: the mapped one and another the map has never seen.
struct Walls {
  cv::Mat mapped = MakeTexture(3);
  cv::Mat other = MakeTexture(99);
};

// A system that tracked frames [0, kMappedFrames) of the mapped wall and then lost the camera on a frame of the
// other; nullptr (with the benchmark stopped) when it did not.
std::unique_ptr<System> MapAndLose(benchmark::State& state, const Walls& walls) {
  auto system = std::make_unique<System>(Options());
  for (int k = 0; k < kMappedFrames; ++k) {
    const core::RgbdFrame frame = MakeFrame(walls.mapped, k);
    if (system->Track(frame, system->Extract(frame.rgb), {}).state != TrackingState::kOk) {
      state.SkipWithError(("frame " + std::to_string(k) + " of the wall was not tracked").c_str());
      return nullptr;
    }
  }
  core::RgbdFrame lost = MakeFrame(walls.other, 0);
  lost.timestamp = MakeFrame(walls.mapped, kMappedFrames - 1).timestamp + 1.0 / 30.0;
  if (system->Track(lost, system->Extract(lost.rgb), {}).state != TrackingState::kLost) {
    state.SkipWithError("a frame of another wall was tracked in the map");
    return nullptr;
  }
  return system;
}

// Times System::Track of `frame` kLossSeconds after the last tracked frame; `relocalized` says whether the frame is
// of a mapped place, to be relocalised, or not.
void TrackAfterLoss(benchmark::State& state, const Walls& walls, core::RgbdFrame frame, bool relocalized) {
  frame.timestamp = MakeFrame(walls.mapped, kMappedFrames - 1).timestamp + kLossSeconds;
  int inliers = 0;
  bool keyframe = false;
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<System> system = MapAndLose(state, walls);
    if (!system) break;
    const ExtractedFeatures features = system->Extract(frame.rgb);
    state.ResumeTiming();
    const TrackResult result = system->Track(frame, features, {});
    state.PauseTiming();
    const bool found = result.state == TrackingState::kProvisional && result.method == TrackingMethod::kRelocalization;
    if (relocalized && !found) {
      state.SkipWithError("the view of a mapped place was not relocalised");
      break;
    }
    if (!relocalized && result.state != TrackingState::kLost) {
      state.SkipWithError("the view of an unknown place was tracked");
      break;
    }
    inliers = result.inliers;
    keyframe = result.keyframe;
    system.reset();  // stops its threads, outside the timing
    state.ResumeTiming();
  }
  state.counters["inliers"] = inliers;
  state.counters["keyframe"] = keyframe ? 1 : 0;
}

void BM_RelocalizeMappedPlace(benchmark::State& state) {
  const Walls walls;
  TrackAfterLoss(state, walls, MakeFrame(walls.mapped, 5), true);
}
// Each timed call costs a build of about a quarter of a second: 0.1 s of timed calls (a few dozen) rather than 0.5.
BENCHMARK(BM_RelocalizeMappedPlace)->Unit(benchmark::kMillisecond)->MinTime(0.1);

void BM_RelocalizeUnknownPlace(benchmark::State& state) {
  const Walls walls;
  TrackAfterLoss(state, walls, MakeFrame(walls.other, 10), false);
}
BENCHMARK(BM_RelocalizeUnknownPlace)->Unit(benchmark::kMillisecond)->MinTime(0.1);

}  // namespace
}  // namespace hoidslam::slam
