#include "hoidslam/pipeline/run.h"

#include <cmath>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/hoid/explain.h"
#include "hoidslam/report/annotate.h"
#include "hoidslam/pipeline/detector_thread.h"
#include "hoidslam/pipeline/paced_replay.h"

namespace hoidslam::pipeline {
namespace {

// `value` to `decimals` places, so the log prints 3.687 rather than 3.6870000000000003.
double Round(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

// The judged boxes with `dynamic` as their verdict, with their reasons (and, for hoidplus, what memory and
// depth added).
nlohmann::json JudgedBoxList(const hoid::JudgedBoxes& boxes, bool dynamic) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    const hoid::Decision& decision = boxes.decisions[i];
    if (decision.dynamic != dynamic) continue;
    const core::Detection& d = boxes.detections[i];
    nlohmann::json entry = {{"label", d.label},
                            {"score", Round(d.score, 3)},
                            {"box", {Round(d.box.x, 1), Round(d.box.y, 1), Round(d.box.width, 1),
                                     Round(d.box.height, 1)}},
                            {"reason", hoid::ToString(decision.reason)}};
    if (decision.person_index >= 0 && decision.person_index != static_cast<int>(i)) {
      entry["person"] = decision.person_index;
      entry["interaction"] = Round(decision.interaction_ratio, 3);
    }
    if (!std::isnan(decision.depth_difference)) entry["depth_difference"] = Round(decision.depth_difference, 3);
    if (i < boxes.context.size()) {
      const hoid::BoxContext& context = boxes.context[i];
      if (context.track != 0) entry["track"] = context.track;
      if (context.missed_frames > 0) {
        entry["missed_frames"] = context.missed_frames;
        entry["carried_by"] = hoid::ToString(context.carry);
      }
      if (dynamic && context.foreground) {
        entry["foreground"] = {Round(context.foreground->near, 3), Round(context.foreground->far, 3)};
        entry["kept_beyond"] = Round(context.region.cut, 3);
      }
    }
    list.push_back(std::move(entry));
  }
  return list;
}

// Whether frame `index` of `total` is one of `count` snapshots: the middles of `count` equal parts of the run.
bool IsSnapshot(std::size_t index, std::size_t total, std::size_t count) {
  for (std::size_t k = 0; k < count && k < total; ++k) {
    if ((2 * k + 1) * total / (2 * count) == index) return true;
  }
  return false;
}

void WriteSnapshot(const std::filesystem::path& path, const core::RgbdFrame& frame, const hoid::JudgedBoxes& boxes,
                   const std::vector<cv::KeyPoint>& keypoints, const std::vector<std::uint8_t>& keep) {
  std::vector<report::BoxAnnotation> annotations;
  annotations.reserve(boxes.detections.size());
  for (std::size_t i = 0; i < boxes.detections.size(); ++i) {
    annotations.push_back({boxes.detections[i].box, hoid::CaptionDecision(boxes.detections[i], boxes.decisions[i]),
                           boxes.decisions[i].dynamic});
  }
  cv::Mat image = report::DrawBoxAnnotations(frame.rgb, annotations);
  report::DrawKeptAndDropped(image, keypoints, keep);
  io::WriteImageAtomically(path, image);
}

// The detections each frame is judged by. Frames go to the detector thread; the synchronous mode waits for each
// frame's own detections, the real-time mode for the first frame's only and then takes the newest there are. The
// newest good detections are carried to the frame (hoid/late_detections.h); a frame the detector failed on keeps
// them. Each frame's age of its detections goes into its log entry and the summary.
class FrameDetections {
 public:
  FrameDetections(detect::Detector& detector, const RunOptions& options)
      : realtime_(options.realtime.enabled),
        thread_limit_(realtime_ ? std::optional<OpenCvThreadLimit>(std::in_place) : std::nullopt),
        thread_(detector, options.realtime.detector_latency_ms),
        late_(cv::Size(options.system.camera.width, options.system.camera.height), options.realtime.late_detections) {}

  void Submit(std::size_t index, const core::RgbdFrame& frame) { thread_.Submit(index, frame.timestamp, frame.rgb); }

