#pragma once
// Mode hoidplus (docs/hoidplus.md): the HOID rule at its core, and what no box-based filter combines:
//   1. depth-refined exclusion: inside a dynamic box only its foreground (foreground.h) is dropped, and the
//      object–person interaction is confirmed by their foreground depths instead of two 20×20 centre patches;
//   2. memory across frames: detections are tracked from frame to frame (box overlap plus class). A confirmed
//      track the detector misses stays excluded for a while, its box carried by the motion of its own keypoints;
//      an object a person handles (by the HOID rule) stays dynamic until it has been seen still in the world for a
//      set time (so one a person merely passes is released once its stillness is known); a person is dynamic
//      however still they stand; a class the detector confuses for a moment is outvoted;
//   3. a geometric safety net for what no detector saw: in the SLAM core (slam::TrackerOptions).
// Parts 1 and 2 live here, switched by core::HoidPlusOptions. The filter is the one stateful part of the
// exclusion: one instance per run, fed every frame in order, and told each frame's pose after tracking.

#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/detection.h"
#include "hoidslam/core/options.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/hoid/filter.h"
#include "hoidslam/hoid/foreground.h"
#include "hoidslam/hoid/keypoint_motion.h"

namespace hoidslam::hoid {

// What hoidplus knows about a judged box besides the verdict.
struct BoxContext {
  std::uint64_t track = 0;                 // its track (memory on; ids start at 1), 0 without memory
  int missed_frames = 0;                   // frames since the detector last saw it (0: a detection of this frame)
  Carry carry = Carry::kNone;
  std::optional<DepthCluster> foreground;  // depth refinement on and the box held valid depth
  ExclusionRegion region;                  // where keypoints were dropped (dynamic boxes): the box, grown with
                                           // depth refinement, and the foreground's cut
};

// Every box judged on one frame: the detector's detections in their order (labels as the track decided), then
// the boxes of confirmed tracks the detector missed. The three vectors run in parallel; context is empty in the
// modes without memory or depth (filled by HoidPlusFilter only).
struct JudgedBoxes {
  std::vector<core::Detection> detections;
  std::vector<Decision> decisions;
  std::vector<BoxContext> context;
};

// The exclusion regions of the dynamic boxes (from their context; empty without context).
std::vector<ExclusionRegion> DynamicRegions(const JudgedBoxes& boxes);

class HoidPlusFilter {
 public:
  // `camera` places objects in the world for the stillness test. Throws core::InputError when the options fail
  // Check().
  HoidPlusFilter(const core::HoidOptions& options, const core::CameraIntrinsics& camera);

  // Judges one frame (timestamps increase) and marks keep[i] = 0 for the keypoints to drop. `depth` is CV_32FC1
  // metres (may be empty: no depth refinement then); `descriptors` has one ORB row per keypoint (may be empty:
  // missed boxes are then carried by velocity only).
  void Filter(double timestamp, const cv::Mat& depth, std::span<const core::Detection> detections,
              std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors, JudgedBoxes& boxes,
              std::vector<std::uint8_t>& keep);

  // The pose tracking found for the frame last filtered (nullopt: lost), so that objects are placed in the world.
  void Localize(const std::optional<core::Pose>& T_cw);

 private:
  struct Track {
    std::uint64_t id = 0;
    std::vector<std::pair<std::string, int>> label_votes;  // detections per label
    std::string label;                                     // the label with the most votes (first on ties)
    cv::Rect2f box;
    double last_detected = 0.0;
    double last_updated = 0.0;
    int hits = 0;
    int missed_frames = 0;
    cv::Point2f velocity{0.0F, 0.0F};  // of the box centre, pixels per second
    bool handled = false;              // an object a person handled, not yet seen still for still_seconds
    double last_handled = -std::numeric_limits<double>::infinity();  // when the HOID rule last said so
    std::deque<std::pair<double, Eigen::Vector3d>> positions;  // in the world, over the last still_seconds
    std::optional<Eigen::Vector3d> pending_position;          // this frame's, in the camera, until Localize

    void Vote(const std::string& vote);
  };

  // Continues tracks with the frame's detections; fills boxes.detections (and track ids in context) with the
  // detections then the carried boxes of confirmed tracks the detector missed.
  void Associate(double timestamp, std::span<const core::Detection> detections,
                 std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors, JudgedBoxes& boxes);
  // Where a missed track's box is now: moved by its dropped keypoints' motion from the last frame, else by velocity.
  std::pair<cv::Rect2f, Carry> CarryBox(const Track& track, double dt, std::span<const cv::KeyPoint> keypoints,
                                        const cv::Mat& descriptors) const;
  // Box i's foreground, found once a frame and kept in its context; none when `depth` is empty.
  const std::optional<DepthCluster>& Foreground(const cv::Mat& depth, JudgedBoxes& boxes, std::size_t i) const;
  // The object–person depth test on the 2D interactions, with the foregrounds in context.
  void ConfirmByDepth(const cv::Mat& depth, JudgedBoxes& boxes) const;
  // The verdicts memory changes: missed persons and handled objects. `refining_depth` is `depth` when depth
  // refinement is on (objects are then placed at their foreground), else empty (placed by the centre patch).
  void ApplyMemory(double timestamp, const cv::Mat& depth, const cv::Mat& refining_depth, JudgedBoxes& boxes);
  bool SeenStill(const Track& track, double timestamp) const;
  Track* FindTrack(std::uint64_t id);

  core::HoidOptions options_;
  core::CameraIntrinsics camera_;
  std::vector<Track> tracks_;
  std::uint64_t next_track_id_ = 1;
  double last_timestamp_ = 0.0;
  bool has_last_frame_ = false;
  // The last frame's keypoints, descriptors and verdicts, to carry missed boxes by their keypoints' motion.
  std::vector<cv::Point2f> last_points_;
  cv::Mat last_descriptors_;
  std::vector<std::uint8_t> last_keep_;
};

}  // namespace hoidslam::hoid
