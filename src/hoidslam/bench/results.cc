#include "hoidslam/bench/results.h"

#include <algorithm>
#include <fstream>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"

namespace hoidslam::bench {
namespace {

namespace fs = std::filesystem;

// The last non-empty line of a log, without the terminal's progress-line carriage returns.
std::string LastLine(const fs::path& log) {
  std::ifstream in(log);
  std::string last;
  for (std::string line; std::getline(in, line);) {
    const std::size_t cr = line.find_last_of('\r');
    if (cr != std::string::npos) line = line.substr(cr + 1);
    if (line.find_first_not_of(" \t") != std::string::npos) last = line;
  }
  return last.empty() ? "no output" : last;
}

std::optional<double> Optional(const nlohmann::json& json, const nlohmann::json::json_pointer& pointer) {
  if (!json.contains(pointer) || json.at(pointer).is_null()) return std::nullopt;
  return json.at(pointer).get<double>();
}

}  // namespace

const char* ToString(RunStatus status) {
  switch (status) {
    case RunStatus::kOk: return "ok";
    case RunStatus::kFailed: return "failed";
    case RunStatus::kInterrupted: return "interrupted";
    case RunStatus::kNotRun: return "not run";
  }
  return "?";
}

RunResult ReadRunResult(const Plan& plan, const RunSpec& spec) {
  RunResult result;
  const fs::path summary_path = plan.RunFolder(spec) / "summary.json";
  if (!fs::exists(summary_path)) {
    // The run folder appears complete or not at all; a log without it is a run that ended without outputs.
    if (fs::exists(plan.RunLog(spec))) {
      result.status = RunStatus::kFailed;
      result.message = LastLine(plan.RunLog(spec));
    }
    return result;
  }
  try {
    std::ifstream in(summary_path);
    const nlohmann::json s = nlohmann::json::parse(in);
    result.status = s.at("interrupted").get<bool>() ? RunStatus::kInterrupted : RunStatus::kOk;
    result.frames = s.at("frames").get<std::size_t>();
    result.tracked = s.at("tracked").get<std::size_t>();
    result.lost = s.at("lost").get<std::size_t>();
    result.before_initialization = s.at("before_initialization").get<std::size_t>();
    const nlohmann::json& ms = s.at("median_ms");
    result.median_ms = {.load = ms.at("load").get<double>(),
                        .extract = ms.at("extract").get<double>(),
                        .detect = ms.at("detect").get<double>(),
                        .filter = ms.at("filter").get<double>(),
                        .track = ms.at("track").get<double>(),
                        .tracking_total = ms.at("tracking_total").get<double>()};
    using Pointer = nlohmann::json::json_pointer;
    result.ate_rmse = Optional(s, Pointer("/evaluation/ate/error_m/rmse"));
    result.ate_mean = Optional(s, Pointer("/evaluation/ate/error_m/mean"));
    result.ate_median = Optional(s, Pointer("/evaluation/ate/error_m/median"));
    result.rpe_translation_rmse = Optional(s, Pointer("/evaluation/rpe/translation_m/rmse"));
    result.rpe_rotation_rmse = Optional(s, Pointer("/evaluation/rpe/rotation_deg/rmse"));
    result.leaked = Optional(s, Pointer("/exclusion_quality/leaked"));
    result.wasted = Optional(s, Pointer("/exclusion_quality/wasted"));
    result.relocalizations = Optional(s, Pointer("/evaluation/relocalizations/count"));
    result.false_relocalizations = Optional(s, Pointer("/evaluation/relocalizations/false"));
    result.loops = Optional(s, Pointer("/evaluation/loops/count"));
    result.false_loops = Optional(s, Pointer("/evaluation/loops/false"));
    result.merges = Optional(s, Pointer("/evaluation/merges/count"));
    result.false_merges = Optional(s, Pointer("/evaluation/merges/false"));
    result.return_events = Optional(s, Pointer("/evaluation/loop_recall/events"));
    result.returns_recalled = Optional(s, Pointer("/evaluation/loop_recall/recalled"));
    result.closures_judged = Optional(s, Pointer("/evaluation/loop_recall/closures"));
    result.closures_confirmed = Optional(s, Pointer("/evaluation/loop_recall/confirmed"));
    result.dense_area = Optional(s, Pointer("/dense/mesh/area_m2"));
    result.dense_fuse_ms = Optional(s, Pointer("/dense/median_fuse_ms"));
    result.dense_build_seconds = Optional(s, Pointer("/dense/build_seconds"));
    result.dense_volume_mb = Optional(s, Pointer("/dense/volume_mb"));
    result.dense_people_kept = Optional(s, Pointer("/dense/people/share"));
    result.dense_accuracy_median = Optional(s, Pointer("/evaluation/dense/accuracy_m/median"));
    result.dense_accuracy_p90 = Optional(s, Pointer("/evaluation/dense/accuracy_m/p90"));
    result.dense_completeness = Optional(s, Pointer("/evaluation/dense/completeness"));
    result.dense_ghost_area = Optional(s, Pointer("/evaluation/dense/ghost_area_m2"));
    result.dense_ghost_share = Optional(s, Pointer("/evaluation/dense/ghost_share"));
    result.dense_occupied_cells = Optional(s, Pointer("/evaluation/dense/occupied_cells"));
    result.dense_ghost_cells = Optional(s, Pointer("/evaluation/dense/ghost_cells"));
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError::InFile(summary_path, fmt::format("not a run summary: {}", e.what()));
  }
  result.covered = CoveredFrames(plan.sequences[spec.sequence].path / "events.jsonl", result.frames);
  return result;
}

std::size_t CoveredFrames(const fs::path& events, std::size_t frames) {
  std::ifstream in(events);
  if (!in) return 0;
  std::vector<std::pair<std::size_t, bool>> changes;  // frame, covered from it on
  std::size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      const nlohmann::json event = nlohmann::json::parse(line);
      const std::string action = event.value("action", "");
      if (action == "cover_lens" || action == "uncover_lens") {
        changes.emplace_back(event.at("frame").get<std::size_t>(), action == "cover_lens");
      }
    } catch (const nlohmann::json::exception& e) {
      throw core::InputError::AtLine(events, number, fmt::format("not an event: {}", e.what()));
    }
  }
  std::stable_sort(changes.begin(), changes.end(), [](const auto& l, const auto& r) { return l.first < r.first; });
  std::size_t covered = 0;
  bool covering = false;
  std::size_t since = 0;  // while covering: the frame the lens has been covered from
  for (const auto& [frame, cover] : changes) {
    if (cover == covering) continue;  // covered again, or uncovered while open
    if (cover) since = frame;
    if (!cover) covered += std::min(frame, frames) - std::min(since, frames);
    covering = cover;
  }
  if (covering) covered += frames - std::min(since, frames);
  return covered;
}

