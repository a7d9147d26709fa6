#pragma once
// Which keypoints of a frame take part in tracking: the exclusion step between ORB extraction and tracking.
// In the detector-based modes (none, person, classes, hoid2d, hoid3d) the HOID filter judges the frame's
// detections and every keypoint inside a dynamic box is dropped; mode hoidplus adds depth-refined exclusion and
// memory across frames (hoid/hoidplus.h) and turns on the SLAM core's safety net; in mode `oracle` the keypoints on the
// sequence's ground-truth moving-pixel mask (`mask/` of a synthetic sequence) are dropped instead — the upper
// bound of what any filter can do. On a sequence with masks, every mode is also scored against them: how many of
// the keypoints on moving things were kept (leaked) and how many static ones were dropped (wasted), and of the
// wasted ones how many the rules of hoidplus drop anyway (no depth; a person standing still, from `people/`).

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include <optional>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/detection.h"
#include "hoidslam/core/frame.h"
#include "hoidslam/core/options.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/hoid/filter.h"
#include "hoidslam/hoid/hoidplus.h"

namespace hoidslam::pipeline {

struct ExclusionOptions {
  core::HoidOptions hoid;  // the mode and rules of the detector-based modes
  bool oracle = false;     // drop the ground-truth moving pixels instead; detections are then only logged

  // "none", "person", "classes", "hoid2d", "hoid3d", "hoidplus" (all three parts), "hoidplus:depth+memory" (the
  // parts named) or "oracle", as `--filter` takes it.
  std::string ModeName() const;
  // Whether the mode needs a detector's boxes.
  bool NeedsDetections() const { return !oracle && hoid.mode != core::FilterMode::kNone; }
  // Whether the SLAM core's safety net is on (mode hoidplus with its net part).
  bool SafetyNet() const { return !oracle && hoid.mode == core::FilterMode::kHoidPlus && hoid.plus.safety_net; }
};

// Parses a `--filter` value into `options` (the mode; "hoidplus" keeps the parts HOIDplus.* switches on, all three
// by default, and "hoidplus:depth", "hoidplus:memory+net" turn on only the parts named, from depth, memory and
// net; the HOID rules stay).
// Throws InputError naming `parameter`.
void SetFilterMode(std::string_view text, ExclusionOptions& options, const std::string& parameter = "--filter");

// A frame's keypoints counted against the ground-truth moving mask.
struct ExclusionCounts {
  std::size_t moving_kept = 0;     // leaked: on something moving, yet used for tracking
  std::size_t moving_dropped = 0;
  std::size_t static_kept = 0;
  std::size_t static_dropped = 0;  // wasted: on the static world, yet dropped
  // Of those, the ones the rules of hoidplus (docs/hoidplus.md) drop whatever its depth test does, each counted
  // once: keypoints without valid depth (inside a dynamic box they stay dropped) and, with depth, people standing
  // still (static in the moving mask, yet a person stays excluded). The rest was dropped although its depth could
  // have set it apart.
  std::size_t static_dropped_without_depth = 0;
  std::size_t static_dropped_on_still_people = 0;  // with valid depth; 0 unless the sequence has people/ masks

  // Shares in [0, 1]; 0 when there is nothing to share.
  double Leaked() const;
  double Wasted() const;
  ExclusionCounts& operator+=(const ExclusionCounts& other);
};

// How far beyond what tracking drops the static map leaves out, for hoidplus with depth (dense::DenseOptions has
// the defaults and the reasons). A parameter of the map rather than of the filter: tracking needs the keypoints
// next to a person now, the map keeps a ghost for good and sees what is next to the person from other views.
struct StaticMapReach {
  double depth_extent = 0.0;  // m behind each foreground's median, inside the box
  double box_margin = 0.0;    // share of a dynamic box's width and height on each side, as far as tracking's cut
};

// Whether a keypoint lies on a marked pixel of `mask` (CV_8U, non-zero = marked): the pixel its position rounds
// to. The oracle drops and the scoring counts by this one rule.
bool OnMask(const cv::Mat& mask, const cv::KeyPoint& keypoint);

// One run's exclusion, frame after frame (mode hoidplus remembers earlier frames: one instance per run, frames in
// order).
class KeypointExclusion {
 public:
  // `sequence_root`: where an oracle looks for mask/; `camera`: the sequence's (hoidplus places objects with it).
  // Throws InputError when the options fail Check(), or for oracle when the folder has no mask/ folder.
  KeypointExclusion(const ExclusionOptions& options, const std::filesystem::path& sequence_root,
                    const core::CameraIntrinsics& camera = {});

