#pragma once
// The per-frame work of a SLAM run: ORB extraction → detections → exclusion (HOID filter or oracle mask) → a
// second extraction outside what is dynamic (KeypointBudget) → tracking, with the frame's log entry and the run's
// counts. `hoidslam run` (run.h) feeds it a sequence's frames, the public API (hoidslam.h) a program's frames:
// one code path, so the same frames give the same trajectory whichever way they come in.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "hoidslam/core/detection.h"
#include "hoidslam/core/frame.h"
#include "hoidslam/detect/detector.h"
#include "hoidslam/hoid/hoidplus.h"
#include "hoidslam/pipeline/exclusion.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/slam/system.h"

namespace hoidslam::pipeline {

// What one frame went through.
struct FrameOutcome {
  slam::TrackResult result;
  // The keypoints judged: those of the first extraction the filter dropped (keep 0) or kept on something dynamic,
  // then those tracked; with KeypointBudget::kImage simply the first extraction's.
  slam::ExtractedFeatures features;
  std::vector<std::uint8_t> keep;  // per keypoint: 1 handed to tracking, 0 dropped by the filter
  hoid::JudgedBoxes boxes;         // every box judged, with the verdict and reason
  std::size_t extracted = 0;       // keypoints of the first extraction, over the whole image
  std::size_t dropped = 0;         // of those, dropped by the filter
  StageTimes times;
  nlohmann::json entry;  // the frame's line of frames.jsonl (run.h)
};

class Session {
 public:
  // `detector` gives the frames' boxes when they do not come with their own (it may be null when every frame
  // brings its boxes, or the mode needs none) and is used until Finish. `sequence_root` is where mode oracle looks
  // for mask/ (empty: frames of no folder). Throws InputError when the options fail Check(), and as
  // KeypointExclusion does.
  Session(const RunOptions& options, detect::Detector* detector, const std::filesystem::path& sequence_root);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Frame `index` (frames in order, indices increasing). `detections`: the frame's own boxes, judged instead of
  // the detector's (null: the detector's). `load_ms` and `dropped_before` (frames a paced run passed over) go into
  // the log and the counts. The outcome stays valid until the next call. Throws InputError naming `detections`
  // when the mode needs boxes and neither a detector nor the frame gives them; throws core::Error after Finish.
  const FrameOutcome& Track(std::size_t index, const core::RgbdFrame& frame,
                            const std::vector<core::Detection>* detections = nullptr, double load_ms = 0.0,
                            std::size_t dropped_before = 0);

  // Stops the detector thread (the detector is the caller's again), lets local mapping finish and makes the final
  // adjustment when the options ask for it: the trajectory and the map are final. Idempotent.
  void Finish();
  bool finished() const { return finished_; }
  // Writes trajectory.txt, keyframes.txt and map.ply (run.h) into `folder` (which must exist), each file complete
  // or absent, and counts the keyframes and map points into the summary. Call after Finish for the final map.
  void WriteOutputs(const std::filesystem::path& folder);

  // What the static map leaves out of the frame last tracked, its regions reaching as far as `reach` says
  // (KeypointExclusion::StaticMapExclusion).
  cv::Mat StaticMapExclusion(const core::RgbdFrame& frame, const StaticMapReach& reach) const;

  RunSummary& summary() { return summary_; }
  const RunSummary& summary() const { return summary_; }
  const slam::System& system() const { return *system_; }
  const RunOptions& options() const { return options_; }

 private:
  class Detections;

  RunOptions options_;
  KeypointExclusion exclusion_;
  std::unique_ptr<slam::System> system_;
  RunSummary summary_;
  std::unique_ptr<Detections> detections_;  // the detector thread, when there is a detector and boxes are needed
  FrameOutcome outcome_;
  std::vector<double> tracked_stamps_;  // of every frame handed to tracking, by its id there (slam::Frame::id)
  bool finished_ = false;
  bool depth_judged_ = false;  // the depth's unit, on the first frame with enough of it (depth_units.h)
};

}  // namespace hoidslam::pipeline
