// The shipped vocabulary (data/vocabulary/orb-k10-l5.hbow, k = 10, L = 5) at work: the bag of words and direct
// index of a 640×480 frame's 1000 ORB descriptors (budget: median <= 1.5 ms), and loading the file (<= 150 ms).
// The frame is a real TUM fr3 walking_xyz frame the vocabulary was not trained on; without the shared data, a
// procedural image stands in.
// Run: bow_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <filesystem>
#include <random>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/bow/test_images.h"
#include "hoidslam/bow/vocabulary.h"
#include "support/shared_data.h"

namespace hoidslam::bow {
namespace {

const std::filesystem::path kShippedVocabulary = std::filesystem::path(HOIDSLAM_VOCABULARY_DIR) / "orb-k10-l5.hbow";

// Random filled rectangles over noise: corners at many scales, for 1000 keypoints.
cv::Mat ProceduralFrame() {
  cv::Mat image(480, 640, CV_8UC1);
  cv::randu(image, 90, 166);
  std::mt19937 rng(7);
  for (int i = 0; i < 1500; ++i) {
    const cv::Rect box(static_cast<int>(rng() % 640), static_cast<int>(rng() % 480), 4 + static_cast<int>(rng() % 40),
                       4 + static_cast<int>(rng() % 40));
    cv::rectangle(image, box, cv::Scalar(static_cast<double>(rng() % 256)), cv::FILLED);
  }
  return image;
}

void TransformFrame(benchmark::State& state) {
  const Vocabulary vocabulary = Vocabulary::Load(kShippedVocabulary);
  const std::filesystem::path frame = testing::SharedPath(fixtures::kTumFrame);
  const bool real = std::filesystem::exists(frame);
  const cv::Mat descriptors = fixtures::OrbDescriptors(real ? fixtures::ReadGray(frame) : ProceduralFrame());
  for (auto _ : state) {
    ImageWords words = vocabulary.Transform(descriptors);
    benchmark::DoNotOptimize(words);
  }
  state.counters["keypoints"] = descriptors.rows;
  state.SetLabel(real ? "TUM fr3 walking_xyz frame" : "procedural frame (shared data not found)");
}
BENCHMARK(TransformFrame)->Unit(benchmark::kMillisecond);

void LoadShipped(benchmark::State& state) {
  for (auto _ : state) {
    Vocabulary vocabulary = Vocabulary::Load(kShippedVocabulary);
    benchmark::DoNotOptimize(vocabulary);
  }
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(kShippedVocabulary)) / 1e6;
}
BENCHMARK(LoadShipped)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoidslam::bow
