#pragma once
// What finds people and objects in a frame. Backends: OnnxDetector (a YOLO-family model run by OpenCV's dnn
// module), FileDetector (replays a detections file written earlier, by `hoidslam detect` or by any other tool)
// and NoDetector. MakeDetector (make_detector.h) picks one from options.

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "hoidslam/core/detection.h"

namespace hoidslam::detect {

class Detector {
 public:
  Detector() = default;
  virtual ~Detector() = default;
  Detector(const Detector&) = delete;
  Detector& operator=(const Detector&) = delete;

  // The detections in `bgr` (CV_8UC3), the colour image of the frame taken at `timestamp` seconds. Boxes are in
  // pixels of `bgr` and lie inside it. Throws InputError for input the backend cannot
  // serve (e.g. a timestamp missing from a detections file).
  virtual std::vector<core::Detection> Detect(double timestamp, const cv::Mat& bgr) = 0;

  // What produces the detections, for logs and detections-file headers: e.g. "yolox_nano.onnx".
  virtual std::string Name() const = 0;

  // The file the detections come from (a model, a detections file), for the record of a run; empty: none.
  virtual std::filesystem::path Source() const { return {}; }
};

// Finds nothing: the baseline that keeps every feature.
class NoDetector final : public Detector {
 public:
  std::vector<core::Detection> Detect(double /*timestamp*/, const cv::Mat& /*bgr*/) override { return {}; }
  std::string Name() const override { return "none"; }
};

}  // namespace hoidslam::detect
