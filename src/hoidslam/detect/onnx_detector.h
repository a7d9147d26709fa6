#pragma once
// A YOLO-family detector exported to ONNX (YOLOX, YOLOv5, YOLOv8, YOLO11), run on the CPU by OpenCV's dnn
// module. The output layout is recognised from the output tensor's shape; docs/detectors.md explains each.

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/dnn/dnn.hpp>

#include "hoidslam/detect/detector.h"
#include "hoidslam/detect/yolo_decode.h"

namespace hoidslam::detect {

// Settings names in comments (section Detector.*); the `hoidslam detect` flags are given too.
struct OnnxDetectorOptions {
  std::filesystem::path model;            // Detector.model (--model): the .onnx file, required
  int input_size = 0;                     // Detector.inputSize (--input-size): square network input, pixels, a
                                          //   multiple of 32; 0 = the model's declared input size, or 640 when the
                                          //   model declares none (dynamic axes)
  float confidence_threshold = 0.25F;     // Detector.confThreshold (--conf): minimum score, in (0, 1)
  float nms_threshold = 0.45F;            // Detector.nmsThreshold (--nms): IoU above which a box suppresses a
                                          //   weaker one of its class, in (0, 1]
  YoloLayout layout = YoloLayout::kAuto;  // Detector.layout (--layout): kAuto recognises it from the output
  std::filesystem::path class_names;      // Detector.classNames (--names): one name per line; empty = COCO-80

  void Check() const;
};

// The network input side used when the model does not declare one.
inline constexpr int kDefaultInputSize = 640;

// One network per detector: Detect() runs one frame at a time (give each thread its own detector).
class OnnxDetector final : public Detector {
 public:
  // Loads the model and runs it once on a blank image to learn its output layout. Throws InputError naming the
  // model file when it is missing, not loadable ONNX, not an image model (1×3×H×W input), has an output matching
  // no known layout, or has a number of classes other than the class names list; and naming the parameter for
  // invalid options.
  explicit OnnxDetector(const OnnxDetectorOptions& options);

  // Best score first; `timestamp` is not used.
  std::vector<core::Detection> Detect(double timestamp, const cv::Mat& bgr) override;
  std::string Name() const override { return options_.model.filename().string(); }
  std::filesystem::path Source() const override { return options_.model; }

  cv::Size input_size() const { return input_size_; }
  const OutputFormat& output_format() const { return format_; }
  const std::vector<std::string>& class_names() const { return class_names_; }

 private:
  cv::Mat Preprocess(const cv::Mat& bgr, LetterboxTransform& transform) const;

  OnnxDetectorOptions options_;
  cv::dnn::Net net_;
  cv::Size input_size_;
  std::string output_name_;  // the network output holding the detections
  OutputFormat format_;
  std::vector<std::string> class_names_;
};

}  // namespace hoidslam::detect
