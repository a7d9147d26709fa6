#pragma once
// Chooses and builds a detector backend from options.

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "hoidslam/detect/detector.h"
#include "hoidslam/detect/onnx_detector.h"

namespace hoidslam::detect {

enum class DetectorKind {
  kNone,  // NoDetector
  kOnnx,  // OnnxDetector
  kFile,  // FileDetector
};

std::string_view ToString(DetectorKind kind);
// Parses "none", "onnx", "file"; throws InputError naming `parameter` otherwise.
DetectorKind ParseDetectorKind(std::string_view text, const std::string& parameter = "Detector.kind");

struct DetectorOptions {
  DetectorKind kind = DetectorKind::kNone;  // Detector.kind
  OnnxDetectorOptions onnx;                 // used when kind is kOnnx
  std::filesystem::path detections_file;    // Detector.detectionsFile: required when kind is kFile

  // Checks the options of the chosen backend only.
  void Check() const;
};

// Throws InputError as the chosen backend's constructor does.
std::unique_ptr<Detector> MakeDetector(const DetectorOptions& options);

}  // namespace hoidslam::detect
