// `hoidslam report`: one self-contained HTML page about a folder written by `hoidslam run`: counts, the trajectory
// seen from above against ground truth, the error over time, features, time per stage, the map in 3D (with the
// dense map when the run made one), and the annotated snapshots when the run saved any (docs/report.md).
#include <filesystem>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "commands.h"
#include "hoidslam/dense/display_mesh.h"
#include "hoidslam/report/html_report.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;

struct ReportArgs {
  std::string run_folder;
  std::string groundtruth;  // empty: the file the run was evaluated against, if it is still there
  std::string out;          // empty: <run folder>/report.html
};

void RunReport(const ReportArgs& args) {
  const fs::path folder = args.run_folder;
  const fs::path groundtruth = args.groundtruth.empty() ? report::RecordedGroundTruthIfPresent(folder, "--groundtruth")
                                                        : fs::path(args.groundtruth);
  const fs::path out = args.out.empty() ? folder / "report.html" : fs::path(args.out);
  // The report module does not link Open3D: the dense map is made small here (docs/report.md).
  report::WriteRunReport(folder, groundtruth, out, {},
                         dense::ReadMeshForDisplay(folder / "mesh.ply", report::kReportDenseTriangles));
  fmt::print("wrote {} ({})\n", out.string(),
             groundtruth.empty() ? "no ground truth" : "ground truth " + groundtruth.string());
}

}  // namespace

void AddReportCommand(CLI::App& app) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* command = app.add_subcommand(
      "report",
      "One self-contained HTML page about a run of `hoidslam run`: counts, trajectory against ground truth, error "
      "over time, features per frame, time per stage, annotated snapshots; opens offline in any browser");
  command->add_option("run-folder", args->run_folder, "Output folder of `hoidslam run`")->required();
  command->add_option("--groundtruth", args->groundtruth,
                      "Ground-truth trajectory, TUM format (default: the file the run was evaluated against, when "
                      "summary.json names one)");
  command->add_option("--out", args->out, "HTML file to write (default: <run-folder>/report.html)");
  command->callback([args] { RunReport(*args); });
}

}  // namespace hoidslam::apps