  // The boxes to judge frame `index` (submitted) by, and what the log and summary say of them.
  std::vector<core::Detection> For(std::size_t index, const core::RgbdFrame& frame,
                                   const slam::ExtractedFeatures& features, nlohmann::json& entry,
                                   RunSummary& summary) {
    // Without detections yet, the real-time mode waits too, so that the map does not start on the people in view.
    std::optional<DetectorResult> result =
        realtime_ && newest_ ? thread_.TakeNewest() : std::optional(thread_.WaitForNext());
    if (result && result->error) {
      // One bad frame must not end a run.
      spdlog::warn("frame {} ({:.6f}): detector failed, using the newest detections there are: {}", result->frame,
                   result->timestamp, *result->error);
      ++summary.detector_failures;
      entry["detector_error"] = *result->error;
    } else if (result) {
      newest_ = std::move(*result);
    }
    late_.Remember(index, features.keypoints, features.descriptors);
    std::vector<core::Detection> boxes;
    if (!newest_) return boxes;
    std::size_t by_keypoints = 0, grown = 0;
    for (hoid::CarriedDetection& carried : late_.Carry(newest_->frame, newest_->detections, index)) {
      by_keypoints += carried.carry == hoid::Carry::kKeypoints ? 1 : 0;
      grown += carried.carry == hoid::Carry::kGrown ? 1 : 0;
      boxes.push_back(std::move(carried.detection));
    }
    const double age_ms = (frame.timestamp - newest_->timestamp) * 1000.0;
    summary.detection_age_frames.push_back(index - newest_->frame);
    summary.detection_age_ms.push_back(age_ms);
    summary.detector_ms.push_back(newest_->milliseconds);
    summary.boxes_carried_by_keypoints += by_keypoints;
    summary.boxes_grown += grown;
    entry["detections"] = {{"frame", newest_->frame},
                           {"age_frames", index - newest_->frame},
                           {"age_ms", Round(age_ms, 1)},
                           {"detector_ms", Round(newest_->milliseconds, 1)},
                           {"carried_by_keypoints", by_keypoints},
                           {"grown", grown}};
    return boxes;
  }

 private:
  bool realtime_;
  std::optional<OpenCvThreadLimit> thread_limit_;  // before the thread: the pool is limited while it runs
  DetectorThread thread_;
  hoid::LateDetections late_;
  std::optional<DetectorResult> newest_;  // the newest good detections
};

// Spends the budget the filter freed on the static world: `features` becomes the keypoints of the first
// extraction on what is dynamic (those the filter dropped, keep 0, for the log and the scoring; those hoidplus kept
// behind a person, keep 1), then those of a second extraction outside it (keep 1).
void ExtractOutsideDynamic(slam::System& system, const KeypointExclusion& exclusion, const core::RgbdFrame& frame,
                           const hoid::JudgedBoxes& boxes, slam::ExtractedFeatures& features,
                           std::vector<std::uint8_t>& keep) {
  const cv::Mat dynamic = exclusion.DynamicPixels(frame, boxes, features.keypoints, keep);
  const slam::ExtractedFeatures outside = system.ExtractOutside(dynamic);
  slam::ExtractedFeatures merged;
  std::vector<std::uint8_t> merged_keep;
  merged.keypoints.reserve(features.keypoints.size() + outside.keypoints.size());
  merged.descriptors.reserve(features.keypoints.size() + outside.keypoints.size());
  for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
    if (keep[i] != 0 && !OnMask(dynamic, features.keypoints[i])) continue;  // the second extraction has its like
    merged.keypoints.push_back(features.keypoints[i]);
    merged.descriptors.push_back(features.descriptors.row(static_cast<int>(i)));
    merged_keep.push_back(keep[i]);
  }
  merged.keypoints.insert(merged.keypoints.end(), outside.keypoints.begin(), outside.keypoints.end());
  merged.descriptors.push_back(outside.descriptors);
  merged_keep.resize(merged.keypoints.size(), 1);
  features = std::move(merged);
  keep = std::move(merged_keep);
}

constexpr core::EnumNames<KeypointBudget, 2> kBudgetNames = {{
    {KeypointBudget::kStatic, "static"},
    {KeypointBudget::kImage, "image"},
}};

}  // namespace

std::string_view ToString(KeypointBudget budget) { return core::EnumName(kBudgetNames, budget); }

KeypointBudget ParseKeypointBudget(std::string_view text, const std::string& parameter) {
  return core::ParseEnumName(kBudgetNames, text, parameter, "keypoint budget");
}

void RealTimeOptions::Check() const {
  if (preload_megabytes < 1 || preload_megabytes > (std::size_t{1} << 20)) {
    throw core::InputError::ForParameter("--preload-mb",
                                         fmt::format("must be in [1, 1048576] MB, got {}", preload_megabytes));
  }
  if (!(detector_latency_ms >= 0.0 && detector_latency_ms <= 60000.0)) {
    throw core::InputError::ForParameter("--detector-latency",
                                         fmt::format("must be in [0, 60000] ms, got {}", detector_latency_ms));
  }
  late_detections.Check();
}

