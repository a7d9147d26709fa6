// `hoidslam eval`: ATE and RPE of an estimated trajectory against ground truth, computed as TUM's
// evaluate_ate.py and evaluate_rpe.py do (docs/evaluation.md).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "ate_options.h"
#include "commands.h"
#include "hoidslam/eval/evaluation.h"
#include "hoidslam/report/trajectory_plot.h"

namespace hoidslam::apps {
namespace {

struct EvalArgs {
  std::string groundtruth;
  std::string estimate;
  std::string json;  // empty: no JSON file
  std::vector<std::filesystem::path> plots;  // the estimate plotted over the ground truth, each by its extension
  std::string rpe_delta_unit = "s";
  eval::EvaluationOptions options;
};

void RunEval(const EvalArgs& args) {
  report::CheckPlotFiles(args.plots, "--plot");
  eval::EvaluationOptions options = args.options;
  options.rpe.offset = options.ate.association.offset;  // one time offset for both errors, as the flag says
  options.rpe.delta_unit = args.rpe_delta_unit == "f" ? eval::DeltaUnit::kFrames : eval::DeltaUnit::kSeconds;
  const eval::Evaluation evaluation = eval::EvaluateTrajectoryFiles(args.groundtruth, args.estimate, options);
  if (!args.json.empty()) eval::WriteEvaluationJson(args.json, evaluation);  // first: a failure prints no table
  fmt::print("{}", eval::FormatEvaluation(evaluation));
  if (!args.plots.empty()) {
    const std::filesystem::path estimate = args.estimate;
    const report::EstimateSource source{estimate.stem().string(), estimate};
    report::WriteTrajectoryPlot(report::LoadTrajectoryPlot(args.groundtruth, std::span(&source, 1), options.ate),
                                args.plots, "--plot");
  }
}

}  // namespace

void AddEvalCommand(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  eval::EvaluationOptions& options = args->options;
  CLI::App* command = app.add_subcommand(
      "eval",
      "Absolute trajectory error (ATE) and relative pose error (RPE) of an estimated trajectory against ground "
      "truth, both TUM format (timestamp tx ty tz qx qy qz qw), as TUM's evaluate_ate.py / evaluate_rpe.py");
  command->add_option("--gt", args->groundtruth, "Ground-truth trajectory file")->required();
  command->add_option("--est", args->estimate, "Estimated trajectory file")->required();
  AddAteOptions(*command, options.ate);
  command->add_option("--rpe-delta", options.rpe.delta, "Step between the poses compared for RPE")
      ->capture_default_str();
  command->add_option("--rpe-delta-unit", args->rpe_delta_unit, "Unit of --rpe-delta: s (seconds) or f (frames)")
      ->check(CLI::IsMember({"s", "f"}))
      ->capture_default_str();
  command->add_option("--json", args->json, "Also write the results to this JSON file");
  command->add_option("--plot", args->plots,
                      "Also plot the estimate over the ground truth, as `hoidslam plot` does, into this file: .html "
                      "the page with the figure and the ATE table, .png or .svg the figure alone (repeatable)");
  command->callback([args] { RunEval(*args); });
}

}  // namespace hoidslam::apps
