#include "hoidslam/pipeline/session.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "hoidslam/core/descriptor_distance.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/io/ply_file.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/hoid/late_detections.h"
#include "hoidslam/pipeline/depth_units.h"
#include "hoidslam/pipeline/detector_thread.h"

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
    if (!std::isnan(decision.extent)) entry["extent"] = Round(decision.extent, 2);
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

// Spends the budget the filter freed on the static world: `features` becomes the keypoints of the first
// extraction on what is dynamic (those the filter dropped, keep 0, for the log and the scoring; those hoidplus kept
// behind a person, keep 1), then those of a second extraction outside it (keep 1).
void ExtractOutsideDynamic(slam::System& system, const KeypointExclusion& exclusion, const core::RgbdFrame& frame,
                           const hoid::JudgedBoxes& boxes, slam::ExtractedFeatures& features,
                           std::vector<std::uint8_t>& keep) {
  const cv::Mat dynamic = exclusion.DynamicPixels(frame, boxes, features.keypoints, keep);
  const slam::ExtractedFeatures outside = system.ExtractOutside(dynamic);
  std::vector<std::size_t> first;  // the first extraction's keypoints that stay
  for (std::size_t i = 0; i < features.keypoints.size(); ++i) {
    if (keep[i] == 0 || OnMask(dynamic, features.keypoints[i])) first.push_back(i);  // else the second has its like
  }
  slam::ExtractedFeatures merged;
  std::vector<std::uint8_t> merged_keep;
  merged.keypoints.reserve(first.size() + outside.keypoints.size());
  merged.descriptors.create(static_cast<int>(first.size() + outside.keypoints.size()), core::kOrbDescriptorBytes,
                            CV_8UC1);
  for (const std::size_t i : first) {
    const auto row = static_cast<int>(merged.keypoints.size());
    std::memcpy(merged.descriptors.ptr(row), features.descriptors.ptr(static_cast<int>(i)), core::kOrbDescriptorBytes);
    merged.keypoints.push_back(features.keypoints[i]);
    merged_keep.push_back(keep[i]);
  }
  if (!outside.keypoints.empty()) {
    outside.descriptors.copyTo(merged.descriptors.rowRange(static_cast<int>(first.size()), merged.descriptors.rows));
  }
  merged.keypoints.insert(merged.keypoints.end(), outside.keypoints.begin(), outside.keypoints.end());
  merged_keep.resize(merged.keypoints.size(), 1);
  features = std::move(merged);
  keep = std::move(merged_keep);
}

}  // namespace

