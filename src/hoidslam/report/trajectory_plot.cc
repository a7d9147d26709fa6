#include "hoidslam/report/trajectory_plot.h"

#include <algorithm>
#include <cctype>
#include <limits>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/eval/evaluation.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/trajectory_file.h"
#include "hoidslam/report/html_report.h"
#include "hoidslam/report/raster.h"
#include "hoidslam/report/svg_plot.h"
#include "hoidslam/report/table.h"

namespace hoidslam::report {
namespace {

namespace fs = std::filesystem;
using core::InputError;


enum class PlotFormat { kHtml, kPng, kSvg };

PlotFormat FormatOf(const fs::path& file, const std::string& option) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".html") return PlotFormat::kHtml;
  if (extension == ".png") return PlotFormat::kPng;
  if (extension == ".svg") return PlotFormat::kSvg;
  throw InputError::ForParameter(
      option, fmt::format("{}: the extension says what to write, and must be .html, .png or .svg", file.string()));
}

std::string Metres(double value) { return fmt::format("{:.6f}", value); }  // as `hoidslam eval` prints them

bool HasGroundTruth(const TrajectoryPlot& plot) { return !plot.groundtruth_path.empty(); }

// The positions of `estimate` in time order, moved into the ground truth's frame when it was aligned to it.
std::vector<Eigen::Vector3d> ShownPositions(const PlottedEstimate& estimate) {
  std::vector<Eigen::Vector3d> positions;
  for (const core::StampedPose& pose : eval::SortedUniqueByTime(estimate.trajectory)) {
    const Eigen::Vector3d p = pose.T_wc.translation();
    positions.push_back(estimate.ate ? estimate.ate->alignment.Apply(p) : p);
  }
  return positions;
}

// The ground-truth stamps the estimates' pairs span, from the earliest to the latest.
std::pair<double, double> PairedTimeSpan(const TrajectoryPlot& plot) {
  double first = std::numeric_limits<double>::infinity();
  double last = -first;
  for (const PlottedEstimate& estimate : plot.estimates) {
    for (const eval::AtePair& pair : estimate.ate->pairs) {
      first = std::min(first, pair.groundtruth_timestamp);
      last = std::max(last, pair.groundtruth_timestamp);
    }
  }
  return {first, last};
}

// Ground truth usually covers more than was estimated (a cut recording): only the estimates' time span.
Path3d GroundTruthOverEstimates(const TrajectoryPlot& plot, double width, bool dashed) {
  const auto [first, last] = PairedTimeSpan(plot);
  const double margin = plot.options.association.max_difference;
  Path3d path{.name = "ground truth", .colour = std::string(kGroundTruthColour), .width = width, .dashed = dashed};
  for (const core::StampedPose& pose : eval::SortedUniqueByTime(plot.groundtruth)) {
    if (pose.timestamp >= first - margin && pose.timestamp <= last + margin) {
      path.points.push_back(pose.T_wc.translation());
    }
  }
  return path;
}

ChartOptions PanelOptions(std::string title) {
  return {.title = std::move(title), .width = kPlotPanelWidth, .height = kPlotPanelHeight};
}

Drawing PathsPanel(const TrajectoryPlot& plot) {
  std::vector<Path3d> paths;
  if (HasGroundTruth(plot)) paths.push_back(GroundTruthOverEstimates(plot, 6.0, false));
  for (std::size_t i = 0; i < plot.estimates.size(); ++i) {
    paths.push_back({plot.estimates[i].name, ShownPositions(plot.estimates[i]), std::string(PaletteColour(i))});
  }
  return PathPlotDrawing(paths, PanelOptions(HasGroundTruth(plot) ? "Trajectories seen from above, aligned"
                                                                  : "Trajectories seen from above, as estimated"));
}

Drawing ErrorOverTimePanel(const TrajectoryPlot& plot) {
  const double t0 = PairedTimeSpan(plot).first;
  std::vector<LineSeries> series;
  for (std::size_t i = 0; i < plot.estimates.size(); ++i) {
    const PlottedEstimate& estimate = plot.estimates[i];
    const std::string rmse = FormatSignificant(estimate.ate->error.rmse, 3);
    LineSeries line{.name = fmt::format("{} (RMSE {} m)", estimate.name, rmse), .colour = std::string(PaletteColour(i))};
    for (const eval::AtePair& pair : estimate.ate->pairs) {
      line.x.push_back(pair.groundtruth_timestamp - t0);
      line.y.push_back(pair.error);
    }
    series.push_back(std::move(line));
  }
  ChartOptions options = PanelOptions("ATE over time");
  options.x_label = "time (s)";
  options.y_label = "ATE (m)";
  return LineChartDrawing(series, options);
}

