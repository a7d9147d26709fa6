#include "hoidslam/pipeline/exclusion.h"

#include <cmath>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"
#include "hoidslam/pipeline/dynamic_mask.h"

namespace hoidslam::pipeline {

std::string ExclusionOptions::ModeName() const {
  if (oracle) return "oracle";
  const core::HoidPlusOptions& plus = hoid.plus;
  if (hoid.mode != core::FilterMode::kHoidPlus || (plus.depth && plus.memory && plus.safety_net)) {
    return std::string(core::ToString(hoid.mode));
  }
  return fmt::format("{}{}", core::kHoidPlusPartsPrefix, plus.Parts());
}

void SetFilterMode(std::string_view text, ExclusionOptions& options, const std::string& parameter) {
  if (text == "oracle") {
    options.oracle = true;
    return;
  }
  if (text.starts_with(core::kHoidPlusPartsPrefix)) {
    options.hoid.plus.SetParts(text.substr(core::kHoidPlusPartsPrefix.size()), parameter);
    options.hoid.mode = core::FilterMode::kHoidPlus;
    options.oracle = false;
    return;
  }
  try {
    options.hoid.mode = core::ParseFilterMode(text, parameter);
  } catch (const core::InputError&) {
    throw core::InputError::ForParameter(
        parameter,
        fmt::format("unknown mode '{}': use none, person, classes, hoid2d, hoid3d, hoidplus[:parts] or oracle", text));
  }
  options.oracle = false;
}

double ExclusionCounts::Leaked() const {
  const std::size_t moving = moving_kept + moving_dropped;
  return moving == 0 ? 0.0 : static_cast<double>(moving_kept) / static_cast<double>(moving);
}

double ExclusionCounts::Wasted() const {
  const std::size_t still = static_kept + static_dropped;
  return still == 0 ? 0.0 : static_cast<double>(static_dropped) / static_cast<double>(still);
}

ExclusionCounts& ExclusionCounts::operator+=(const ExclusionCounts& other) {
  moving_kept += other.moving_kept;
  moving_dropped += other.moving_dropped;
  static_kept += other.static_kept;
  static_dropped += other.static_dropped;
  static_dropped_without_depth += other.static_dropped_without_depth;
  static_dropped_on_still_people += other.static_dropped_on_still_people;
  return *this;
}

namespace {

// The pixel of `image` the keypoint's position rounds to; nullopt outside the image.
std::optional<cv::Point> PixelOf(const cv::Mat& image, const cv::KeyPoint& keypoint) {
  const cv::Point pixel(static_cast<int>(std::lround(keypoint.pt.x)), static_cast<int>(std::lround(keypoint.pt.y)));
  if (pixel.x < 0 || pixel.y < 0 || pixel.x >= image.cols || pixel.y >= image.rows) return std::nullopt;
  return pixel;
}

// By the rule hoidplus drops by (hoid/foreground.h): the depth at the pixel the keypoint rounds to.
bool HasValidDepth(const cv::Mat& depth, const cv::KeyPoint& keypoint) {
  const std::optional<cv::Point> pixel = PixelOf(depth, keypoint);
  return pixel && hoid::IsValidDepth(depth.at<float>(*pixel));
}

}  // namespace

bool OnMask(const cv::Mat& mask, const cv::KeyPoint& keypoint) {
  const std::optional<cv::Point> pixel = PixelOf(mask, keypoint);
  return pixel && mask.at<std::uint8_t>(*pixel) != 0;
}

KeypointExclusion::KeypointExclusion(const ExclusionOptions& options, const std::filesystem::path& sequence_root,
                                     const core::CameraIntrinsics& camera)
    : options_(options) {
  options_.hoid.Check();
  if (!options_.oracle && options_.hoid.mode == core::FilterMode::kHoidPlus) plus_.emplace(options_.hoid, camera);
  if (std::filesystem::is_directory(sequence_root / "mask")) {
    mask_folder_ = sequence_root / "mask";
    if (std::filesystem::is_directory(sequence_root / "people")) people_folder_ = sequence_root / "people";
  } else if (options_.oracle) {
    throw core::InputError::InFile(
        sequence_root / "mask",
        "not found: --filter oracle needs the ground-truth moving masks of a `hoidslam synth` sequence");
  }
}

const cv::Mat& KeypointExclusion::ReadMask(const std::filesystem::path& folder, const core::RgbdFrame& frame,
                                           const char* what, CachedMask& cache) {
  // A mask has the colour image's name: mask/<t>.png, people/<t>.png beside rgb/<t>.png.
  const std::filesystem::path path = folder / std::filesystem::path(frame.rgb_path).filename();
  if (path == cache.path) return cache.mask;
  cv::Mat mask = io::ReadImage(path, cv::IMREAD_GRAYSCALE, what);
  if (mask.size() != frame.rgb.size()) {
    throw core::InputError::InFile(path, fmt::format("is {}×{}, the frame {}×{}", mask.cols, mask.rows,
                                                     frame.rgb.cols, frame.rgb.rows));
  }
  cache.mask = std::move(mask);
  cache.path = path;
  return cache.mask;
}

const cv::Mat& KeypointExclusion::MovingMask(const core::RgbdFrame& frame) const {
  return ReadMask(mask_folder_, frame, "moving mask", moving_);
}

ExclusionCounts KeypointExclusion::Score(const core::RgbdFrame& frame, std::span<const cv::KeyPoint> keypoints,
                                         std::span<const std::uint8_t> keep) const {
  const cv::Mat& mask = MovingMask(frame);
  const cv::Mat no_people;
  const cv::Mat& people = ScoresStillPeople() ? ReadMask(people_folder_, frame, "people mask", people_) : no_people;
  ExclusionCounts counts;
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const bool kept = keep[i] != 0;
    if (OnMask(mask, keypoints[i])) {
      ++(kept ? counts.moving_kept : counts.moving_dropped);
    } else if (kept) {
      ++counts.static_kept;
    } else {
      ++counts.static_dropped;
      if (!HasValidDepth(frame.depth, keypoints[i])) {
        ++counts.static_dropped_without_depth;
      } else if (OnMask(people, keypoints[i])) {  // a person, yet static: standing still
        ++counts.static_dropped_on_still_people;
      }
    }
  }
  return counts;
}

