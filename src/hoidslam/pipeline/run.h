#pragma once
// One SLAM run over a sequence, frame by frame: load → ORB extraction → detector → exclusion (HOID filter or
// oracle mask) → a second extraction outside what is dynamic (KeypointBudget) → tracking (local mapping beside
// it), with every stage timed and every frame logged. What `hoidslam run` executes; the CLI only parses options
// around it.
//
// Outputs, in the folder given (each file complete or absent):
//   trajectory.txt  every frame tracked in the main map, TUM format, camera-to-world (lost frames left out)
//   keyframes.txt   the main map's keyframes, TUM format
//   map.ply         the main map's points, coloured
//   trajectory-map<id>.txt  the frames tracked in each other map never merged into the main one (slam::System::Maps:
//                   tracking lost long in new ground starts a map of its own world frame)
//   frames.jsonl    one JSON object per frame: state (and why a lost frame was lost), features extracted /
//                   dropped / kept for tracking / matched / inliers, the dynamic detections with their reasons
//                   (hoidplus: every box, with track, carry and foreground depth, and the map points its safety
//                   net erased), time of each stage, and on a sequence with ground-truth moving masks the
//                   keypoints kept and dropped on moving and static pixels (docs/slam.md has the schema)
//   snapshots/      a few frames drawn as the filter saw them: boxes coloured by the HOID decision, keypoints
//                   kept (green) and dropped (red); named by frame index, 000123.jpg

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hoidslam/detect/detector.h"
#include "hoidslam/hoid/late_detections.h"
#include "hoidslam/io/rgbd_sequence.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/pipeline/exclusion.h"
#include "hoidslam/slam/system.h"

namespace hoidslam::pipeline {

class Playback;
class Session;
struct FrameOutcome;

// How the detector keeps pace with tracking (docs/realtime.md).
struct RealTimeOptions {
  // The detector in its own thread: each frame is judged by the newest detections there are, carried from the
  // frame the detector saw to this one (hoid/late_detections.h), and tracking never waits for them, but for the
  // first frame's. Off: every frame waits for its own detections (reproducible, for benchmarks).
  bool enabled = false;
  // Frames arrive at their recorded rate, as from a live camera; those that come while the system is busy are
  // dropped (live_pacing.h). Off: every frame is processed, as fast as it goes.
  bool pace = false;
  // How much memory the frames a paced replay decodes ahead may take (paced_replay.h); the clock stops while a
  // further chunk is decoded. 2 GiB holds about 1,000 frames of 640×480.
  std::size_t preload_megabytes = 2048;
  // Every detection takes at least this long (ms): a simulated network latency, for a detections file.
  double detector_latency_ms = 0.0;
  hoid::LateDetectionOptions late_detections;

  // Throws InputError naming the parameter (--preload-mb, --detector-latency) when out of range.
  void Check() const;
};

// Where a frame's keypoint budget (ORBextractor.nFeatures) goes.
enum class KeypointBudget {
  // To what the filter keeps: once it has dropped people and what they carry, the frame is extracted again outside
  // the pixels it dropped (slam::System::ExtractOutside), so that a frame full of people still gets about the
  // whole budget on the static world. The dropped keypoints stay in the log and the scoring, never in tracking.
  kStatic,
  // Over the whole image, as ORB-SLAM spreads it; what the filter drops is lost to tracking.
  kImage,
};
std::string_view ToString(KeypointBudget budget);
// "static" or "image"; throws InputError naming `parameter` for anything else.
KeypointBudget ParseKeypointBudget(std::string_view text, const std::string& parameter);

struct RunOptions {
  slam::SystemOptions system;
  ExclusionOptions exclusion;
  RealTimeOptions realtime;
  KeypointBudget keypoint_budget = KeypointBudget::kStatic;
  std::size_t max_frames = 0;  // 0: the whole sequence
  std::size_t snapshots = 6;   // annotated frames written, evenly spread over the run
  // Where the final map is written as a map file (slam/map_file.h); empty: nowhere.
  std::filesystem::path save_map;
  // The depth images' units a metre (DepthMapFactor) and whether the first frame's depth is checked against a
  // room's (Depth.checkUnits, pipeline/depth_units.h).
  double depth_factor = 5000.0;
  bool check_depth_units = true;
  // Where the settings came from and why (io::SettingsChoice::Describe), said when the run starts and in the
  // message about an image of another size.
  std::string settings_source = "the default settings";