// The detections each frame is judged by. Frames go to the detector thread; the synchronous mode waits for each
// frame's own detections, the real-time mode for the first frame's only and then takes the newest there are. The
// newest good detections are carried to the frame (hoid/late_detections.h); a frame the detector failed on keeps
// them. Each frame's age of its detections goes into its log entry and the summary.
class Session::Detections {
 public:
  Detections(detect::Detector& detector, const RunOptions& options)
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


namespace {

// `options`, once they pass Check(): nothing is built from options that fail it.
const RunOptions& Checked(const RunOptions& options) {
  options.Check();
  return options;
}

}  // namespace

Session::Session(const RunOptions& options, detect::Detector* detector, const std::filesystem::path& sequence_root)
    : options_(Checked(options)), exclusion_(options.exclusion, sequence_root, options.system.camera) {
  slam::SystemOptions system_options = options.system;
  if (options.exclusion.SafetyNet()) {
    system_options.tracking.moving_point_outliers = options.exclusion.hoid.plus.moving_point_outliers;
  }
  system_ = std::make_unique<slam::System>(system_options);
  if (exclusion_.CanScore()) summary_.exclusion.emplace();
  summary_.still_people_scored = exclusion_.ScoresStillPeople();
  summary_.vocabulary_identity = system_->VocabularyIdentity();
  // Both modes hand frames to the detector thread: the synchronous one then waits for each frame's detections.
  if (detector != nullptr && (options.exclusion.NeedsDetections() || options.exclusion.oracle)) {
    detections_ = std::make_unique<Detections>(*detector, options);
  }
}

Session::~Session() = default;

const FrameOutcome& Session::Track(std::size_t index, const core::RgbdFrame& frame,
                                   const std::vector<core::Detection>* detections, double load_ms,
                                   std::size_t dropped_before) {
  if (finished_) throw core::Error("a frame came after the session finished");
  if (detections == nullptr && detections_ == nullptr && options_.exclusion.NeedsDetections()) {
    throw core::InputError::ForParameter(
        "detections", fmt::format("mode {} needs the frame's detections: give them, or a detector model (or use "
                                  "filter none)",
                                  options_.exclusion.ModeName()));
  }
  if (!depth_judged_ && options_.check_depth_units) {
    if (const std::optional<DepthSpread> spread = MeasureDepth(frame.depth)) {
      depth_judged_ = true;
      if (std::string problem = DepthUnitsProblem(*spread, options_.depth_factor); !problem.empty()) {
        throw core::InputError::ForParameter("depth", problem);
      }
    }
  }
  FrameOutcome& out = outcome_;
  out.times = StageTimes{};
  out.times.load = load_ms;
  summary_.dropped += dropped_before;
  const bool detect = detections == nullptr && detections_ != nullptr;
  if (detect) detections_->Submit(index, frame);

  core::Stopwatch clock;
  out.features = system_->Extract(frame.rgb);
  out.times.extract = clock.ElapsedMilliseconds();

  out.entry = {{"frame", index}, {"timestamp", frame.timestamp}};
  if (dropped_before > 0) out.entry["dropped_before"] = dropped_before;
  std::vector<core::Detection> frame_detections;
  if (detect) {
    clock.Restart();
    frame_detections = detections_->For(index, frame, out.features, out.entry, summary_);
    out.times.detect = clock.ElapsedMilliseconds();
  } else if (detections != nullptr) {
    frame_detections = *detections;
  }

  clock.Restart();
  exclusion_.Mark(frame, frame_detections, out.features.keypoints, out.features.descriptors, out.keep, out.boxes);
  out.times.filter = clock.ElapsedMilliseconds();
  out.extracted = out.features.keypoints.size();
  out.dropped = static_cast<std::size_t>(std::count(out.keep.begin(), out.keep.end(), std::uint8_t{0}));
  if (out.dropped > 0 && options_.keypoint_budget == KeypointBudget::kStatic) {
    clock.Restart();
    ExtractOutsideDynamic(*system_, exclusion_, frame, out.boxes, out.features, out.keep);
    out.times.extract += clock.ElapsedMilliseconds();
  }
  const std::size_t kept = out.features.keypoints.size() - out.dropped;
  if (exclusion_.CanScore()) {
    const ExclusionCounts counts = exclusion_.Score(frame, out.features.keypoints, out.keep);
    *summary_.exclusion += counts;
    out.entry["exclusion"] = {{"moving_kept", counts.moving_kept},
                              {"moving_dropped", counts.moving_dropped},
                              {"static_kept", counts.static_kept},
                              {"static_dropped", counts.static_dropped},
                              {"static_dropped_without_depth", counts.static_dropped_without_depth}};
    if (exclusion_.ScoresStillPeople()) {
      out.entry["exclusion"]["static_dropped_on_still_people"] = counts.static_dropped_on_still_people;
    }
  }

  clock.Restart();
  out.result = system_->Track(frame, out.features, out.keep);
  out.times.track = clock.ElapsedMilliseconds();
  const slam::TrackResult& result = out.result;
  exclusion_.AfterTracking(result.T_cw);

  ++summary_.frames;
  summary_.keypoints_extracted += out.extracted;
  summary_.keypoints_dropped += out.dropped;
  summary_.keypoints_tracked += kept;
  summary_.moving_points += static_cast<std::size_t>(result.moving_points);
  tracked_stamps_.push_back(frame.timestamp);
  if (result.T_cw) {
    ++summary_.tracked;
    if (result.method == slam::TrackingMethod::kRelocalization) summary_.relocalized.push_back(frame.timestamp);
  } else if (result.state == slam::TrackingState::kNotInitialized) {
    ++summary_.before_initialization;
  } else {
    ++summary_.lost;
  }
  // A refuted relocalisation: its frames were counted tracked, and are lost after all.
  for (const std::uint64_t id : result.withdrawn) {
    const double stamp = tracked_stamps_.at(id);
    --summary_.tracked;
    ++summary_.lost;
    ++summary_.withdrawn;
    std::erase(summary_.relocalized, stamp);
  }
  summary_.times.push_back(out.times);

  nlohmann::json& entry = out.entry;
  entry["state"] = slam::ToString(result.state);
  entry["method"] = slam::ToString(result.method);
  if (result.failure != slam::TrackingFailure::kNone) entry["failure"] = slam::ToString(result.failure);
  if (result.rejection != slam::PoseRejection::kNone) entry["rejection"] = slam::ToString(result.rejection);
  if (!result.withdrawn.empty()) entry["withdrawn"] = result.withdrawn;
  if (result.evidence) {
    // What the pose was judged on (docs/slam.md, "Accepting a pose").
    entry["evidence"] = {{"inlier_ratio", Round(result.evidence->inlier_ratio(), 3)},
                         {"outlier_clustering", Round(result.evidence->outlier_clustering, 2)}};
    if (result.evidence->motion_chi2) entry["evidence"]["motion_chi2"] = Round(*result.evidence->motion_chi2, 1);
  }
  entry["keyframe"] = result.keyframe;
  if (result.T_cw) entry["map"] = result.map;
  entry["features"] = {{"extracted", out.extracted},
                       {"dropped", out.dropped},
                       {"kept", kept},
                       {"matched", result.matched},
                       {"inliers", result.inliers}};
  if (options_.exclusion.SafetyNet()) entry["features"]["moving_points"] = result.moving_points;
  entry["dynamic"] = JudgedBoxList(out.boxes, true);
  // Every verdict of hoidplus is logged, since memory can keep or release a box whatever the frame shows.
  if (!out.boxes.context.empty()) entry["static"] = JudgedBoxList(out.boxes, false);
  const StageTimes& times = out.times;
  entry["ms"] = {{"load", Round(times.load, 3)},       {"extract", Round(times.extract, 3)},
                 {"detect", Round(times.detect, 3)},   {"filter", Round(times.filter, 3)},
                 {"track", Round(times.track, 3)}};
  return out;
}

void Session::Finish() {
  if (finished_) return;
  detections_.reset();  // the detector thread stops: the detector is the caller's again
  system_->Finish();
  summary_.final_adjustment_ms = system_->FinalAdjustmentMilliseconds();
  if (!options_.save_map.empty()) system_->SaveMap(options_.save_map);
  summary_.loops = system_->LoopClosures();
  summary_.merges = system_->MapMerges();
  summary_.maps = system_->Maps();
  summary_.main_map = slam::MainMapOf(summary_.maps);
  summary_.loop_timings = system_->LoopClosingTimings();
  finished_ = true;
}

cv::Mat Session::StaticMapExclusion(const core::RgbdFrame& frame, const StaticMapReach& reach) const {
  return exclusion_.StaticMapExclusion(frame, outcome_.boxes, reach);
}

void Session::WriteOutputs(const std::filesystem::path& folder) {
  io::WriteTumTrajectory(folder / "trajectory.txt", system_->FrameTrajectory(summary_.main_map));
  for (const slam::MapSummary& map : summary_.maps) {
    if (map.id != summary_.main_map) {
      io::WriteTumTrajectory(folder / OtherMapTrajectoryName(map.id), system_->FrameTrajectory(map.id));
    }
  }
  const core::Trajectory keyframes = system_->KeyFrameTrajectory();
  io::WriteTumTrajectory(folder / "keyframes.txt", keyframes);
  std::vector<io::ColoredPoint> cloud;
  for (const slam::MapPointSample& p : system_->MapPoints()) cloud.push_back({p.position, p.color});
  io::WritePly(folder / "map.ply", cloud);
  summary_.keyframes = keyframes.size();
  summary_.map_points = cloud.size();
}

}  // namespace hoidslam::pipeline
