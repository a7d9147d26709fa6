#pragma once
// The ONNX detector's command-line options, shared by every command that runs a detector.

#include <string>

#include <CLI/CLI.hpp>

#include "hoidslam/detect/onnx_detector.h"

namespace hoidslam::apps {

struct OnnxArgs {
  std::string model;
  float conf = detect::OnnxDetectorOptions{}.confidence_threshold;
  float nms = detect::OnnxDetectorOptions{}.nms_threshold;
  int input_size = 0;
  std::string layout = "auto";
  std::string names;

  detect::OnnxDetectorOptions ToOptions() const;
};

// Adds --model (required when `model_required`), --conf, --nms, --input-size, --layout, --names.
void AddOnnxOptions(CLI::App& command, OnnxArgs& args, bool model_required);

}  // namespace hoidslam::apps
