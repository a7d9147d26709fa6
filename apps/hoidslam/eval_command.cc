// `hoidslam eval`: ATE and RPE of an estimated trajectory against ground truth, computed as TUM's
// evaluate_ate.py and evaluate_rpe.py do (docs/evaluation.md).
#include <memory>
#include <string>

#include <fmt/format.h>

#include "commands.h"
#include "hoidslam/eval/evaluation.h"

namespace hoidslam::apps {
namespace {

struct EvalArgs {
  std::string groundtruth;
  std::string estimate;
  std::string json;  // empty: no JSON file
  std::string rpe_delta_unit = "s";
  eval::EvaluationOptions options;
};

void RunEval(const EvalArgs& args) {
  eval::EvaluationOptions options = args.options;
  options.rpe.offset = options.ate.association.offset;  // one time offset for both errors, as the flag says
  options.rpe.delta_unit = args.rpe_delta_unit == "f" ? eval::DeltaUnit::kFrames : eval::DeltaUnit::kSeconds;
  const eval::Evaluation evaluation = eval::EvaluateTrajectoryFiles(args.groundtruth, args.estimate, options);
  if (!args.json.empty()) eval::WriteEvaluationJson(args.json, evaluation);  // first: a failure prints no table
  fmt::print("{}", eval::FormatEvaluation(evaluation));
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
  command->add_option("--max-difference", options.ate.association.max_difference,
                      "Largest time difference (s) of an associated pose pair for ATE")
      ->capture_default_str();
  command->add_option("--offset", options.ate.association.offset,
                      "Time offset (s) added to the estimated stamps before comparing them")
      ->capture_default_str();
  command->add_flag("--scale", options.ate.estimate_scale,
                    "Align with scale (Sim(3)) for ATE, for estimates of unknown scale such as monocular ones");
  command->add_option("--rpe-delta", options.rpe.delta, "Step between the poses compared for RPE")
      ->capture_default_str();
  command->add_option("--rpe-delta-unit", args->rpe_delta_unit, "Unit of --rpe-delta: s (seconds) or f (frames)")
      ->check(CLI::IsMember({"s", "f"}))
      ->capture_default_str();
  command->add_option("--json", args->json, "Also write the results to this JSON file");
  command->callback([args] { RunEval(*args); });
}

}  // namespace hoidslam::apps
