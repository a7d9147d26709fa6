#include "hoidslam/eval/evaluation.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/trajectory_file.h"

namespace hoidslam::eval {

namespace {

nlohmann::json StatisticsToJson(const ErrorStatistics& s) {
  return {{"pairs", s.count}, {"rmse", s.rmse},     {"mean", s.mean}, {"median", s.median},
          {"std", s.std},     {"min", s.min},       {"max", s.max}};
}

std::string StatisticsRow(std::string_view name, const ErrorStatistics& s) {
  return fmt::format("{:<28}{:>11.6f}{:>11.6f}{:>11.6f}{:>11.6f}{:>11.6f}{:>11.6f}{:>8}\n", name, s.rmse, s.mean,
                     s.median, s.std, s.min, s.max, s.count);
}

// With the options checked and both files read, what remains to go wrong is how the two files fit together.
core::InputError BetweenFiles(const std::filesystem::path& groundtruth, const std::filesystem::path& estimate,
                              const core::InputError& e) {
  return core::InputError(
      fmt::format("ground truth {} and estimate {}: {}", groundtruth.string(), estimate.string(), e.what()));
}

}  // namespace

AteResult ComputeAteOfFiles(const core::Trajectory& groundtruth, const std::filesystem::path& groundtruth_path,
                            const core::Trajectory& estimate, const std::filesystem::path& estimate_path,
                            const AteOptions& options) {
  try {
    return ComputeAte(groundtruth, estimate, options);
  } catch (const core::InputError& e) {
    throw BetweenFiles(groundtruth_path, estimate_path, e);
  }
}

Evaluation EvaluateTrajectoryFiles(const std::filesystem::path& groundtruth, const std::filesystem::path& estimate,
                                   const EvaluationOptions& options) {
  options.Check();
  Evaluation evaluation{groundtruth, estimate, options};
  const core::Trajectory gt = io::ReadTumTrajectory(groundtruth);
  const core::Trajectory est = io::ReadTumTrajectory(estimate);
  evaluation.groundtruth_poses = gt.size();
  evaluation.estimate_poses = est.size();
  evaluation.ate = ComputeAteOfFiles(gt, groundtruth, est, estimate, options.ate);
  try {
    evaluation.rpe = ComputeRpe(gt, est, options.rpe);
  } catch (const core::InputError& e) {
    throw BetweenFiles(groundtruth, estimate, e);
  }
  return evaluation;
}

std::string FormatEvaluation(const Evaluation& evaluation) {
  const RpeOptions& rpe = evaluation.options.rpe;
  const std::string per = rpe.delta_unit == DeltaUnit::kSeconds && rpe.delta == 1.0
                              ? "/s"
                              : fmt::format("/{}{}", rpe.delta, ToString(rpe.delta_unit));
  std::string text = fmt::format("ground truth {} ({} poses)\nestimate     {} ({} poses)\n",
                                 evaluation.groundtruth_path.string(), evaluation.groundtruth_poses,
                                 evaluation.estimate_path.string(), evaluation.estimate_poses);
  text += fmt::format("{:<28}{:>11}{:>11}{:>11}{:>11}{:>11}{:>11}{:>8}\n", "", "rmse", "mean", "median", "std", "min",
                      "max", "pairs");
  text += StatisticsRow(evaluation.options.ate.estimate_scale ? "ATE (m, Sim3-aligned)" : "ATE (m)",
                        evaluation.ate.error);
  text += StatisticsRow(fmt::format("RPE translation (m{})", per), evaluation.rpe.translation);
  text += StatisticsRow(fmt::format("RPE rotation (deg{})", per), evaluation.rpe.rotation_deg);
  if (evaluation.options.ate.estimate_scale) text += fmt::format("estimated scale {:.6f}\n", evaluation.ate.alignment.scale);
  return text;
}

nlohmann::json EvaluationToJson(const Evaluation& evaluation) {
  const EvaluationOptions& options = evaluation.options;
  const Alignment& alignment = evaluation.ate.alignment;
  nlohmann::json rotation = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rotation.push_back({alignment.rotation(r, 0), alignment.rotation(r, 1), alignment.rotation(r, 2)});
  return {
      {"groundtruth", {{"path", evaluation.groundtruth_path.string()}, {"poses", evaluation.groundtruth_poses}}},
      {"estimate", {{"path", evaluation.estimate_path.string()}, {"poses", evaluation.estimate_poses}}},
      {"options",
       {{"max_difference", options.ate.association.max_difference},
        {"offset", options.ate.association.offset},
        {"estimate_scale", options.ate.estimate_scale},
        {"rpe_delta", options.rpe.delta},
        {"rpe_delta_unit", std::string(ToString(options.rpe.delta_unit))}}},
      {"ate",
       {{"error_m", StatisticsToJson(evaluation.ate.error)},
        {"alignment",
         {{"rotation", rotation},
          {"translation", {alignment.translation.x(), alignment.translation.y(), alignment.translation.z()}},
          {"scale", alignment.scale}}}}},
      {"rpe",
       {{"translation_m", StatisticsToJson(evaluation.rpe.translation)},
        {"rotation_deg", StatisticsToJson(evaluation.rpe.rotation_deg)}}},
  };
}

void WriteEvaluationJson(const std::filesystem::path& path, const Evaluation& evaluation) {
  io::AtomicFile file(path);
  file.stream() << EvaluationToJson(evaluation).dump(2) << '\n';
  file.Commit();
}

}  // namespace hoidslam::eval
