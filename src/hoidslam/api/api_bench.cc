// The public API's own cost per frame beside the tracking it calls: System::Track's wall time against the time the
// frame spent inside hoidslam (FrameResult::milliseconds: extraction, filter, tracking), over a rendered synthetic
// walk in the deterministic hoid2d mode with each frame's boxes given. bench/python_overhead.py runs this and the
// same frames through the Python module: what the Python call adds is its own difference less this one.
#include <algorithm>
#include <cstdlib>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/hoidslam.h"
#include "hoidslam/hoidslam_opencv.h"
#include "hoidslam/core/stopwatch.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"

namespace hoidslam {
namespace {

namespace fs = std::filesystem;

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

// $HOIDSLAM_BENCH_SEQUENCE (the folder bench/python_overhead.py rendered), else 150 frames of walking_xyz rendered
// once for the program.
fs::path Walk() {
  if (const char* folder = std::getenv("HOIDSLAM_BENCH_SEQUENCE"); folder != nullptr && *folder != '\0') return folder;
  static const testing::TempDir dir;
  static const fs::path root = [] {
    SynthOptions options;
    options.out = dir / "walking_xyz";
    options.frames = 150;
    options.tum_dir = hoidslam::testing::SharedPath("data/tum");
    RenderSynthetic(options);
    return options.out;
  }();
  return root;
}

void BM_TrackOverhead(benchmark::State& state) {
  if (std::getenv("HOIDSLAM_BENCH_SEQUENCE") == nullptr && !fs::exists(hoidslam::testing::SharedPath("data/tum"))) {
    state.SkipWithError("shared TUM data not found (set HOIDSLAM_SHARED_DIR)");
    return;
  }
  const Sequence sequence(Walk());
  const DetectionsFile detections(sequence.root() / "detections.jsonl");
  std::vector<double> call_ms, inside_ms, api_ms;
  for (auto _ : state) {
    Options options;
    options.filter = "hoid2d";
    options.deterministic = true;
    System slam(options);
    for (std::size_t i = 0; i < sequence.size(); ++i) {
      const Frame frame = sequence.Load(i);
      const std::vector<Detection> boxes = detections.Find(frame.timestamp).value_or(std::vector<Detection>{});
      const ImageView rgb{frame.rgb.data(), frame.width, frame.height, 0, PixelFormat::kBgr};
      const ImageView depth{frame.depth.data(), frame.width, frame.height, 0, PixelFormat::kDepthFloat32};
      const core::Stopwatch clock;
      const FrameResult result = slam.Track(rgb, depth, frame.timestamp, boxes);
      const double ms = clock.ElapsedMilliseconds();
      call_ms.push_back(ms);
      inside_ms.push_back(result.milliseconds);
      api_ms.push_back(ms - result.milliseconds);
    }
  }
  state.counters["call_ms"] = Median(call_ms);
  state.counters["inside_ms"] = Median(inside_ms);
  state.counters["api_ms"] = Median(api_ms);
}
BENCHMARK(BM_TrackOverhead)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace hoidslam
