#pragma once
// `hoidslam plot` and `hoidslam eval --plot`: estimated trajectories over their ground truth, each associated,
// aligned and measured exactly as `hoidslam eval` does it, as one figure — the paths seen from above, the ATE over
// time, each path coloured by its error — in a self-contained HTML page with the ATE table, or as a PNG or SVG
// (docs/evaluation.md, "Plots").

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/eval/ate.h"
#include "hoidslam/report/drawing.h"

namespace hoidslam::report {

// An estimate to plot: a TUM trajectory file and the name its legend entries and table row give it.
struct EstimateSource {
  std::string name{};
  std::filesystem::path path{};
};

struct PlottedEstimate {
  std::string name{};
  std::filesystem::path path{};
  core::Trajectory trajectory{};         // as read
  std::optional<eval::AteResult> ate{};  // with ground truth: what `hoidslam eval` prints, and every pair
};

struct TrajectoryPlot {
  std::filesystem::path groundtruth_path{};  // empty: none; the estimates are drawn as they are, not aligned
  core::Trajectory groundtruth{};
  eval::AteOptions options{};
  std::vector<PlottedEstimate> estimates{};
};

// Reads the ground truth (when `groundtruth` is not empty) and every estimate and, with ground truth, computes each
// estimate's ATE as `hoidslam eval` does. Throws InputError naming the option or the file: bad `options`, no
// estimate, two estimates of one name, a file that cannot be read or has a bad line, an estimate with too few
// stamps matching the ground truth.
TrajectoryPlot LoadTrajectoryPlot(const std::filesystem::path& groundtruth, std::span<const EstimateSource> estimates,
                                  const eval::AteOptions& options);

// A folder written by `hoidslam run` as an estimate: its trajectory.txt, named after the folder. Throws
// InputError when the folder has no trajectory.txt.
EstimateSource RunFolderEstimate(const std::filesystem::path& run_folder);

// The one ground truth the runs were evaluated against (summary.json), when it is still there; empty when none
// was. Throws InputError naming `option` (to give one) when two runs were evaluated against different files.
std::filesystem::path GroundTruthOfRuns(std::span<const std::filesystem::path> run_folders, std::string_view option);

// The figure's panels are this large, two to a row: the paths seen from above; then, with ground truth, the ATE
// over time and, for each estimate, its path coloured by its error (one colour scale for all, so the same colour
// is the same error in every panel).
inline constexpr int kPlotPanelWidth = 560;
inline constexpr int kPlotPanelHeight = 420;

Drawing TrajectoryFigure(const TrajectoryPlot& plot);

// The page: what was compared and how, the table (per estimate: poses, pairs, and ATE RMSE, mean, median, std, min
// and max with the digits `hoidslam eval` prints), the figure as inline SVG.
std::string TrajectoryPlotHtml(const TrajectoryPlot& plot);

// Throws InputError naming `option` unless every file ends in .html, .png or .svg and can be written now: said
// before the work, not after it.
void CheckPlotFiles(std::span<const std::filesystem::path> files, const std::string& option);

// Each file by its extension: .html the page, .png and .svg the figure; each complete or absent.
void WriteTrajectoryPlot(const TrajectoryPlot& plot, std::span<const std::filesystem::path> files,
                         const std::string& option);

}  // namespace hoidslam::report
