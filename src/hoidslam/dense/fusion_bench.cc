// A keyframe's fusion, as DenseMapper::Build does it for each final keyframe (StaticWorld::Fuse): the volume's
// integration (1 cm voxels, 4 cm truncation, Open3D on one OpenMP thread) and, in a second thread at the same time,
// the occupancy map's rays (5 cm), of a real 640×480 TUM fr3/walking_xyz frame cut to the default depth range —
// into an empty volume and into one that already holds the view. Target (docs/dense.md): ≤ 30 ms a keyframe, median.
// Run: dense_bench --benchmark_filter=Fuse --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <filesystem>
#include <memory>
#include <stdexcept>

#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/dense/fusible_depth.h"
#include "hoidslam/dense/static_world.h"
#include "hoidslam/dense/tsdf_volume.h"
#include "support/shared_data.h"

namespace hoidslam::dense {
namespace {

struct Keyframe {
  cv::Mat bgr, depth;
};

Keyframe RealKeyframe() {
  const std::filesystem::path pair = testing::SharedPath("data/tum/fr3_walking_xyz_pair");
  Keyframe keyframe;
  keyframe.bgr = cv::imread((pair / "rgb/1341846313.592026.png").string(), cv::IMREAD_COLOR);
  const cv::Mat raw = cv::imread((pair / "depth/1341846313.592088.png").string(), cv::IMREAD_UNCHANGED);
  if (keyframe.bgr.empty() || raw.empty()) throw std::runtime_error("the shared TUM frame pair is missing: " + pair.string());
  cv::Mat metres;
  raw.convertTo(metres, CV_32FC1, 1.0 / 5000.0);  // TUM: 5000 units a metre
  keyframe.depth = FusibleDepth(metres, cv::Mat(), DenseOptions{});
  return keyframe;
}

void BM_FuseKeyframe(benchmark::State& state, bool known_space) {
  UseOneOpenMPThread();  // as DenseMapper::Build
  const Keyframe keyframe = RealKeyframe();
  const DenseOptions options;
  const core::CameraIntrinsics camera;  // TUM fr3
  auto world = std::make_unique<StaticWorld>(options, camera);
  if (known_space) world->Fuse(keyframe.bgr, keyframe.depth, core::Pose::Identity());
  for (auto _ : state) {
    if (!known_space) {
      state.PauseTiming();
      world = std::make_unique<StaticWorld>(options, camera);
      state.ResumeTiming();
    }
    world->Fuse(keyframe.bgr, keyframe.depth, core::Pose::Identity());
  }
  state.counters["blocks"] = static_cast<double>(world->volume().Blocks());
}
BENCHMARK_CAPTURE(BM_FuseKeyframe, empty_volume, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FuseKeyframe, known_space, true)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoidslam::dense
