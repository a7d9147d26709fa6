#pragma once
// One SLAM run over a sequence, frame by frame: load → ORB extraction → detector → exclusion (HOID filter or
// oracle mask) → tracking (local mapping beside it), with every stage timed and every frame logged. What
// `hoidslam run` executes; the CLI only parses options around it.
//
// Outputs, in the folder given (each file complete or absent):
//   trajectory.txt  every tracked frame, TUM format, camera-to-world (lost frames left out)
//   keyframes.txt   the keyframes, TUM format
//   map.ply         the sparse map, coloured
//   frames.jsonl    one JSON object per frame: state, features extracted / dropped / matched / inliers, the
//                   dynamic detections with their reasons (hoidplus: every box, with track, carry and
//                   foreground depth, and the map points its safety net erased), time of each stage, and on a sequence with
//                   ground-truth moving masks the keypoints kept and dropped on moving and static pixels
//                   (docs/slam.md has the schema)
//   snapshots/      a few frames drawn as the filter saw them: boxes coloured by the HOID decision, keypoints
//                   kept (green) and dropped (red); named by frame index, 000123.jpg

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hoidslam/detect/detector.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/pipeline/exclusion.h"
#include "hoidslam/slam/system.h"

namespace hoidslam::pipeline {

struct RunOptions {
  slam::SystemOptions system;
  ExclusionOptions exclusion;
  std::size_t max_frames = 0;  // 0: the whole sequence
  std::size_t snapshots = 6;   // annotated frames written, evenly spread over the run

  // The camera, depth, ORB and HOID settings of a settings file; the rest at their defaults.
  static RunOptions FromSettings(const io::Settings& settings);
};

// Milliseconds per stage of one frame.
struct StageTimes {
  double load = 0, extract = 0, detect = 0, filter = 0, track = 0;
  // What the budget counts as tracking a frame: extraction, filter and tracking (detector excluded).
  double TrackingTotal() const { return extract + filter + track; }
};

struct RunSummary {
  std::size_t frames = 0;            // frames processed
  std::size_t tracked = 0;           // in trajectory.txt
  std::size_t lost = 0;              // after initialisation, not tracked
  std::size_t before_initialization = 0;  // before the map could start (too few keypoints with depth)
  std::size_t keyframes = 0;
  std::size_t map_points = 0;
  std::size_t detector_failures = 0;  // frames whose detections could not be had (the previous ones were used)
  std::size_t keypoints_extracted = 0;
  std::size_t keypoints_dropped = 0;
  std::size_t moving_points = 0;     // map points the safety net erased (hoidplus)
  std::vector<StageTimes> times;     // one per frame
  std::optional<ExclusionCounts> exclusion;  // over all frames, when the sequence has ground-truth moving masks
  bool interrupted = false;          // stopped early by the caller; the outputs hold the frames done
};

// Asks `detector` for the frame's boxes. When it fails, `detections` keeps the previous frame's boxes (the people
// seen a frame ago are the best guess for this one), the failure is logged, and its message is returned.
std::optional<std::string> DetectOrKeepPrevious(detect::Detector& detector, const core::RgbdFrame& frame,
                                                std::size_t index, std::vector<core::Detection>& detections);

// Runs `sequence` and writes the outputs into `folder` (which must exist). `stop_requested` is polled between
// frames. Throws InputError for unreadable input (naming the file); a detector that fails on one frame is logged
// and the frame uses the previous frame's detections.
RunSummary RunSequence(const io::RgbdSequence& sequence, detect::Detector& detector, const RunOptions& options,
                       const std::filesystem::path& folder, const std::function<bool()>& stop_requested = {});

}  // namespace hoidslam::pipeline