  // The camera, depth, ORB and HOID settings of a settings file; the rest at their defaults.
  static RunOptions FromSettings(const io::Settings& settings);
  // Throws InputError naming the parameter: the system's and real-time options, and the real-time mode with the
  // deterministic one (whose point, the same output on every run, the real-time mode gives up).
  void Check() const;
};

// How many frames of a sequence of `frames` a run of at most `max_frames` (0: no limit) plays.
std::size_t FramesToPlay(std::size_t max_frames, std::size_t frames);

// Throws InputError naming the colour image of `frame` when it is not of the camera's size (the settings are
// another camera's), and the settings it came from (RunOptions::settings_source). RunSequence checks every frame.
void CheckImageSize(const core::RgbdFrame& frame, const RunOptions& options);

// Milliseconds per stage of one frame. `load` is reading and decoding the images (near 0 in a paced replay, which
// decodes ahead). `detect` is what tracking spent on the detections: waiting for the detector
// (all of its time in the synchronous mode, the first frame's only in the real-time mode) and carrying late boxes.
struct StageTimes {
  double load = 0, extract = 0, detect = 0, filter = 0, track = 0;
  // What the budget counts as tracking a frame: extraction, filter and tracking (detector excluded).
  double TrackingTotal() const { return extract + filter + track; }
};

struct RunSummary {
  std::size_t frames = 0;            // frames processed
  std::size_t tracked = 0;           // in any map (trajectory.txt holds the main map's), provisionally or not
  std::size_t lost = 0;              // after initialisation, not tracked
  // Tracked provisionally after a loss, then withdrawn when the frames after refuted the pose (counted lost, not
  // tracked; slam/tracker.h).
  std::size_t withdrawn = 0;
  std::size_t before_initialization = 0;  // before the map could start (too few keypoints with depth)
  std::size_t keyframes = 0;
  std::size_t map_points = 0;
  std::size_t detector_failures = 0;  // frames whose detections could not be had (the previous ones were used)
  std::size_t keypoints_extracted = 0;  // by the first extraction, over the whole image
  std::size_t keypoints_dropped = 0;    // of those, by the filter
  std::size_t keypoints_tracked = 0;    // handed to tracking: the rest, or those of the extraction outside the drops
  std::size_t moving_points = 0;     // map points the safety net erased (hoidplus)
  std::size_t dropped = 0;           // frames a paced run passed over, arriving while the system was busy
  std::vector<double> relocalized;   // stamps of the frames relocalisation found again after a loss (not withdrawn)
  std::vector<slam::LoopClosure> loops;   // closed, in order
  std::vector<slam::LoopClosure> merges;  // of two maps, in order
  std::vector<slam::MapSummary> maps;     // with tracked frames, by id
  slam::MapId main_map = 0;
  slam::LoopCloser::Timings loop_timings;
  double final_adjustment_ms = 0.0;  // System::FinalAdjustmentMilliseconds
  std::vector<StageTimes> times;     // one per frame
  // Per frame judged by detections: how many frames and ms (of the recording) the detections were older than the
  // frame, and how long the detector took on them, waiting included.
  std::vector<std::size_t> detection_age_frames;
  std::vector<double> detection_age_ms;
  std::vector<double> detector_ms;
  std::size_t boxes_carried_by_keypoints = 0;  // late boxes moved by their keypoints' motion
  std::size_t boxes_grown = 0;                 // late boxes grown, with too few keypoint matches
  double seconds = 0.0;              // wall-clock time of the frame loop, less a paced replay's decoding holds
  std::optional<ExclusionCounts> exclusion;  // over all frames, when the sequence has ground-truth moving masks
  bool still_people_scored = false;  // it also has people masks: exclusion's static_dropped_on_still_people counts
  bool interrupted = false;          // stopped early by the caller; the outputs hold the frames done
  std::string vocabulary_identity;   // of the vocabulary place recognition used (slam::System::VocabularyIdentity)
};

// The name of the trajectory file of a map other than the main one: trajectory-map<id>.txt.
std::string OtherMapTrajectoryName(slam::MapId map);

// Asks `detector` for the frame's boxes. When it fails, `detections` keeps the previous frame's boxes (the people
// seen a frame ago are the best guess for this one), the failure is logged, and its message is returned.
std::optional<std::string> DetectOrKeepPrevious(detect::Detector& detector, const core::RgbdFrame& frame,
                                                std::size_t index, std::vector<core::Detection>& detections);

// What a caller may follow and steer of a run (a viewer, Ctrl-C); every member is optional and none slows a run
// that leaves it empty.
struct RunHooks {
  // Polled between frames (and while a paced run or a paused playback waits).
  std::function<bool()> stop_requested{};
  // Pause, step and speed of a run that is not paced; ignored by a paced one, whose clock is the recording's.
  Playback* playback = nullptr;
  // Called on the run's thread: when the session exists (it lives until `finished` returns), after each frame
  // tracked (the frame and its outcome are valid during the call), and once the outputs are written — or, when the
  // run throws, before the session goes.
  std::function<void(const Session&)> started{};
  std::function<void(std::size_t index, const core::RgbdFrame&, const FrameOutcome&)> frame_tracked{};
  std::function<void(const Session&)> finished{};
};

// Runs `sequence` and writes the outputs into `folder` (which must exist). Throws InputError for unreadable input
// (naming the file); a detector that fails on one frame is logged, and the frame uses the newest detections there
// are, carried to it like late ones.
RunSummary RunSequence(const io::RgbdSequence& sequence, detect::Detector& detector, const RunOptions& options,
                       const std::filesystem::path& folder, const RunHooks& hooks = {});

}  // namespace hoidslam::pipeline
