#pragma once
// ATE and RPE of an estimated trajectory file against a ground-truth file: what `hoidslam eval` runs,
// with the readable table and the JSON summary it writes.

#include <filesystem>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "hoidslam/eval/ate.h"
#include "hoidslam/eval/rpe.h"

namespace hoidslam::eval {

struct EvaluationOptions {
  AteOptions ate{};
  RpeOptions rpe{};

  void Check() const {
    ate.Check();
    rpe.Check();
  }
};

struct Evaluation {
  std::filesystem::path groundtruth_path;
  std::filesystem::path estimate_path;
  EvaluationOptions options{};
  std::size_t groundtruth_poses = 0;  // distinct stamps read from each file
  std::size_t estimate_poses = 0;
  AteResult ate{};
  RpeResult rpe{};
};

// Reads both TUM trajectory files and computes ATE and RPE. Every InputError names the file it is about;
// too few matches name both files.
Evaluation EvaluateTrajectoryFiles(const std::filesystem::path& groundtruth, const std::filesystem::path& estimate,
                                   const EvaluationOptions& options);

// ComputeAte of two trajectories read from the files named, as EvaluateTrajectoryFiles computes it: an InputError
// about how the two fit together (too few matching stamps) names both files.
AteResult ComputeAteOfFiles(const core::Trajectory& groundtruth, const std::filesystem::path& groundtruth_path,
                            const core::Trajectory& estimate, const std::filesystem::path& estimate_path,
                            const AteOptions& options);

// A table for people: ATE statistics in metres with the number of pairs, RPE translation and rotation per delta.
std::string FormatEvaluation(const Evaluation& evaluation);

// Summary statistics, alignment and options (no per-pair lists).
nlohmann::json EvaluationToJson(const Evaluation& evaluation);

// EvaluationToJson written atomically (complete or absent).
void WriteEvaluationJson(const std::filesystem::path& path, const Evaluation& evaluation);

}  // namespace hoidslam::eval
