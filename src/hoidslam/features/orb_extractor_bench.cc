// ORB extraction on a real 640×480 TUM frame (fr3 walking_xyz, grayscale), 1000 features, 8 levels, 1.2 — the
// per-frame setting, alone and followed by the second extraction outside the people of a crowded frame. Budget
// (DESIGN.md): median <= 6 ms. Without the shared data, a procedural image stands in.
// Run: features_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <filesystem>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/features/orb_extractor.h"
#include "support/shared_data.h"

namespace hoidslam::features {
namespace {

// Random filled rectangles and circles over a gradient, then a light blur: corners at many scales.
cv::Mat ProceduralImage() {
  cv::Mat image(480, 640, CV_8UC1);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) image.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>((x + y) / 5);
  }
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> px(0, 639);
  std::uniform_int_distribution<int> py(0, 479);
  std::uniform_int_distribution<int> extent(4, 40);
  std::uniform_int_distribution<int> grey(0, 255);
  for (int i = 0; i < 1500; ++i) {
    const cv::Scalar colour(grey(rng));
    if (i % 2 == 0) {
      cv::rectangle(image, cv::Rect(px(rng), py(rng), extent(rng), extent(rng)), colour, cv::FILLED);
    } else {
      cv::circle(image, cv::Point(px(rng), py(rng)), extent(rng) / 2, colour, cv::FILLED);
    }
  }
  cv::GaussianBlur(image, image, cv::Size(3, 3), 0.8);
  return image;
}

cv::Mat BenchImage(bool& real) {
  const std::filesystem::path path = testing::SharedPath("data/tum/fr3_walking_xyz_pair/rgb/1341846313.592026.png");
  const cv::Mat image = std::filesystem::exists(path) ? cv::imread(path.string(), cv::IMREAD_GRAYSCALE) : cv::Mat();
  real = !image.empty();
  return real ? image : ProceduralImage();
}

void RunExtract(benchmark::State& state) {
  bool real = false;
  const cv::Mat image = BenchImage(real);
  core::OrbOptions options;  // 1000 features, 8 levels, 1.2, FAST 20 / 7
  OrbExtractor extractor(options);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  for (auto _ : state) {
    extractor.Extract(image, keypoints, descriptors);
    benchmark::DoNotOptimize(descriptors.data);
    benchmark::ClobberMemory();
  }
  state.counters["keypoints"] = static_cast<double>(keypoints.size());
  state.SetLabel(real ? "TUM fr3_walking_xyz frame" : "procedural image (shared data not found)");
}

// As the SLAM system runs it: the levels spread over OpenCV's threads.
void BM_Extract(benchmark::State& state) { RunExtract(state); }

// All on one core: the CPU time a frame costs, what matters when tracking, mapping and the detector share cores.
void BM_ExtractOneThread(benchmark::State& state) {
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  RunExtract(state);
  cv::setNumThreads(threads);
}

// A crowded frame as `run` extracts it: Extract, then ExtractOutside spending the budget again outside three
// people who cover four fifths of the image (what the exclusion filter drops; the boxes of the extractor's
// tests). The time of both calls.
void BM_ExtractOutsidePeople(benchmark::State& state) {
  bool real = false;
  const cv::Mat image = BenchImage(real);
  cv::Mat people(image.size(), CV_8UC1, cv::Scalar(0));
  for (const cv::Rect& person : {cv::Rect(0, 80, 200, 400), cv::Rect(230, 0, 200, 480), cv::Rect(470, 100, 170, 380)}) {
    people(person).setTo(255);
  }
  OrbExtractor extractor(core::OrbOptions{});
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  for (auto _ : state) {
    extractor.Extract(image, keypoints, descriptors);
    extractor.ExtractOutside(people, keypoints, descriptors);
    benchmark::DoNotOptimize(descriptors.data);
    benchmark::ClobberMemory();
  }
  state.counters["keypoints"] = static_cast<double>(keypoints.size());
  state.SetLabel(real ? "TUM fr3_walking_xyz frame" : "procedural image (shared data not found)");
}

void BM_DescriptorDistance(benchmark::State& state) {
  cv::Mat descriptors(1000, 32, CV_8UC1);
  cv::randu(descriptors, 0, 256);
  for (auto _ : state) {
    int sum = 0;
    for (int i = 1; i < descriptors.rows; ++i) sum += DescriptorDistance(descriptors.ptr(0), descriptors.ptr(i));
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * (descriptors.rows - 1));
}

BENCHMARK(BM_Extract)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExtractOneThread)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExtractOutsidePeople)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DescriptorDistance)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hoidslam::features
