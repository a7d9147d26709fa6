// The occupancy map's work per keyframe: the rays of one 640×480 depth image, every 4th pixel in x and y (19,200
// rays), into OctoMap leaves of 5 cm — into an empty map and into one that already holds the same view (a keyframe
// over known space) — and a whole room: 24 views inserted and projected to the 2D grid. The keyframe is a real
// TUM fr3/walking_xyz depth image, cut to the dense module's default depth range; without the shared data, a view
// of the test room stands in. Target: a keyframe well under 50 ms.
// Run: dense_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <filesystem>
#include <memory>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/dense/occupancy.h"
#include "hoidslam/dense/test_room.h"
#include "support/shared_data.h"

namespace hoidslam::dense {
namespace {

cv::Mat KeyframeDepth(bool& real) {
  const std::filesystem::path path =
      testing::SharedPath("data/tum/fr3_walking_xyz_pair/depth/1341846313.592088.png");
  const cv::Mat raw = std::filesystem::exists(path) ? cv::imread(path.string(), cv::IMREAD_UNCHANGED) : cv::Mat();
  real = !raw.empty();
  if (!real) {
    const test_room::Room room = test_room::TestRoom();
    return test_room::RenderDepth(room, core::CameraIntrinsics{}, test_room::RoomViews(room)[1]);
  }
  cv::Mat depth;
  raw.convertTo(depth, CV_32FC1, 1.0 / 5000.0);  // TUM: 5000 units a metre
  const DenseOptions range;
  depth.setTo(0.0F, (depth < range.min_depth) | (depth > range.max_depth));
  return depth;
}

void BM_InsertKeyframe(benchmark::State& state, bool known_space) {
  bool real = false;
  const cv::Mat depth = KeyframeDepth(real);
  const core::CameraIntrinsics camera;  // TUM fr3
  auto map = std::make_unique<OccupancyMap>(OccupancyOptions{});
  if (known_space) map->InsertDepth(depth, camera, core::Pose::Identity());
  for (auto _ : state) {
    if (!known_space) {
      state.PauseTiming();
      map = std::make_unique<OccupancyMap>(OccupancyOptions{});
      state.ResumeTiming();
    }
    map->InsertDepth(depth, camera, core::Pose::Identity());
  }
  state.counters["occupied_leaves"] = static_cast<double>(map->OccupiedLeaves());
  state.SetLabel(real ? "TUM fr3/walking_xyz depth" : "test room (no shared data)");
}
BENCHMARK_CAPTURE(BM_InsertKeyframe, empty_map, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_InsertKeyframe, known_space, true)->Unit(benchmark::kMillisecond);

void BM_MapTheRoom(benchmark::State& state) {
  const test_room::Room room = test_room::TestRoom();
  const core::CameraIntrinsics camera;
  std::vector<std::pair<core::Pose, cv::Mat>> views;
  for (const core::Pose& T_fc : test_room::RoomViews(room)) {
    views.emplace_back(T_fc, test_room::RenderDepth(room, camera, T_fc));
  }
  std::size_t occupied = 0;
  for (auto _ : state) {
    OccupancyMap map{OccupancyOptions{}};
    for (const auto& [T_fc, depth] : views) map.InsertDepth(depth, camera, T_fc);
    const OccupancyGrid grid = map.Project(core::Pose::Identity());
    benchmark::DoNotOptimize(grid.cells.data());
    state.PauseTiming();
    occupied = map.OccupiedLeaves();
    state.ResumeTiming();
  }
  state.counters["keyframes"] = static_cast<double>(views.size());
  state.counters["occupied_leaves"] = static_cast<double>(occupied);
}
BENCHMARK(BM_MapTheRoom)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoidslam::dense