Drawing ErrorAlongPathPanel(const TrajectoryPlot& plot, const PlottedEstimate& estimate, const ColourScale& scale) {
  ValuePath path{.name = estimate.name};
  for (const eval::AtePair& pair : estimate.ate->pairs) {
    path.points.push_back(pair.aligned_position);
    path.values.push_back(pair.error);
  }
  const Path3d groundtruth = GroundTruthOverEstimates(plot, 1.5, true);
  return ValuePathPlotDrawing(std::span(&groundtruth, 1), path, scale,
                              PanelOptions(fmt::format("{}: ATE along the path", estimate.name)));
}

Table EstimateTable(const TrajectoryPlot& plot) {
  Table table;
  table.header = {"estimate", "file", "poses"};
  if (HasGroundTruth(plot)) {
    for (const char* column : {"pairs", "ATE RMSE (m)", "mean", "median", "std", "min", "max"}) {
      table.header.emplace_back(column);
    }
    if (plot.options.estimate_scale) table.header.emplace_back("scale");
  }
  for (const PlottedEstimate& estimate : plot.estimates) {
    std::vector<std::string>& row = table.rows.emplace_back();
    row = {estimate.name, estimate.path.string(), std::to_string(estimate.trajectory.size())};
    if (!estimate.ate) continue;
    const eval::ErrorStatistics& e = estimate.ate->error;
    for (const std::string& cell : {std::to_string(e.count), Metres(e.rmse), Metres(e.mean), Metres(e.median),
                                    Metres(e.std), Metres(e.min), Metres(e.max)}) {
      row.push_back(cell);
    }
    if (plot.options.estimate_scale) row.push_back(fmt::format("{:.6f}", estimate.ate->alignment.scale));
  }
  return table;
}

std::string PageHtml(const TrajectoryPlot& plot, const Drawing& figure) {
  std::string body;
  if (HasGroundTruth(plot)) {
    const eval::AssociationOptions& association = plot.options.association;
    body += fmt::format(
        "<h1>Trajectories against ground truth</h1>\n<p class=\"sub\">ground truth <b>{}</b> ({} poses) · each "
        "estimate aligned {} onto it as <code>hoidslam eval</code> aligns it, over the poses whose stamps differ by "
        "less than {} s (offset {} s)</p>\n",
        EscapeXml(plot.groundtruth_path.string()), plot.groundtruth.size(),
        plot.options.estimate_scale ? "with scale (Sim(3))" : "rigidly", association.max_difference,
        association.offset);
  } else {
    body += "<h1>Trajectories</h1>\n<p class=\"sub\">no ground truth: each path as estimated, in its own frame</p>\n";
  }
  body += TableHtml(EstimateTable(plot));
  const std::string caption =
      HasGroundTruth(plot)
          ? "Top left: the paths seen from above, each estimate aligned onto the ground truth (grey); a dot marks "
            "the start. Top right: each estimate's ATE (the distance of an aligned position from the ground truth "
            "at the same time) over time. Then each estimate's path coloured by that error, all on one scale."
          : "The paths seen from above, as estimated; a dot marks the start.";
  body += fmt::format("<figure>{}<figcaption>{}</figcaption></figure>\n", ToSvg(figure), EscapeXml(caption));
  return HtmlPage(HasGroundTruth(plot) ? "Trajectories against ground truth · hoidslam" : "Trajectories · hoidslam",
                  body);
}

void WriteText(const fs::path& file, const std::string& text) {
  io::AtomicFile out(file);
  out.stream() << text;
  out.Commit();
}

}  // namespace

