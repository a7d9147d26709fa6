#include "hoidslam/pipeline/exclusion.h"

#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"

namespace hoidslam::pipeline {

std::string_view ExclusionOptions::ModeName() const { return oracle ? "oracle" : core::ToString(hoid.mode); }

void SetFilterMode(std::string_view text, ExclusionOptions& options, const std::string& parameter) {
  if (text == "oracle") {
    options.oracle = true;
    return;
  }
  try {
    options.hoid.mode = core::ParseFilterMode(text, parameter);
  } catch (const core::InputError&) {
    throw core::InputError::ForParameter(
        parameter, fmt::format("unknown mode '{}': use none, person, classes, hoid2d, hoid3d or oracle", text));
  }
  options.oracle = false;
}

KeypointExclusion::KeypointExclusion(const ExclusionOptions& options, const std::filesystem::path& sequence_root)
    : options_(options) {
  options_.hoid.Check();
  if (options_.oracle) {
    mask_folder_ = sequence_root / "mask";
    if (!std::filesystem::is_directory(mask_folder_)) {
      throw core::InputError::InFile(
          mask_folder_, "not found: --filter oracle needs the ground-truth moving masks of a `hoidslam synth` sequence");
    }
  }
}

void KeypointExclusion::Mark(const core::RgbdFrame& frame, std::span<const core::Detection> detections,
                             std::span<const cv::KeyPoint> keypoints, std::vector<std::uint8_t>& keep,
                             std::vector<hoid::Decision>& decisions) const {
  core::HoidOptions hoid = options_.hoid;
  if (options_.oracle) hoid.mode = core::FilterMode::kNone;  // the boxes are logged, not used
  hoid::ClassifyDetections(detections, hoid, frame.depth, decisions);
  if (!options_.oracle) {
    hoid::MarkKeypointsToKeep(keypoints, detections, decisions, keep);
    return;
  }
  // The mask has the colour image's name: mask/<t>.png beside rgb/<t>.png.
  const std::filesystem::path mask_path = mask_folder_ / std::filesystem::path(frame.rgb_path).filename();
  const cv::Mat mask = io::ReadImage(mask_path, cv::IMREAD_GRAYSCALE, "moving mask");
  if (mask.size() != frame.rgb.size()) {
    throw core::InputError::InFile(mask_path, fmt::format("is {}×{}, the frame {}×{}", mask.cols, mask.rows,
                                                          frame.rgb.cols, frame.rgb.rows));
  }
  keep.assign(keypoints.size(), 1);
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const int x = static_cast<int>(std::lround(keypoints[i].pt.x));
    const int y = static_cast<int>(std::lround(keypoints[i].pt.y));
    if (x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<std::uint8_t>(y, x) != 0) keep[i] = 0;
  }
}

}  // namespace hoidslam::pipeline
