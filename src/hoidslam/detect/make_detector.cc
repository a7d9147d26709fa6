#include "hoidslam/detect/make_detector.h"

#include <array>
#include <utility>

#include <fmt/format.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/detect/file_detector.h"

namespace hoidslam::detect {
namespace {

constexpr core::EnumNames<DetectorKind, 3> kKindNames = {{
    {DetectorKind::kNone, "none"},
    {DetectorKind::kOnnx, "onnx"},
    {DetectorKind::kFile, "file"},
}};

}  // namespace

std::string_view ToString(DetectorKind kind) { return core::EnumName(kKindNames, kind); }

DetectorKind ParseDetectorKind(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kKindNames, text, parameter, "detector");
}

void DetectorOptions::Check() const {
  switch (kind) {
    case DetectorKind::kOnnx:
      onnx.Check();
      break;
    case DetectorKind::kFile:
      if (detections_file.empty()) {
        throw core::InputError::ForParameter("Detector.detectionsFile", "required when Detector.kind is file");
      }
      break;
    case DetectorKind::kNone:
      break;
  }
}

std::unique_ptr<Detector> MakeDetector(const DetectorOptions& options) {
  options.Check();
  switch (options.kind) {
    case DetectorKind::kOnnx:
      return std::make_unique<OnnxDetector>(options.onnx);
    case DetectorKind::kFile:
      return std::make_unique<FileDetector>(options.detections_file);
    case DetectorKind::kNone:
      break;
  }
  return std::make_unique<NoDetector>();
}

}  // namespace hoidslam::detect
