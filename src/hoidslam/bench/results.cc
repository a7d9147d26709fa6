#include "hoidslam/bench/results.h"

#include <fstream>

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
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError::InFile(summary_path, fmt::format("not a run summary: {}", e.what()));
  }
  return result;
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
               {"median_ms",
                {{"load", r.median_ms.load},
                 {"extract", r.median_ms.extract},
                 {"detect", r.median_ms.detect},
                 {"filter", r.median_ms.filter},
                 {"track", r.median_ms.track},
                 {"tracking_total", r.median_ms.tracking_total}}}});
  return json;
}

}  // namespace hoidslam::bench