TrajectoryPlot LoadTrajectoryPlot(const fs::path& groundtruth, std::span<const EstimateSource> estimates,
                                  const eval::AteOptions& options) {
  options.Check();
  if (estimates.empty()) throw InputError::ForParameter("--est", "nothing to plot: give an estimate (--est or --run)");
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    for (std::size_t j = i + 1; j < estimates.size(); ++j) {
      if (estimates[i].name != estimates[j].name) continue;
      throw InputError::ForParameter(
          "--name", fmt::format("{} and {} are both named '{}'; give each --est a name of its own",
                                estimates[i].path.string(), estimates[j].path.string(), estimates[i].name));
    }
  }
  TrajectoryPlot plot{.groundtruth_path = groundtruth, .options = options};
  if (!groundtruth.empty()) plot.groundtruth = io::ReadTumTrajectory(groundtruth);
  for (const EstimateSource& source : estimates) {
    PlottedEstimate& estimate = plot.estimates.emplace_back();
    estimate.name = source.name;
    estimate.path = source.path;
    estimate.trajectory = io::ReadTumTrajectory(source.path);
    if (!groundtruth.empty()) {
      estimate.ate = eval::ComputeAteOfFiles(plot.groundtruth, groundtruth, estimate.trajectory, source.path, options);
    }
  }
  return plot;
}

EstimateSource RunFolderEstimate(const fs::path& run_folder) {
  if (!fs::is_directory(run_folder)) {
    throw InputError::InFile(run_folder, "is not a folder (give a folder of hoidslam run)");
  }
  const fs::path trajectory = run_folder / "trajectory.txt";
  if (!fs::exists(trajectory)) {
    throw InputError::InFile(trajectory, "is missing: is this a folder written by hoidslam run?");
  }
  return {fs::weakly_canonical(run_folder).filename().string(), trajectory};
}

fs::path GroundTruthOfRuns(std::span<const fs::path> run_folders, std::string_view option) {
  fs::path chosen, chosen_by;
  for (const fs::path& run : run_folders) {
    const fs::path groundtruth = RecordedGroundTruthIfPresent(run, option);
    if (groundtruth.empty()) continue;
    if (chosen.empty()) {
      chosen = groundtruth;
      chosen_by = run;
    } else if (fs::weakly_canonical(groundtruth) != fs::weakly_canonical(chosen)) {
      throw InputError::ForParameter(
          std::string(option),
          fmt::format("the runs {} and {} were evaluated against different ground truths ({} and {}); give the one "
                      "to plot against",
                      chosen_by.string(), run.string(), chosen.string(), groundtruth.string()));
    }
  }
  return chosen;
}

Drawing TrajectoryFigure(const TrajectoryPlot& plot) {
  std::vector<Drawing> panels;
  panels.push_back(PathsPanel(plot));
  if (HasGroundTruth(plot)) {
    panels.push_back(ErrorOverTimePanel(plot));
    double largest = 0.0;
    for (const PlottedEstimate& estimate : plot.estimates) largest = std::max(largest, estimate.ate->error.max);
    // An estimate equal to its ground truth has no error at all; the scale still needs a range to show.
    const ColourScale scale{.low = 0.0, .high = std::max(largest, 1e-6), .label = "ATE (m)"};
    for (const PlottedEstimate& estimate : plot.estimates) panels.push_back(ErrorAlongPathPanel(plot, estimate, scale));
  }
  constexpr std::size_t kColumns = 2;
  const std::size_t columns = std::min(kColumns, panels.size());
  const std::size_t rows = (panels.size() + kColumns - 1) / kColumns;
  Drawing figure(static_cast<int>(columns) * kPlotPanelWidth, static_cast<int>(rows) * kPlotPanelHeight,
                 HasGroundTruth(plot) ? "Trajectories against ground truth" : "Trajectories");
  for (std::size_t i = 0; i < panels.size(); ++i) {
    figure.Place(panels[i], {static_cast<double>(i % kColumns * kPlotPanelWidth),
                             static_cast<double>(i / kColumns * kPlotPanelHeight)});
  }
  return figure;
}

std::string TrajectoryPlotHtml(const TrajectoryPlot& plot) { return PageHtml(plot, TrajectoryFigure(plot)); }

void CheckPlotFiles(std::span<const fs::path> files, const std::string& option) {
  for (const fs::path& file : files) {
    FormatOf(file, option);
    io::CheckWritableFile(file, option);
  }
}

void WriteTrajectoryPlot(const TrajectoryPlot& plot, std::span<const fs::path> files, const std::string& option) {
  const Drawing figure = TrajectoryFigure(plot);
  for (const fs::path& file : files) {
    switch (FormatOf(file, option)) {
      case PlotFormat::kHtml: WriteText(file, PageHtml(plot, figure)); break;
      case PlotFormat::kPng: io::WriteImageAtomically(file, RenderImage(figure)); break;
      case PlotFormat::kSvg: WriteText(file, ToSvg(figure) + "\n"); break;
    }
  }
}

}  // namespace hoidslam::report
