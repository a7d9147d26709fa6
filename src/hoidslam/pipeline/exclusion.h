#pragma once
// Which keypoints of a frame take part in tracking: the exclusion step between ORB extraction and tracking.
// In the detector-based modes (none, person, classes, hoid2d, hoid3d) the HOID filter judges the frame's
// detections and every keypoint inside a dynamic box is dropped; in mode `oracle` the keypoints on the
// sequence's ground-truth moving-pixel mask (`mask/` of a synthetic sequence) are dropped instead — the upper
// bound of what any filter can do. On a sequence with masks, every mode is also scored against them: how many of
// the keypoints on moving things were kept (leaked) and how many static ones were dropped (wasted).

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/core/frame.h"
#include "hoidslam/core/options.h"
#include "hoidslam/hoid/filter.h"

namespace hoidslam::pipeline {

struct ExclusionOptions {
  core::HoidOptions hoid;  // the mode and rules of the detector-based modes
  bool oracle = false;     // drop the ground-truth moving pixels instead; detections are then only logged

  // "none", "person", "classes", "hoid2d", "hoid3d" or "oracle", as `--filter` takes it.
  std::string_view ModeName() const;
  // Whether the mode needs a detector's boxes.
  bool NeedsDetections() const { return !oracle && hoid.mode != core::FilterMode::kNone; }
};

// Parses a `--filter` value into `options` (the mode; the HOID rules stay). Throws InputError naming `parameter`.
void SetFilterMode(std::string_view text, ExclusionOptions& options, const std::string& parameter = "--filter");

// A frame's keypoints counted against the ground-truth moving mask.
struct ExclusionCounts {
  std::size_t moving_kept = 0;     // leaked: on something moving, yet used for tracking
  std::size_t moving_dropped = 0;
  std::size_t static_kept = 0;
  std::size_t static_dropped = 0;  // wasted: on the static world, yet dropped

  // Shares in [0, 1]; 0 when there is nothing to share.
  double Leaked() const;
  double Wasted() const;
  ExclusionCounts& operator+=(const ExclusionCounts& other);
};

// Whether a keypoint lies on a marked pixel of `mask` (CV_8U, non-zero = marked): the pixel its position rounds
// to. The oracle drops and the scoring counts by this one rule.
bool OnMask(const cv::Mat& mask, const cv::KeyPoint& keypoint);

class KeypointExclusion {
 public:
  // `sequence_root`: where an oracle looks for mask/. Throws InputError when the options fail Check(), or for
  // oracle when the folder has no mask/ folder.
  KeypointExclusion(const ExclusionOptions& options, const std::filesystem::path& sequence_root);

  // keep[i] = 0 for the keypoints to drop. `decisions` gets the HOID filter's verdict on every detection (all
  // static in oracle mode). `rgb_path` names the frame's colour image, whose mask the oracle reads. Throws
  // InputError naming the mask file when it is missing or not the frame's size.
  void Mark(const core::RgbdFrame& frame, std::span<const core::Detection> detections,
            std::span<const cv::KeyPoint> keypoints, std::vector<std::uint8_t>& keep,
            std::vector<hoid::Decision>& decisions) const;

  // Whether the sequence has ground-truth moving masks to score against.
  bool CanScore() const { return !mask_folder_.empty(); }
  // `keep` (from Mark) against the frame's moving mask. Requires CanScore(); throws like Mark for a bad mask.
  ExclusionCounts Score(const core::RgbdFrame& frame, std::span<const cv::KeyPoint> keypoints,
                        std::span<const std::uint8_t> keep) const;
  // The frame's ground-truth moving mask (mask/<colour file name>, non-zero = moving). Requires CanScore(); throws
  // InputError naming the file when it is missing or not the frame's size. The last one read is kept, since Mark
  // (oracle) and Score read the same file.
  const cv::Mat& MovingMask(const core::RgbdFrame& frame) const;

 private:
  ExclusionOptions options_;
  std::filesystem::path mask_folder_;  // empty when the sequence has no masks
  mutable std::filesystem::path cached_mask_path_;  // one KeypointExclusion per run: not shared across threads
  mutable cv::Mat cached_mask_;
};

}  // namespace hoidslam::pipeline