  // keep[i] = 0 for the keypoints to drop. `boxes` gets every box judged and the filter's verdict on it (the
  // detections; for hoidplus also the boxes of tracked people the detector missed; all static in oracle mode).
  // `descriptors` (one row per keypoint, may be empty) let hoidplus carry missed boxes with their keypoints. The
  // oracle reads the mask named like the frame's colour image. Throws InputError naming the mask file when it is
  // missing or not the frame's size.
  void Mark(const core::RgbdFrame& frame, std::span<const core::Detection> detections,
            std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors, std::vector<std::uint8_t>& keep,
            hoid::JudgedBoxes& boxes);
  // The pose tracking found for the frame last marked (nullopt: not tracked); hoidplus's memory needs it.
  void AfterTracking(const std::optional<core::Pose>& T_cw);
  // The pixels the frame last marked drops, CV_8UC1 255 = dropped (not for oracle, whose mask is its own):
  // the dynamic boxes, or for hoidplus with depth their foreground regions.
  cv::Mat PaintDropped(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes) const;
  // What the static map (dense/) leaves out of the frame last marked, CV_8UC1 255 = left out: what PaintDropped
  // paints, for hoidplus with depth each region reaching as far as `reach` says where that is more than the
  // filter's own HOIDplus.depthExtent and boxMargin (a map keeps a ghost for good, tracking needs its keypoints
  // now); for oracle the moving mask and every person, still or not (people/, when the sequence has it), since
  // the static world it is measured against holds no person.
  cv::Mat StaticMapExclusion(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                             const StaticMapReach& reach) const;
  // Where the frame last marked has something dynamic, CV_8UC1 255 = dynamic: a second extraction looks for no
  // keypoint there. The dynamic boxes whole (for hoidplus too: its depth test keeps what lies behind a person, but
  // the person's outline in colour, where the depth image has the background, is no place to look for more; on
  // walking_xyz hoidplus drifted from 3.4 to 11 mm when it did), for oracle the moving mask, and the pixel every
  // keypoint `keep` drops rounds to, so that none is taken up again.
  cv::Mat DynamicPixels(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                        std::span<const cv::KeyPoint> keypoints, std::span<const std::uint8_t> keep) const;

  // Whether the sequence has ground-truth moving masks to score against.
  bool CanScore() const { return !mask_folder_.empty(); }
  // Whether it also has people masks (people/, 255 where a person is drawn, moving or not), so that Score counts
  // static_dropped_on_still_people.
  bool ScoresStillPeople() const { return !people_folder_.empty(); }
  // `keep` (from Mark) against the frame's moving mask, and its depth (valid: hoid::IsValidDepth at the pixel the
  // keypoint rounds to). Requires CanScore(); throws like Mark for a bad mask or people mask.
  ExclusionCounts Score(const core::RgbdFrame& frame, std::span<const cv::KeyPoint> keypoints,
                        std::span<const std::uint8_t> keep) const;
  // The frame's ground-truth moving mask (mask/<colour file name>, non-zero = moving). Requires CanScore(); throws
  // InputError naming the file when it is missing or not the frame's size. The last one read is kept, since Mark
  // (oracle) and Score read the same file.
  const cv::Mat& MovingMask(const core::RgbdFrame& frame) const;

 private:
  // PaintDropped with hoidplus's regions reaching as far as `reach` says (never less far than the filter's own).
  cv::Mat PaintReaching(const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                        const StaticMapReach& reach) const;
  // The last mask read from one folder (one KeypointExclusion per run: not shared across threads).
  struct CachedMask {
    std::filesystem::path path;
    cv::Mat mask;
  };
  // <folder>/<colour file name>, read once; throws like MovingMask, naming the mask `what`.
  static const cv::Mat& ReadMask(const std::filesystem::path& folder, const core::RgbdFrame& frame,
                                 const char* what, CachedMask& cache);

  ExclusionOptions options_;
  std::optional<hoid::HoidPlusFilter> plus_;  // mode hoidplus
  std::filesystem::path mask_folder_;    // empty when the sequence has no masks
  std::filesystem::path people_folder_;  // empty when it has no people masks (or no moving masks)
  mutable CachedMask moving_;
  mutable CachedMask people_;
};

}  // namespace hoidslam::pipeline
