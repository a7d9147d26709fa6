#pragma once
// Small charts for the HTML reports and figures: a line chart (values over time), a path plot with equal axis
// scale (a trajectory seen from above), a path coloured by a value with its colour bar, and a bar chart (grouped or
// stacked). No plotting library: each chart lays itself out into a Drawing (drawing.h) of plain shapes, written as
// SVG that every browser draws and every printer prints, or painted into an image (raster.h) for a PNG.
//
// Non-finite values are never written: a NaN in a line series breaks the line there, a NaN bar is drawn as a
// missing mark, and degenerate ranges (one point, all values equal) get a range around the value.

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "hoidslam/report/drawing.h"

namespace hoidslam::report {

// Size and text shared by every chart. Every member of the structs here has an initializer, so that designated
// initializers can name only what differs: {.title = "ATE", .width = 520}.
struct ChartOptions {
  std::string title{};      // drawn above the chart and kept as its <title>; may be empty
  std::string x_label{};    // under the horizontal axis
  std::string y_label{};    // beside the vertical axis
  int width = 720;          // pixels of the SVG's own coordinate system (>= 100); the page may scale it
  int height = 340;         // >= 100
  bool y_from_zero = true;  // line charts: the value axis includes 0 (bars always start at 0)
  bool log_y = false;       // line and bar charts: logarithmic value axis; values <= 0 are left out
};

// Ground truth under estimates: wide and light, so that it shows where an estimate runs on top of it.
inline constexpr std::string_view kGroundTruthColour = "#bbbbbb";

// The chart colours, colour-blind safe (Okabe and Ito), as "#rrggbb"; `index` wraps around.
std::string_view PaletteColour(std::size_t index);

// A colour for `fraction` of a sequential scale, as "#rrggbb": dark blue (0) through green to yellow (1), evenly
// brighter so the order reads in grey and for colour-blind eyes. Outside [0, 1] (and NaN): the nearest end.
std::string SequentialColour(double fraction);

// One line of a line chart: points (x[i], y[i]); a non-finite x or y breaks the line there.
struct LineSeries {
  std::string name{};       // legend entry
  std::vector<double> x{};
  std::vector<double> y{};  // as long as x
  std::string colour{};     // CSS colour; empty: PaletteColour(index of the series)
};

// Axes with round ticks, grid, axis labels, a legend (when any series has a name) and one line per series.
// A point alone between breaks is drawn as a dot. LineChart is its SVG.
Drawing LineChartDrawing(std::span<const LineSeries> series, const ChartOptions& options);
std::string LineChart(std::span<const LineSeries> series, const ChartOptions& options);

// One path of a path plot, in world coordinates (metres).
struct Path3d {
  std::string name{};                     // legend entry
  std::vector<Eigen::Vector3d> points{};  // may be empty: the path is then in the legend only
  std::string colour{};                   // CSS colour; empty: PaletteColour(index of the path)
  double width = 2.0;                     // of the line, pixels: a wide light reference stays visible under others
  bool dashed = false;
};

// The two world axes (0 = x, 1 = y, 2 = z) along which `points` extend most, in increasing order: the view
// "from above" whatever way up the world frame is. {0, 1} for fewer than two points.
std::array<int, 2> LargestExtentAxes(std::span<const Eigen::Vector3d> points);

// The paths projected on the world axes LargestExtentAxes(paths[0].points) picks (pass the ground truth first),
// with one metre as long on both axes; the axis labels name the world axes ("x (m)", "z (m)"); options.x_label
// and y_label are not used. A dot marks where each path starts. PathPlot is its SVG.
Drawing PathPlotDrawing(std::span<const Path3d> paths, const ChartOptions& options);
std::string PathPlot(std::span<const Path3d> paths, const ChartOptions& options);

// A path whose every step is coloured by a value at its end (an error along a trajectory).
struct ValuePath {
  std::string name{};                     // legend entry
  std::vector<Eigen::Vector3d> points{};
  std::vector<double> values{};           // one per point; a NaN leaves its step out
};

// The values the colours of a ValuePath stand for: `low` at the dark end, `high` at the bright end.
struct ColourScale {
  double low = 0.0;
  double high = 1.0;     // > low
  std::string label{};   // beside the colour bar, e.g. "ATE (m)"
};

// PathPlotDrawing of `references` (drawn first, the first one picking the view) and `path` on top, its steps in the
// colours of `scale`, with a colour bar on the right. Several of these with one scale compare at a glance.
// Throws std::invalid_argument for a path without one value per point, or an empty scale.
Drawing ValuePathPlotDrawing(std::span<const Path3d> references, const ValuePath& path, const ColourScale& scale,
                             const ChartOptions& options);

// One series of a bar chart: one value per category; NaN marks a missing value (a failed run).
struct BarSeries {
  std::string name{};            // legend entry
  std::vector<double> values{};  // NaN: missing
  std::string colour{};          // CSS colour; empty: PaletteColour(index of the series)
};

enum class BarLayout {
  kGrouped,  // the series' bars side by side in each category
  kStacked,  // the series' bars on top of each other (values >= 0)
};

struct BarChartOptions {
  ChartOptions chart{};
  BarLayout layout = BarLayout::kGrouped;
  bool value_labels = true;    // the value above each bar (stacked: the total), where it fits
  int significant_digits = 3;  // of the value labels, >= 1
};

// Categories along the horizontal axis (labels slanted when they do not fit), the value axis from 0 (or from
// the decade below the smallest value with chart.log_y). Every series must have one value per category.
std::string BarChart(std::span<const std::string> categories, std::span<const BarSeries> series,
                     const BarChartOptions& options);

// `value` to `significant` digits without an exponent and without trailing zeros: 0.0035, 3.44, 1250.
std::string FormatSignificant(double value, int significant);

}  // namespace hoidslam::report
