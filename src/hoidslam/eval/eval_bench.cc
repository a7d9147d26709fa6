// Cost of evaluating a long run: ATE and RPE of a 30 Hz estimate against 100 Hz ground truth.
#include <benchmark/benchmark.h>

#include "hoidslam/eval/ate.h"
#include "hoidslam/eval/rpe.h"
#include "hoidslam/eval/test_trajectories.h"

namespace hoidslam::eval {
namespace {

struct Inputs {
  core::Trajectory groundtruth;
  core::Trajectory estimate;
};

// state.range(0) seconds of motion.
Inputs MakeInputs(const benchmark::State& state) {
  const auto seconds = static_cast<std::size_t>(state.range(0));
  Inputs inputs{test_data::MakeLissajousTrajectory(100 * seconds, 100.0), {}};
  for (const core::StampedPose& pose : test_data::MakeLissajousTrajectory(30 * seconds, 30.0))
    inputs.estimate.push_back({pose.timestamp + 0.004, pose.T_wc});
  return inputs;
}

void BM_Ate(benchmark::State& state) {
  const Inputs inputs = MakeInputs(state);
  for (auto _ : state) benchmark::DoNotOptimize(ComputeAte(inputs.groundtruth, inputs.estimate, {}));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(inputs.estimate.size()));
}
BENCHMARK(BM_Ate)->Arg(60)->Arg(600)->Unit(benchmark::kMillisecond);

void BM_Rpe(benchmark::State& state) {
  const Inputs inputs = MakeInputs(state);
  for (auto _ : state) benchmark::DoNotOptimize(ComputeRpe(inputs.groundtruth, inputs.estimate, {}));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(inputs.estimate.size()));
}
BENCHMARK(BM_Rpe)->Arg(60)->Arg(600)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoidslam::eval
