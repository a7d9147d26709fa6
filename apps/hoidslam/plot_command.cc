// `hoidslam plot`: estimated trajectories over their ground truth, each associated and aligned as `hoidslam eval`
// does, as a self-contained HTML page (figure and ATE table), a PNG or an SVG (docs/evaluation.md, "Plots").
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ate_options.h"
#include "commands.h"
#include "hoidslam/core/error.h"
#include "hoidslam/report/trajectory_plot.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;

struct PlotArgs {
  fs::path groundtruth;  // empty: the one the --run folders were evaluated against, if any
  std::vector<fs::path> estimates;
  std::vector<std::string> names;  // none, or one per --est
  std::vector<fs::path> run_folders;
  std::vector<fs::path> outputs;
  eval::AteOptions options;
};

// The --est files (named by --name, else by their file name) and then the --run folders, in the order given.
std::vector<report::EstimateSource> Estimates(const PlotArgs& args) {
  if (!args.names.empty() && args.names.size() != args.estimates.size()) {
    throw core::InputError::ForParameter(
        "--name", fmt::format("{} names for {} --est files: give one per --est, in the same order, or none",
                              args.names.size(), args.estimates.size()));
  }
  std::vector<report::EstimateSource> estimates;
  for (std::size_t i = 0; i < args.estimates.size(); ++i) {
    estimates.push_back({args.names.empty() ? args.estimates[i].stem().string() : args.names[i], args.estimates[i]});
  }
  for (const fs::path& run : args.run_folders) estimates.push_back(report::RunFolderEstimate(run));
  return estimates;
}

void RunPlot(const PlotArgs& args) {
  report::CheckPlotFiles(args.outputs, "--out");
  const std::vector<report::EstimateSource> estimates = Estimates(args);
  const fs::path groundtruth =
      args.groundtruth.empty() ? report::GroundTruthOfRuns(args.run_folders, "--gt") : args.groundtruth;
  const report::TrajectoryPlot plot = report::LoadTrajectoryPlot(groundtruth, estimates, args.options);
  report::WriteTrajectoryPlot(plot, args.outputs, "--out");
  for (const report::PlottedEstimate& estimate : plot.estimates) {
    if (estimate.ate) {
      fmt::print("{}: ATE RMSE {:.6f} m over {} pairs ({})\n", estimate.name, estimate.ate->error.rmse,
                 estimate.ate->error.count, estimate.path.string());
    } else {
      fmt::print("{}: {} poses, no ground truth ({})\n", estimate.name, estimate.trajectory.size(),
                 estimate.path.string());
    }
  }
  std::vector<std::string> written;
  for (const fs::path& output : args.outputs) written.push_back(output.string());
  fmt::print("wrote {}\n", fmt::join(written, ", "));
}

}  // namespace

void AddPlotCommand(CLI::App& app) {
  auto args = std::make_shared<PlotArgs>();
  CLI::App* command = app.add_subcommand(
      "plot",
      "Estimated trajectories over their ground truth, each aligned as `hoidslam eval` aligns it: the paths seen "
      "from above, the ATE over time and each path coloured by its error, with the ATE table; one self-contained "
      "HTML page, a PNG or an SVG");
  command->add_option("--gt", args->groundtruth,
                      "Ground-truth trajectory, TUM format (default: the file the --run folders were evaluated "
                      "against; none: the paths only, as estimated)");
  command->add_option("--est", args->estimates, "Estimated trajectory, TUM format (repeatable)");
  command->add_option("--name", args->names,
                      "Name of each --est in the legends and the table, in the same order (default: its file name "
                      "without extension)");
  command->add_option("--run", args->run_folders,
                      "Output folder of `hoidslam run`: its trajectory.txt, named after the folder (repeatable)");
  command->add_option("--out", args->outputs,
                      "File to write, its format by its extension: .html the page, .png or .svg the figure alone "
                      "(repeatable)")
      ->required();
  AddAteOptions(*command, args->options);
  command->callback([args] { RunPlot(*args); });
}

}  // namespace hoidslam::apps
