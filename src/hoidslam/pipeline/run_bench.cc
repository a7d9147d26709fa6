// End-to-end speed of `hoidslam run` on this machine: frames per second over a rendered synthetic walking
// sequence (people walking and carrying things on the real TUM fr3 camera path), with the YOLOX-Nano detector,
// loading, ORB extraction, the HOID filter, tracking and local mapping all in. In the real-time mode the
// detector runs in its own thread and tracking never waits for it; in the synchronous mode every frame waits for
// its own detections. DESIGN.md budgets ≥ 25 frames per second end to end in real time.
#include <filesystem>
#include <memory>

#include <benchmark/benchmark.h>

#include "hoidslam/detect/onnx_detector.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/sequence_writer.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kFrames = 300;  // 10 s of walking_xyz at 30 Hz, people in view from the 100th frame

// The sequence, rendered once for all benchmarks of the program.
const fs::path& WalkingSequence(const testing::TempDir& dir) {
  static const fs::path root = [&] {
    synth::Scenario scenario = synth::LoadScenario("walking_xyz");
    scenario.max_frames = kFrames;
    synth::SynthOptions options;
    options.out = dir / "walking_xyz";
    options.tum_dir = hoidslam::testing::SharedPath("data/tum");
    synth::WriteSequence(scenario, options);
    return options.out;
  }();
  return root;
}

void BM_RunWalkingXyzWithYoloxNano(benchmark::State& state) {
  const fs::path model = hoidslam::testing::SharedPath("models/yolox_nano.onnx");
  if (!fs::exists(model) || !fs::exists(hoidslam::testing::SharedPath("data/tum"))) {
    state.SkipWithError("shared model or TUM data not found (set HOIDSLAM_SHARED_DIR)");
    return;
  }
  static const testing::TempDir dir;
  const io::RgbdSequence sequence = io::RgbdSequence::OpenTum(WalkingSequence(dir));
  detect::OnnxDetectorOptions detector_options;
  detector_options.model = model;
  detect::OnnxDetector detector(detector_options);
  RunOptions options = RunOptions::FromSettings(io::Settings{});
  options.exclusion.hoid.mode = core::FilterMode::kHoid2d;
  options.realtime.enabled = state.range(0) == 1;
  options.snapshots = 0;
  RunSummary summary;
  for (auto _ : state) {
    const testing::TempDir out;
    summary = RunSequence(sequence, detector, options, out.path());
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(summary.frames) / summary.seconds);
  state.counters["tracked"] = static_cast<double>(summary.tracked);
}
BENCHMARK(BM_RunWalkingXyzWithYoloxNano)
    ->ArgName("realtime")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->Repetitions(5)
    ->ReportAggregatesOnly()
    ->UseRealTime();

}  // namespace
}  // namespace hoidslam::pipeline
