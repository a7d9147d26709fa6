// `hoidslam run`: RGB-D SLAM over a sequence with the features of people and of the objects they handle
// dropped before tracking. Writes the trajectory, the keyframes, the sparse map and a per-frame log, and, when
// the sequence has ground truth, prints its ATE and RPE (docs/slam.md).
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "detector_options.h"
#include "sequence_options.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/interrupt.h"
#include "hoidslam/eval/evaluation.h"
#include "hoidslam/eval/statistics.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/pipeline/run.h"
#include "hoidslam/report/html_report.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;

struct RunArgs {
  SequenceArgs sequence;
  std::string settings;
  DetectorArgs detector;
  std::string filter;      // overrides HOID.mode
  std::optional<double> min_interaction_area;  // overrides HOID.minInteractionArea
  std::optional<double> depth_threshold;       // overrides HOID.depthThreshold
  std::size_t snapshots = pipeline::RunOptions{}.snapshots;
  std::string out;
  std::size_t frames = 0;
  bool deterministic = false;
  bool force = false;
};

// The median over the frames of one stage's time (or of a function of the stage times), in ms.
double MedianMs(const std::vector<pipeline::StageTimes>& times, const std::function<double(const pipeline::StageTimes&)>& of) {
  std::vector<double> values;
  values.reserve(times.size());
  for (const auto& t : times) values.push_back(of(t));
  return values.empty() ? 0.0 : eval::ComputeStatistics(values).median;
}

// Against the ground-truth moving masks: null when the sequence has none.
nlohmann::json ExclusionQualityJson(const std::optional<pipeline::ExclusionCounts>& counts) {
  if (!counts) return nullptr;
  return {{"leaked", counts->Leaked()},
          {"wasted", counts->Wasted()},
          {"moving_kept", counts->moving_kept},
          {"moving_dropped", counts->moving_dropped},
          {"static_kept", counts->static_kept},
          {"static_dropped", counts->static_dropped}};
}

nlohmann::json SummaryJson(const pipeline::RunSummary& s, const std::string& sequence, const std::string& mode,
                           const std::string& detector) {
  const auto median = [&](double pipeline::StageTimes::*stage) { return MedianMs(s.times, std::mem_fn(stage)); };
  return {{"sequence", sequence},
          {"filter", mode},
          {"detector", detector},
          {"frames", s.frames},
          {"tracked", s.tracked},
          {"lost", s.lost},
          {"before_initialization", s.before_initialization},
          {"keyframes", s.keyframes},
          {"map_points", s.map_points},
          {"detector_failures", s.detector_failures},
          {"keypoints_extracted", s.keypoints_extracted},
          {"keypoints_dropped", s.keypoints_dropped},
          {"moving_points_erased", s.moving_points},
          {"interrupted", s.interrupted},
          {"exclusion_quality", ExclusionQualityJson(s.exclusion)},
          {"median_ms",
           {{"load", median(&pipeline::StageTimes::load)},
            {"extract", median(&pipeline::StageTimes::extract)},
            {"detect", median(&pipeline::StageTimes::detect)},
            {"filter", median(&pipeline::StageTimes::filter)},
            {"track", median(&pipeline::StageTimes::track)},
            {"tracking_total", MedianMs(s.times, &pipeline::StageTimes::TrackingTotal)}}}};
}