void KeypointExclusion::Mark(const core::RgbdFrame& frame, std::span<const core::Detection> detections,
                             std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors,
                             std::vector<std::uint8_t>& keep, hoid::JudgedBoxes& boxes) {
  if (plus_) {
    plus_->Filter(frame.timestamp, frame.depth, detections, keypoints, descriptors, boxes, keep);
    return;
  }
  boxes.detections.assign(detections.begin(), detections.end());
  boxes.context.clear();
  core::HoidOptions hoid = options_.hoid;
  if (options_.oracle) hoid.mode = core::FilterMode::kNone;  // the boxes are logged, not used
  hoid::ClassifyDetections(detections, hoid, frame.depth, boxes.decisions);
  if (!options_.oracle) {
    hoid::MarkKeypointsToKeep(keypoints, detections, boxes.decisions, keep);
    return;
  }
  const cv::Mat& mask = MovingMask(frame);
  keep.resize(keypoints.size());
  for (std::size_t i = 0; i < keypoints.size(); ++i) keep[i] = OnMask(mask, keypoints[i]) ? 0 : 1;
}

void KeypointExclusion::AfterTracking(const std::optional<core::Pose>& T_cw) {
  if (plus_) plus_->Localize(T_cw);
}

cv::Mat KeypointExclusion::PaintDropped(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes) const {
  return PaintReaching(frame, boxes, {options_.hoid.plus.depth_extent, options_.hoid.plus.box_margin});
}

cv::Mat KeypointExclusion::PaintReaching(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                                         const StaticMapReach& reach) const {
  if (!plus_) return PaintDynamicBoxes(boxes.detections, boxes.decisions, frame.rgb.size());
  std::vector<hoid::ExclusionRegion> regions = hoid::DynamicRegions(boxes);
  // A cut lies the filter's depth extent behind a foreground's median (or at the mode's far end, farther still):
  // moved back by the difference, it lies depth_extent behind.
  const auto farther = static_cast<float>(reach.depth_extent - options_.hoid.plus.depth_extent);
  // A region's box is the detector's grown by the filter's margin m₀ a side, (1 + 2m₀) times its size: grown by
  // g more, (1 + 2m₀)(1 + 2g) = 1 + 2m makes it the detector's box grown by m.
  const double tracking_margin = options_.hoid.plus.box_margin;
  const double wider = ((1.0 + 2.0 * reach.box_margin) / (1.0 + 2.0 * tracking_margin) - 1.0) / 2.0;
  std::vector<hoid::ExclusionRegion> reaching;
  reaching.reserve(2 * regions.size());
  for (hoid::ExclusionRegion region : regions) {
    // Outside the box the map leaves out only what tracking drops inside it: a head or an arm the box cut off lies
    // at the person's own depth, while the floor and the desks around them, beyond tracking's cut, are fused.
    if (wider > 0.0) reaching.push_back({hoid::GrowBox(region.box, wider), region.cut, region.edge_margin});
    if (farther > 0.0F) region.cut += farther;  // +inf stays +inf
    reaching.push_back(region);
  }
  return hoid::PaintExclusionRegions(reaching, options_.hoid.plus.depth ? frame.depth : cv::Mat(), frame.rgb.size());
}

cv::Mat KeypointExclusion::StaticMapExclusion(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                                              const StaticMapReach& reach) const {
  if (!options_.oracle) return PaintReaching(frame, boxes, reach);
  cv::Mat left_out;
  cv::compare(MovingMask(frame), 0, left_out, cv::CMP_NE);
  if (ScoresStillPeople()) left_out.setTo(255, ReadMask(people_folder_, frame, "people mask", people_));
  return left_out;
}

cv::Mat KeypointExclusion::DynamicPixels(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                                         std::span<const cv::KeyPoint> keypoints,
                                         std::span<const std::uint8_t> keep) const {
  cv::Mat dropped;
  if (options_.oracle) {
    cv::compare(MovingMask(frame), 0, dropped, cv::CMP_NE);  // Mark drops on any non-zero value
  } else {
    dropped = PaintDynamicBoxes(boxes.detections, boxes.decisions, frame.rgb.size());
  }
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    if (keep[i] != 0) continue;
    if (const std::optional<cv::Point> pixel = PixelOf(dropped, keypoints[i])) dropped.at<std::uint8_t>(*pixel) = 255;
  }
  return dropped;
}

}  // namespace hoidslam::pipeline
