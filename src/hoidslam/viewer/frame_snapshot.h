#pragma once
// What the viewer shows of one tracked frame: values copied from the frame and its outcome on the run's thread
// (the copies are cheap; the colour image is shared, never written again), turned into the page's JSON later, in
// the viewer's own threads and only when a page asks.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/core/frame.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/hoid/filter.h"
#include "hoidslam/pipeline/session.h"

namespace hoidslam::viewer {

struct FrameSnapshot {
  std::size_t index = 0;
  double timestamp = 0.0;
  cv::Mat image;                     // BGR, shared with the frame
  std::vector<float> keypoints;      // x0, y0, x1, y1, ... pixels
  std::vector<std::uint8_t> keep;    // per keypoint: 1 tracked, 0 dropped by the filter
  std::vector<core::Detection> detections;
  std::vector<hoid::Decision> decisions;  // per detection
  std::optional<core::Pose> T_wc;    // when tracked
  nlohmann::json entry;              // the frame's line of frames.jsonl
};

// The snapshot of a frame just tracked.
FrameSnapshot SnapshotOf(std::size_t index, const core::RgbdFrame& frame, const pipeline::FrameOutcome& outcome);

// The page's `frame` event (docs/viewer.md): the image as a JPEG of `image_scale` times the size (the keypoints and
// boxes stay in the frame's pixels), and the frames per second the run goes at.
std::string FrameEventJson(const FrameSnapshot& snapshot, double fps, double image_scale, int jpeg_quality);

}  // namespace hoidslam::viewer