void RunRun(const RunArgs& args) {
  std::optional<io::Settings> settings;
  if (!args.settings.empty()) settings = io::LoadSettings(args.settings);
  pipeline::RunOptions options = pipeline::RunOptions::FromSettings(settings.value_or(io::Settings{}));
  if (!settings) spdlog::debug("no --settings: the TUM fr3 camera and the default ORB and HOID settings");
  if (!args.filter.empty()) pipeline::SetFilterMode(args.filter, options.exclusion, "--filter");
  if (args.min_interaction_area) options.exclusion.hoid.min_interaction_area = *args.min_interaction_area;
  if (args.depth_threshold) options.exclusion.hoid.depth_threshold = *args.depth_threshold;
  options.snapshots = args.snapshots;
  options.system.deterministic = args.deterministic;
  options.max_frames = args.frames;
  options.system.Check();

  const io::RgbdSequence sequence =
      OpenSequence(args.sequence, settings ? std::optional(settings->depth_map_factor) : std::nullopt);
  const std::unique_ptr<detect::Detector> detector =
      OpenDetector(args.detector, args.sequence, options.exclusion, sequence);

  io::AtomicFolder out(args.out, args.force, "--out", "use --force to replace it");
  core::InterruptGuard interrupts;
  const pipeline::RunSummary summary = pipeline::RunSequence(sequence, *detector, options, out.temporary(),
                                                             [&interrupts] { return interrupts.requested(); });

  nlohmann::json json = SummaryJson(summary, sequence.name(), std::string(options.exclusion.ModeName()), detector->Name());
  std::optional<eval::Evaluation> evaluation;
  const fs::path groundtruth = sequence.root() / "groundtruth.txt";
  if (!sequence.groundtruth().empty()) {
    try {
      evaluation = eval::EvaluateTrajectoryFiles(groundtruth, out.temporary() / "trajectory.txt", {});
      evaluation->estimate_path = out.path() / "trajectory.txt";  // where it will be once the folder is complete
      json["evaluation"] = eval::EvaluationToJson(*evaluation);
    } catch (const core::InputError& e) {
      spdlog::warn("not evaluated: {}", e.what());
    }
  }
  {
    io::AtomicFile file(out.temporary() / "summary.json");
    file.stream() << json.dump(2) << '\n';
    file.Commit();
  }
  try {
    report::WriteRunReport(out.temporary(), evaluation ? groundtruth : fs::path(), out.temporary() / "report.html");
  } catch (const core::InputError& e) {
    spdlog::warn("no report.html: {}", e.what());  // the run's own outputs are complete; only the page is missing
  }
  out.Commit();

  fmt::print("{}: {} frames, {} tracked, {} lost, {} before initialisation; {} keyframes, {} map points\n",
             sequence.name(), summary.frames, summary.tracked, summary.lost, summary.before_initialization,
             summary.keyframes, summary.map_points);
  fmt::print("keypoints: {} extracted, {} dropped by the filter ({:.1f} %)\n", summary.keypoints_extracted,
             summary.keypoints_dropped,
             summary.keypoints_extracted == 0 ? 0.0 : 100.0 * summary.keypoints_dropped / summary.keypoints_extracted);
  if (options.exclusion.SafetyNet()) {
    fmt::print("safety net: {} map points erased as moving\n", summary.moving_points);
  }
  if (summary.exclusion) {
    fmt::print("against the moving masks: {:.1f} % of the keypoints on moving things kept (leaked), {:.1f} % of the "
               "static ones dropped (wasted)\n",
               100.0 * summary.exclusion->Leaked(), 100.0 * summary.exclusion->Wasted());
  }
  const nlohmann::json& ms = json["median_ms"];
  fmt::print("median ms per frame: load {:.2f}, extract {:.2f}, detect {:.2f}, filter {:.3f}, track {:.2f}; "
             "tracking (extract + filter + track) {:.2f}\n",
             ms["load"].get<double>(), ms["extract"].get<double>(), ms["detect"].get<double>(),
             ms["filter"].get<double>(), ms["track"].get<double>(), ms["tracking_total"].get<double>());
  if (evaluation) fmt::print("{}", eval::FormatEvaluation(*evaluation));
  fmt::print("wrote {}/ (trajectory.txt, keyframes.txt, map.ply, frames.jsonl, summary.json, snapshots/, report.html)\n",
             out.path().string());
  if (summary.interrupted) {
    spdlog::warn("interrupted after {} of {} frames; the outputs hold the frames done", summary.frames, sequence.size());
    std::fflush(stdout);  // the signal raised again ends the process without flushing the summary printed above
    interrupts.Reraise();
  }
}

}  // namespace

void AddRunCommand(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* command = app.add_subcommand(
      "run",
      "RGB-D SLAM over a TUM / Bonn / synthetic sequence with the features of people and of the objects they handle "
      "dropped before tracking; writes the trajectory, keyframes, map and a per-frame log, and evaluates against "
      "groundtruth.txt when the sequence has one");
  AddSequenceOptions(*command, args->sequence);
  command->add_option("--settings", args->settings,
                      "Settings file (ORB-SLAM3 format with a HOID section, e.g. config/TUM3.yaml; default: TUM fr3)");
  AddDetectorOptions(*command, args->detector);
  command->add_option("--filter", args->filter,
                      "What is dropped: none, person, classes, hoid2d, hoid3d, hoidplus (HOID with depth, memory and a "
                      "safety net; hoidplus:depth+memory etc. for some parts), or oracle (the ground-truth moving "
                      "masks of a synthetic sequence); default: HOID.mode of the settings, else hoid2d");
  command->add_option("--min-interaction-area", args->min_interaction_area,
                      "Overrides HOID.minInteractionArea: the share of an object's box a person's box must cover "
                      "for the object to count as handled (0..1]")
      ->check(CLI::PositiveNumber & CLI::Range(0.0, 1.0));
  command->add_option("--depth-threshold", args->depth_threshold,
                      "Overrides HOID.depthThreshold: the largest depth difference (m) between a handled object and "
                      "its person in hoid3d")
      ->check(CLI::PositiveNumber);
  command->add_option("--snapshots", args->snapshots,
                      "Annotated frames written to <out>/snapshots/, spread evenly over the run")
      ->capture_default_str();
  command->add_option("--out", args->out, "Output folder (created complete or not at all)")->required();
  command->add_option("--frames", args->frames, "Run only the first N frames (0 = all)")->capture_default_str();
  command->add_flag("--deterministic", args->deterministic,
                    "Local mapping in step with tracking: identical output on every run (slower)");
  command->add_flag("--force", args->force, "Replace the --out folder when it exists and is not empty");
  command->callback([args] { RunRun(*args); });
}

}  // namespace hoidslam::apps
