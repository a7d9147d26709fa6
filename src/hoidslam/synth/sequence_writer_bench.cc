// Speed of the synthetic benchmark generator: the simulation, the ground-truth boxes and masks, the static
// geometry and moving volume, and the whole `synth` job (render + noise + PNG writing of rgb, depth and mask) per
// frame and for a 900-frame sequence.
//
//   build/src/hoidslam/synth/synth_bench --benchmark_filter='Synth|Snapshot|GroundTruth|SequenceGeometry'
#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "hoidslam/synth/renderer.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/sensor_noise.h"
#include "hoidslam/synth/sequence_writer.h"
#include "hoidslam/synth/static_geometry.h"
#include "hoidslam/synth/world.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

// The carry scenario has three people and a procedural 900-frame camera path: no data files needed.
Scenario CarryScenario(std::size_t frames) {
  Scenario scenario = LoadScenario("carry");
  scenario.max_frames = frames;
  return scenario;
}

void BM_WorldSnapshot(benchmark::State& state) {
  const Scenario scenario = CarryScenario(0);
  const TextureSet textures(scenario.textures);
  const World world(scenario, textures);
  double t = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(world.Snapshot(t));
    t = t > 29.0 ? 0.0 : t + 1.0 / 30.0;
  }
}
BENCHMARK(BM_WorldSnapshot)->Unit(benchmark::kMicrosecond);

void BM_GroundTruthBoxesAndMask(benchmark::State& state) {
  const Scenario scenario = CarryScenario(0);
  const TextureSet textures(scenario.textures);
  const World world(scenario, textures);
  const SceneSnapshot snapshot = world.Snapshot(5.0);
  const CameraPath path = ScenarioCameraPath(scenario, {});
  const RenderOutput rendered = Renderer(core::CameraIntrinsics{}, textures).Render(snapshot, path.frames()[150].T_wc);
  for (auto _ : state) {
    benchmark::DoNotOptimize(GroundTruthBoxes(rendered.instance, snapshot, 50));
    benchmark::DoNotOptimize(MovingMask(rendered.instance, snapshot));
  }
}
BENCHMARK(BM_GroundTruthBoxesAndMask)->Unit(benchmark::kMillisecond);

// The static geometry and moving volume of the 900 frames of `carry` (three people carrying things): every
// frame added as WriteSequence adds it, both taken out at the end; items are frames.
void BM_SequenceGeometry(benchmark::State& state) {
  const Scenario scenario = CarryScenario(0);
  const TextureSet textures(scenario.textures);
  const World world(scenario, textures);
  const CameraPath path = ScenarioCameraPath(scenario, {});
  std::vector<SceneSnapshot> snapshots;
  for (const CameraFrame& frame : path.frames()) {
    snapshots.push_back(world.Snapshot(frame.timestamp - path.frames().front().timestamp));
  }
  for (auto _ : state) {
    SequenceGeometry geometry(snapshots.front());
    for (const SceneSnapshot& snapshot : snapshots) geometry.Add(snapshot);
    benchmark::DoNotOptimize(geometry.StaticMesh());
    benchmark::DoNotOptimize(geometry.MovingVolume());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(snapshots.size()));
}
BENCHMARK(BM_SequenceGeometry)->Unit(benchmark::kMillisecond);

// Encoding and writing one frame's three PNGs (colour, 16-bit depth, mask) with the settings WriteSequence uses.
void BM_WriteFramePngs(benchmark::State& state) {
  const Scenario scenario = CarryScenario(0);
  const TextureSet textures(scenario.textures);
  const World world(scenario, textures);
  const SceneSnapshot snapshot = world.Snapshot(5.0);
  const RenderOutput rendered = Renderer(core::CameraIntrinsics{}, textures)
                                    .Render(snapshot, ScenarioCameraPath(scenario, {}).frames()[150].T_wc);
  const cv::Mat rgb = ApplyRgbNoise(rendered.bgr, scenario.sensor_noise, 1);
  const cv::Mat depth = ApplyDepthNoise(rendered.depth, scenario.sensor_noise, 2);
  const cv::Mat mask = MovingMask(rendered.instance, snapshot);
  testing::TempDir temp;
  const std::vector<int> noisy = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                  cv::IMWRITE_PNG_STRATEGY_HUFFMAN_ONLY};
  const std::vector<int> sparse = {cv::IMWRITE_PNG_COMPRESSION, 1, cv::IMWRITE_PNG_STRATEGY,
                                   cv::IMWRITE_PNG_STRATEGY_RLE};
  for (auto _ : state) {
    cv::imwrite((temp / "rgb.png").string(), rgb, noisy);
    cv::imwrite((temp / "depth.png").string(), depth, noisy);
    cv::imwrite((temp / "mask.png").string(), mask, sparse);
  }
}
BENCHMARK(BM_WriteFramePngs)->Unit(benchmark::kMillisecond);

// The whole job for state.range(0) frames of `carry` on state.range(1) threads; ms_per_frame is the job's wall
// time per frame.
void BM_SynthCarry(benchmark::State& state) {
  const Scenario scenario = CarryScenario(static_cast<std::size_t>(state.range(0)));
  testing::TempDir temp;
  SynthOptions options;
  options.out = temp / "carry";
  options.threads = static_cast<int>(state.range(1));
  options.force = true;
  double seconds = 0.0;
  for (auto _ : state) seconds += WriteSequence(scenario, options).seconds;
  state.counters["ms_per_frame"] =
      1e3 * seconds / (static_cast<double>(state.range(0)) * static_cast<double>(state.iterations()));
}
BENCHMARK(BM_SynthCarry)->Args({60, 1})->Args({60, 2})->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK(BM_SynthCarry)->Args({900, 2})->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

// The real TUM camera path of walking_xyz (827 frames), as `hoidslam synth --scenario walking_xyz` renders it.
void BM_SynthWalkingXyz(benchmark::State& state) {
  const std::filesystem::path tum = testing::SharedPath("data/tum");
  if (!std::filesystem::exists(tum / "groundtruth" / "fr3_walking_xyz.txt")) {
    state.SkipWithError("shared TUM data not found (set HOIDSLAM_SHARED_DIR)");
    return;
  }
  const Scenario scenario = LoadScenario("walking_xyz");
  testing::TempDir temp;
  SynthOptions options;
  options.out = temp / "walking_xyz";
  options.tum_dir = tum;
  options.threads = 2;
  options.force = true;
  SynthResult result;
  for (auto _ : state) result = WriteSequence(scenario, options);
  state.counters["frames"] = static_cast<double>(result.frames);
  state.counters["ms_per_frame"] = 1e3 * result.seconds / static_cast<double>(result.frames);
}
BENCHMARK(BM_SynthWalkingXyz)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace hoidslam::synth