std::vector<RunResult> CollectResults(const Plan& plan) {
  std::vector<RunResult> results;
  results.reserve(plan.runs.size());
  for (const RunSpec& spec : plan.runs) results.push_back(ReadRunResult(plan, spec));
  return results;
}

nlohmann::json RunResultToJson(const RunResult& r) {
  const auto optional = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); };
  nlohmann::json json = {{"status", ToString(r.status)}};
  if (r.status == RunStatus::kFailed) json["message"] = r.message;
  if (r.status != RunStatus::kOk && r.status != RunStatus::kInterrupted) return json;
  json.update({{"frames", r.frames},
               {"tracked", r.tracked},
               {"lost", r.lost},
               {"before_initialization", r.before_initialization},
               {"ate_rmse", optional(r.ate_rmse)},
               {"ate_mean", optional(r.ate_mean)},
               {"ate_median", optional(r.ate_median)},
               {"rpe_translation_rmse", optional(r.rpe_translation_rmse)},
               {"rpe_rotation_rmse", optional(r.rpe_rotation_rmse)},
               {"leaked", optional(r.leaked)},
               {"wasted", optional(r.wasted)},
               {"relocalizations", optional(r.relocalizations)},
               {"false_relocalizations", optional(r.false_relocalizations)},
               {"loops", optional(r.loops)},
               {"false_loops", optional(r.false_loops)},
               {"merges", optional(r.merges)},
               {"false_merges", optional(r.false_merges)},
               {"return_events", optional(r.return_events)},
               {"returns_recalled", optional(r.returns_recalled)},
               {"closures_judged", optional(r.closures_judged)},
               {"closures_confirmed", optional(r.closures_confirmed)},
               {"covered", r.covered},
               {"median_ms",
                {{"load", r.median_ms.load},
                 {"extract", r.median_ms.extract},
                 {"detect", r.median_ms.detect},
                 {"filter", r.median_ms.filter},
                 {"track", r.median_ms.track},
                 {"tracking_total", r.median_ms.tracking_total}}}});
  // null for a run without a dense map; the figures of its evaluation null without the sequence's geometry.
  json["dense"] = nullptr;
  if (r.dense_area) {
    json["dense"] = {{"area_m2", optional(r.dense_area)},
                     {"median_fuse_ms", optional(r.dense_fuse_ms)},
                     {"build_seconds", optional(r.dense_build_seconds)},
                     {"volume_mb", optional(r.dense_volume_mb)},
                     {"people_kept", optional(r.dense_people_kept)},
                     {"accuracy_median_m", optional(r.dense_accuracy_median)},
                     {"accuracy_p90_m", optional(r.dense_accuracy_p90)},
                     {"completeness", optional(r.dense_completeness)},
                     {"ghost_area_m2", optional(r.dense_ghost_area)},
                     {"ghost_share", optional(r.dense_ghost_share)},
                     {"occupied_cells", optional(r.dense_occupied_cells)},
                     {"ghost_cells", optional(r.dense_ghost_cells)}};
  }
  return json;
}

}  // namespace hoidslam::bench
