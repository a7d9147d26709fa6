// Detector speed on this machine: YOLOX-Nano at 416×416 on a real TUM frame, the whole Detect() call
// (letterbox and blob, inference, decode, non-maximum suppression). DESIGN.md budgets about 50 ms.
#include <benchmark/benchmark.h>
#include <opencv2/dnn/dnn.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/detect/onnx_detector.h"
#include "hoidslam/detect/yolo_decode.h"
#include "support/shared_data.h"

namespace hoidslam::detect {
namespace {

const char* const kModel = "models/yolox_nano.onnx";
const char* const kFrame = "data/tum/fr3_walking_xyz_pair/rgb/1341846313.592026.png";

// False (and the benchmark marked as failed to run) when the shared model or frame is missing.
bool HaveSharedData(benchmark::State& state) {
  if (std::filesystem::exists(hoidslam::testing::SharedPath(kModel)) &&
      std::filesystem::exists(hoidslam::testing::SharedPath(kFrame))) {
    return true;
  }
  state.SkipWithError("shared model or TUM frame not found (set HOIDSLAM_SHARED_DIR)");
  return false;
}

cv::Mat ReadFrame() { return cv::imread(hoidslam::testing::SharedPath(kFrame).string(), cv::IMREAD_COLOR); }

void BM_YoloxNanoDetectTumFrame(benchmark::State& state) {
  if (!HaveSharedData(state)) return;
  OnnxDetectorOptions options;
  options.model = hoidslam::testing::SharedPath(kModel);
  OnnxDetector detector(options);
  const cv::Mat image = ReadFrame();
  std::size_t detections = 0;
  for (auto _ : state) {
    detections = detector.Detect(0.0, image).size();
    benchmark::DoNotOptimize(detections);
  }
  state.counters["detections"] = static_cast<double>(detections);
}
BENCHMARK(BM_YoloxNanoDetectTumFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

// The post-processing share of the above: decoding YOLOX-Nano's real 1×3549×85 output for the same frame, and
// class-wise non-maximum suppression.
void BM_DecodeAndNmsYoloxNanoOutput(benchmark::State& state) {
  if (!HaveSharedData(state)) return;
  cv::dnn::Net net = cv::dnn::readNetFromONNX(hoidslam::testing::SharedPath(kModel).string());
  const cv::Size input(416, 416);
  LetterboxTransform transform;
  net.setInput(cv::dnn::blobFromImage(Letterbox(ReadFrame(), input, LetterboxPlacement::kTopLeft, transform)));
  const cv::Mat output = net.forward().clone();
  const OutputFormat format{YoloLayout::kYolox, 80};
  std::size_t kept = 0;
  for (auto _ : state) {
    kept = ClassWiseNms(DecodeOutput(output, format, input, 0.25F), 0.45F).size();
    benchmark::DoNotOptimize(kept);
  }
  state.counters["detections"] = static_cast<double>(kept);
}
BENCHMARK(BM_DecodeAndNmsYoloxNanoOutput)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hoidslam::detect
