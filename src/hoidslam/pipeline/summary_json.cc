#include "hoidslam/pipeline/summary_json.h"

#include <functional>
#include <vector>

#include "hoidslam/eval/statistics.h"
#include "hoidslam/io/files.h"

namespace hoidslam::pipeline {
namespace {

// The median over the frames of one stage's time (or of a function of the stage times), in ms.
double MedianMs(const std::vector<StageTimes>& times, const std::function<double(const StageTimes&)>& of) {
  std::vector<double> values;
  values.reserve(times.size());
  for (const auto& t : times) values.push_back(of(t));
  return values.empty() ? 0.0 : eval::ComputeStatistics(values).median;
}

// Against the ground-truth moving masks: null when the sequence has none; the count on still people is null
// when it has no people masks.
nlohmann::json ExclusionQualityJson(const RunSummary& s) {
  if (!s.exclusion) return nullptr;
  const ExclusionCounts& counts = *s.exclusion;
  nlohmann::json on_still_people = nullptr;
  if (s.still_people_scored) on_still_people = counts.static_dropped_on_still_people;
  return {{"leaked", counts.Leaked()},
          {"wasted", counts.Wasted()},
          {"moving_kept", counts.moving_kept},
          {"moving_dropped", counts.moving_dropped},
          {"static_kept", counts.static_kept},
          {"static_dropped", counts.static_dropped},
          {"static_dropped_without_depth", counts.static_dropped_without_depth},
          {"static_dropped_on_still_people", on_still_people}};
}

double Median(std::vector<double> values) {
  return values.empty() ? 0.0 : eval::ComputeStatistics(values).median;
}

// How the detector kept pace: null when the run had no detector.
nlohmann::json DetectionsJson(const RunSummary& s) {
  if (s.detector_ms.empty()) return nullptr;
  const std::vector<double> frames(s.detection_age_frames.begin(), s.detection_age_frames.end());
  return {{"median_age_frames", Median(frames)},
          {"median_age_ms", Median(s.detection_age_ms)},
          {"median_detector_ms", Median(s.detector_ms)},
          {"boxes_carried_by_keypoints", s.boxes_carried_by_keypoints},
          {"boxes_grown", s.boxes_grown}};
}

// The loops closed (or maps merged): the frames at their two ends, the verification's inliers, and how far the
// correction moved the keyframe that closed it (a merge: the map moved, and the map it joined).
nlohmann::json LoopsJson(const std::vector<slam::LoopClosure>& closures) {
  nlohmann::json loops = nlohmann::json::array();
  for (const slam::LoopClosure& loop : closures) {
    nlohmann::json entry = {{"timestamp", loop.timestamp},
                            {"loop_timestamp", loop.loop_timestamp},
                            {"inliers", loop.inliers}};
    if (loop.merged_map) {
      entry["merged_map"] = *loop.merged_map;
      entry["into_map"] = loop.map;
    } else {
      entry["correction_m"] = loop.correction_m;
      entry["correction_deg"] = loop.correction_deg;
    }
    loops.push_back(std::move(entry));
  }
  return loops;
}

// The maps frames were tracked in (after the merges): the main one's frames are in trajectory.txt.
nlohmann::json MapsJson(const RunSummary& s) {
  nlohmann::json maps = nlohmann::json::array();
  for (const slam::MapSummary& map : s.maps) {
    const std::string trajectory =
        map.id == s.main_map ? std::string("trajectory.txt") : OtherMapTrajectoryName(map.id);
    maps.push_back({{"id", map.id}, {"frames", map.frames}, {"keyframes", map.keyframes}, {"trajectory", trajectory}});
  }
  return maps;
}

// How long loop closing looked for loops per keyframe, and verified each candidate: count, median and largest (ms).
nlohmann::json LoopTimingsJson(const RunSummary& s) {
  const auto statistics = [](const std::vector<double>& ms) -> nlohmann::json {
    if (ms.empty()) return {{"count", 0}, {"median", nullptr}, {"max", nullptr}};
    const eval::ErrorStatistics stats = eval::ComputeStatistics(ms);
    return {{"count", ms.size()}, {"median", stats.median}, {"max", stats.max}};
  };
  return {{"detection", statistics(s.loop_timings.detection_ms)},
          {"verification", statistics(s.loop_timings.verification_ms)}};
}

}  // namespace

nlohmann::json RunSummaryJson(const RunSummary& s, const std::string& sequence, const std::string& mode,
                           const std::string& detector, const RealTimeOptions& realtime) {
  const auto median = [&](double StageTimes::*stage) { return MedianMs(s.times, std::mem_fn(stage)); };
  return {{"sequence", sequence},
          {"filter", mode},
          {"detector", detector},
          {"realtime", realtime.enabled},
          {"paced", realtime.pace},
          {"detector_latency_ms", realtime.detector_latency_ms},
          {"frames", s.frames},
          {"dropped", s.dropped},
          {"tracked", s.tracked},
          {"lost", s.lost},
          {"withdrawn", s.withdrawn},
          {"before_initialization", s.before_initialization},
          {"keyframes", s.keyframes},
          {"map_points", s.map_points},
          {"detector_failures", s.detector_failures},
          {"keypoints_extracted", s.keypoints_extracted},
          {"keypoints_dropped", s.keypoints_dropped},
          {"keypoints_tracked", s.keypoints_tracked},
          {"moving_points_erased", s.moving_points},
          {"interrupted", s.interrupted},
          {"seconds", s.seconds},
          {"frames_per_second", s.seconds > 0.0 ? static_cast<double>(s.frames) / s.seconds : 0.0},
          {"loops", LoopsJson(s.loops)},
          {"merges", LoopsJson(s.merges)},
          {"maps", MapsJson(s)},
          {"loop_closing_ms", LoopTimingsJson(s)},
          {"final_adjustment_ms", s.final_adjustment_ms},
          {"detections", DetectionsJson(s)},
          {"exclusion_quality", ExclusionQualityJson(s)},
          {"median_ms",
           {{"load", median(&StageTimes::load)},
            {"extract", median(&StageTimes::extract)},
            {"detect", median(&StageTimes::detect)},
            {"filter", median(&StageTimes::filter)},
            {"track", median(&StageTimes::track)},
            {"tracking_total", MedianMs(s.times, &StageTimes::TrackingTotal)}}}};
}

nlohmann::json ProvenanceJson(const Provenance& provenance) {
  const auto path_or_null = [](const std::filesystem::path& path) {
    return path.empty() ? nlohmann::json(nullptr) : nlohmann::json(path);
  };
  nlohmann::json detector_source = nullptr;
  if (!provenance.detector_source.empty()) {
    detector_source = {{"file", provenance.detector_source},
                       {"sha256", io::FileSha256(provenance.detector_source, "detector file")}};
  }
  return {{"command_line", provenance.command_line},
          {"version", provenance.version},
          {"settings",
           {{"file", path_or_null(provenance.settings_file)},
            {"chosen", provenance.settings_chosen},
            {"values", io::SettingsToJson(provenance.settings)}}},
          {"vocabulary", {{"file", provenance.vocabulary}, {"identity", provenance.vocabulary_identity}}},
          {"detector_source", std::move(detector_source)}};
}

}  // namespace hoidslam::pipeline