void RunOptions::Check() const {
  system.Check();
  realtime.Check();
  if (realtime.enabled && system.deterministic) {
    throw core::InputError::ForParameter(
        "--realtime", "cannot go with --deterministic: the age of the detections each frame gets depends on timing");
  }
}

RunOptions RunOptions::FromSettings(const io::Settings& settings) {
  RunOptions options;
  options.system.camera = settings.camera;
  options.system.bf = settings.bf;
  options.system.close_depth = settings.CloseDepthThreshold();
  options.system.orb = settings.orb;
  options.system.tracking.keyframe_max_interval = std::max(1, static_cast<int>(std::lround(settings.fps)));
  options.exclusion.hoid = settings.hoid;
  return options;
}

std::optional<std::string> DetectOrKeepPrevious(detect::Detector& detector, const core::RgbdFrame& frame,
                                                std::size_t index, std::vector<core::Detection>& detections) {
  try {
    detections = detector.Detect(frame.timestamp, frame.rgb);
    return std::nullopt;
  } catch (const std::exception& e) {
    spdlog::warn("frame {} ({:.6f}): detector failed, using the previous frame's detections: {}", index,
                 frame.timestamp, e.what());
    return e.what();
  }
}

RunSummary RunSequence(const io::RgbdSequence& sequence, detect::Detector& detector, const RunOptions& options,
                       const std::filesystem::path& folder, const std::function<bool()>& stop_requested) {
  options.Check();
  KeypointExclusion exclusion(options.exclusion, sequence.root(), options.system.camera);
  slam::SystemOptions system_options = options.system;
  if (options.exclusion.SafetyNet()) {
    system_options.tracking.moving_point_outliers = options.exclusion.hoid.plus.moving_point_outliers;
  }
  slam::System system(system_options);
  const RealTimeOptions& realtime = options.realtime;
  spdlog::info("{}: {} frames, filter {}, detector {}{}{}{}", sequence.name(), sequence.size(),
               options.exclusion.ModeName(), detector.Name(), realtime.enabled ? ", real time" : "",
               realtime.pace ? ", paced" : "", options.system.deterministic ? ", deterministic" : "");
  io::AtomicFile log(folder / "frames.jsonl");
  if (options.snapshots > 0) std::filesystem::create_directories(folder / "snapshots");

  const std::size_t total = options.max_frames == 0 ? sequence.size() : std::min(options.max_frames, sequence.size());
  RunSummary summary;
  summary.times.reserve(total);
  if (exclusion.CanScore()) summary.exclusion.emplace();
  summary.still_people_scored = exclusion.ScoresStillPeople();
  // A paced replay decodes its first frames before the run's clock starts, as a camera is ready before it streams.
  std::optional<PacedReplay> paced;
  if (realtime.pace) paced.emplace(sequence, total, realtime.preload_megabytes << 20);
  core::ProgressReporter progress("run", total);
  // Both modes hand frames to the detector thread: the synchronous one then waits for each frame's detections.
  std::optional<FrameDetections> detections;
  if (options.exclusion.NeedsDetections() || options.exclusion.oracle) detections.emplace(detector, options);
  hoid::JudgedBoxes boxes;
  std::vector<std::uint8_t> keep;
  const core::Stopwatch run_clock;
  for (std::optional<std::size_t> previous; true;) {
    const std::optional<std::size_t> next =
        paced ? paced->Next(previous, stop_requested) : std::optional(previous ? *previous + 1 : 0);
    if (stop_requested && stop_requested()) {
      summary.interrupted = true;
      break;
    }
    if (!next || *next >= total) break;
    const std::size_t index = *next;
    const std::size_t dropped_before = paced ? paced->dropped() - summary.dropped : 0;
    summary.dropped += dropped_before;
    previous = index;

    StageTimes times;
    core::Stopwatch clock;
    const core::RgbdFrame frame = paced ? paced->Take(index) : sequence.LoadFrame(index);
    times.load = clock.ElapsedMilliseconds();
    if (detections) detections->Submit(index, frame);

    clock.Restart();
    slam::ExtractedFeatures features = system.Extract(frame.rgb);
    times.extract = clock.ElapsedMilliseconds();

    nlohmann::json entry = {{"frame", index}, {"timestamp", frame.timestamp}};
    if (dropped_before > 0) entry["dropped_before"] = dropped_before;
    std::vector<core::Detection> frame_detections;
    if (detections) {
      clock.Restart();
      frame_detections = detections->For(index, frame, features, entry, summary);
      times.detect = clock.ElapsedMilliseconds();
    }

    clock.Restart();
    exclusion.Mark(frame, frame_detections, features.keypoints, features.descriptors, keep, boxes);
    times.filter = clock.ElapsedMilliseconds();
    const std::size_t extracted = features.keypoints.size();
    const auto dropped = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), std::uint8_t{0}));
    if (dropped > 0 && options.keypoint_budget == KeypointBudget::kStatic) {
      clock.Restart();
      ExtractOutsideDynamic(system, exclusion, frame, boxes, features, keep);
      times.extract += clock.ElapsedMilliseconds();
    }
    const std::size_t kept = features.keypoints.size() - dropped;
    if (exclusion.CanScore()) {
      const ExclusionCounts counts = exclusion.Score(frame, features.keypoints, keep);
      *summary.exclusion += counts;
      entry["exclusion"] = {{"moving_kept", counts.moving_kept},
                            {"moving_dropped", counts.moving_dropped},
                            {"static_kept", counts.static_kept},
                            {"static_dropped", counts.static_dropped},
                            {"static_dropped_without_depth", counts.static_dropped_without_depth}};
      if (exclusion.ScoresStillPeople()) {
        entry["exclusion"]["static_dropped_on_still_people"] = counts.static_dropped_on_still_people;
      }
    }
    if (IsSnapshot(index, total, options.snapshots)) {
      WriteSnapshot(folder / "snapshots" / fmt::format("{:06d}.jpg", index), frame, boxes, features.keypoints, keep);
    }

    clock.Restart();
    const slam::TrackResult result = system.Track(frame, features, keep);
    times.track = clock.ElapsedMilliseconds();
    exclusion.AfterTracking(result.T_cw);

    ++summary.frames;
    summary.keypoints_extracted += extracted;
    summary.keypoints_dropped += dropped;
    summary.keypoints_tracked += kept;
    summary.moving_points += static_cast<std::size_t>(result.moving_points);
    if (result.T_cw) {
      ++summary.tracked;
      if (result.method == slam::TrackingMethod::kRelocalization) summary.relocalized.push_back(frame.timestamp);
    } else if (result.state == slam::TrackingState::kNotInitialized) {
      ++summary.before_initialization;
    } else {
      ++summary.lost;
    }
    summary.times.push_back(times);

    entry["state"] = result.T_cw ? "ok" : slam::ToString(result.state);
    entry["method"] = slam::ToString(result.method);
    if (result.failure != slam::TrackingFailure::kNone) entry["failure"] = slam::ToString(result.failure);
    entry["keyframe"] = result.keyframe;
    entry["features"] = {{"extracted", extracted},
                         {"dropped", dropped},
                         {"kept", kept},
                         {"matched", result.matched},
                         {"inliers", result.inliers}};
    if (options.exclusion.SafetyNet()) entry["features"]["moving_points"] = result.moving_points;
    entry["dynamic"] = JudgedBoxList(boxes, true);
    // Every verdict of hoidplus is logged, since memory can keep or release a box whatever the frame shows.
    if (!boxes.context.empty()) entry["static"] = JudgedBoxList(boxes, false);
    entry["ms"] = {{"load", Round(times.load, 3)},       {"extract", Round(times.extract, 3)},
                   {"detect", Round(times.detect, 3)},   {"filter", Round(times.filter, 3)},
                   {"track", Round(times.track, 3)}};
    log.stream() << entry.dump() << '\n';
    progress.Update(index + 1);
  }
  summary.seconds = run_clock.ElapsedMilliseconds() / 1000.0 - (paced ? paced->held_seconds() : 0.0);
  detections.reset();  // the detector thread stops: the detector is the caller's again

  system.Finish();
  io::WriteTumTrajectory(folder / "trajectory.txt", system.FrameTrajectory());
  const core::Trajectory keyframes = system.KeyFrameTrajectory();
  io::WriteTumTrajectory(folder / "keyframes.txt", keyframes);
  std::vector<io::ColoredPoint> cloud;
  for (const slam::MapPointSample& p : system.MapPoints()) cloud.push_back({p.position, p.color});
  io::WritePly(folder / "map.ply", cloud);
  log.Commit();
  summary.keyframes = keyframes.size();
  summary.map_points = cloud.size();
  summary.loops = system.LoopClosures();
  summary.loop_timings = system.LoopClosingTimings();
  return summary;
}

}  // namespace hoidslam::pipeline
