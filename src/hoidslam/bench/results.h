#pragma once
// What a finished bench run left in its folder, read back for the tables. A run is judged only by its folder
// and log, so runs made by `hoidslam bench`, GNU parallel or a Slurm array are collected the same way.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "hoidslam/bench/plan.h"

namespace hoidslam::bench {

enum class RunStatus {
  kOk,           // complete outputs of the whole sequence
  kFailed,       // ended without outputs (an error, a crash, a time limit): never a number in the tables
  kInterrupted,  // stopped early (Ctrl-C); run again by --resume
  kNotRun,       // no trace yet
};
const char* ToString(RunStatus status);

struct StageMedians {
  double load = 0, extract = 0, detect = 0, filter = 0, track = 0, tracking_total = 0;  // ms per frame
};

struct RunResult {
  RunStatus status = RunStatus::kNotRun;
  std::string message;  // kFailed: the last line of the run's log
  std::size_t frames = 0, tracked = 0, lost = 0, before_initialization = 0;
  std::optional<double> ate_rmse, ate_mean, ate_median;  // m; absent without ground truth or a trajectory
  std::optional<double> rpe_translation_rmse;            // m per second
  std::optional<double> rpe_rotation_rmse;               // degrees per second
  StageMedians median_ms;
  std::optional<double> leaked, wasted;  // exclusion quality, shares in [0, 1], on sequences with masks
  // Frames relocalisation found, and of those the false ones (eval/pose_check.h); absent without ground truth.
  std::optional<double> relocalizations, false_relocalizations;
  // Loops closed, and of those the false ones (their two ends' relative pose against the ground truth's); the
  // same for maps merged.
  std::optional<double> loops, false_loops, merges, false_merges;
  // Loop recall (eval/loop_recall.h): the returns to a mapped place and those recalled, the loops and merges judged
  // and those the ground truth confirmed; absent without ground truth (and in runs made before it was measured).
  std::optional<double> return_events, returns_recalled, closures_judged, closures_confirmed;
  std::size_t covered = 0;  // frames of the run with the lens covered (the sequence's events.jsonl)
  // The dense map of a run with --dense: its mesh's surface (m²), the median time to fuse a keyframe (ms), the time
  // to build it after the run (s) and its volume's memory (MB); absent without --dense.
  std::optional<double> dense_area, dense_fuse_ms, dense_build_seconds, dense_volume_mb;
  // The people the dense map kept, judged without ground truth (eval/person_surface.h): the share of the person
  // pixels of the keyframes' person boxes where the map has surface; absent when no keyframe had a person box.
  std::optional<double> dense_people_kept;
  // The dense map against the sequence's exact geometry (eval/dense_score.h): its vertices' distance to the static
  // surface (m), the share of the static surface in view it mapped, its surface farther from every static one (m²)
  // and that surface's share, the occupancy map's occupied cells and of them those only people and moved objects
  // filled; absent without the geometry (real recordings).
  std::optional<double> dense_accuracy_median, dense_accuracy_p90, dense_completeness, dense_ghost_area,
      dense_ghost_share, dense_occupied_cells, dense_ghost_cells;
};

// Frames in [0, frames) the lens was covered in, by the `cover_lens` / `uncover_lens` lines of a synthetic
// sequence's events.jsonl (each with `frame`, the line of rgb.txt; a stretch not uncovered lasts to the end). 0
// when the file is absent. Throws InputError naming the file and line of a malformed line.
std::size_t CoveredFrames(const std::filesystem::path& events, std::size_t frames);

// Reads runs/<id>/summary.json, or the log when the folder is absent. Throws InputError naming summary.json
// when it exists but is not one `hoidslam run` writes.
RunResult ReadRunResult(const Plan& plan, const RunSpec& spec);

// One result per plan.runs entry, in order.
std::vector<RunResult> CollectResults(const Plan& plan);

nlohmann::json RunResultToJson(const RunResult& result);

}  // namespace hoidslam::bench
