#pragma once
// Detections that arrive late. In the real-time mode the detector runs in its own thread and tracking never
// waits for it, so the newest detections are of a frame some way back. Before they judge the frame being
// tracked, each box is carried to it: moved by the median motion, since the frame the detector saw, of the
// keypoints inside it (keypoint_motion.h); with too few keypoint matches, left in place and grown by what it may
// have moved since. The keypoints of recent frames are kept for this, back to the frame of the newest detections.

#include <cstddef>
#include <deque>
#include <span>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/hoid/keypoint_motion.h"

namespace hoidslam::hoid {

struct LateDetectionOptions {
  // A box carried without keypoint matches grows on each side by this share of its size for every frame of age.
  // A person crossing the view at 1 m/s, 2 m away, moves about 4 % of the width of their box in a 30 Hz frame.
  double grow_per_frame = 0.04;
  double max_grow = 0.5;        // and by at most this share
  // Keypoint matches for a box are looked for in the box grown by this share on each side, and by
  // grow_per_frame more for every frame of age.
  double search_margin = 0.5;
  // A keypoint's match is looked for within this many pixels of where it was, plus max_motion_per_frame for
  // every frame of age: a fast camera turn moves the image by about 15 px a 30 Hz frame.
  double max_motion = 30.0;
  double max_motion_per_frame = 15.0;
  std::size_t max_frames = 300;  // frames whose keypoints are kept at most (10 s at 30 Hz); older ones are let go

  // Throws core::InputError naming the option when one is out of range.
  void Check() const;
};

// A detection placed on a later frame, and how.
struct CarriedDetection {
  core::Detection detection;
  Carry carry = Carry::kNone;
};

class LateDetections {
 public:
  // `image_size`: carried boxes are clipped to it (a box carried out of the image is left out). Throws
  // core::InputError when the options fail Check().
  explicit LateDetections(cv::Size image_size, const LateDetectionOptions& options = {});

  // Keeps frame `index`'s keypoints and their descriptors (one ORB row each; may be empty, and then boxes are
  // grown) for detections of it that come later. Frames come in increasing order.
  void Remember(std::size_t index, std::span<const cv::KeyPoint> keypoints, const cv::Mat& descriptors);

  // `detections` of frame `from` placed on frame `to` (from ≤ to, both remembered; a frame no longer remembered
  // counts as having no keypoints). Detections come in frame order, so the frames before `from` are let go.
  std::vector<CarriedDetection> Carry(std::size_t from, std::span<const core::Detection> detections, std::size_t to);

  // Frames remembered now.
  std::size_t frames() const { return frames_.size(); }

 private:
  struct RememberedFrame {
    std::size_t index = 0;
    std::vector<cv::Point2f> points;
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
  };
  const RememberedFrame* Find(std::size_t index) const;

  cv::Size image_size_;
  LateDetectionOptions options_;
  std::deque<RememberedFrame> frames_;
};

}  // namespace hoidslam::hoid
