#include "hoidslam/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

namespace hoidslam::report {
namespace {

// Okabe and Ito's colour-blind safe palette, yellow last (it is hard to see on white).
constexpr std::array<std::string_view, 8> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                      "#E69F00", "#56B4E9", "#000000", "#F0E442"};
constexpr std::string_view kAxisColour = "#777777";
constexpr std::string_view kGridColour = "#e6e6e6";
constexpr double kFontSize = 12.0;
constexpr double kCharWidth = 6.8;  // a generous average advance of the 12 px sans-serif font, for layout only
constexpr double kTitleHeight = 24.0;
constexpr double kLegendRowHeight = 18.0;
constexpr double kLegendSwatch = 18.0;
constexpr double kPadding = 10.0;
constexpr double kInf = std::numeric_limits<double>::infinity();

double TextWidth(std::string_view text, double font_size = kFontSize) {
  return static_cast<double>(text.size()) * kCharWidth * font_size / kFontSize;
}

std::string ColourOf(const std::string& colour, std::size_t index) {
  return colour.empty() ? std::string(PaletteColour(index)) : colour;
}

// 1, 2, 2.5 or 5 times a power of ten, the smallest not below `raw` (> 0).
double NiceStep(double raw) {
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double factor : {1.0, 2.0, 2.5, 5.0}) {
    if (factor * power >= raw * (1.0 - 1e-9)) return factor * power;
  }
  return 10.0 * power;
}

// Decimals needed to write multiples of `step` exactly.
int DecimalsOf(double step) {
  int decimals = 0;
  while (decimals < 12) {
    const double scaled = step * std::pow(10.0, decimals);
    if (std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
    ++decimals;
  }
  return decimals;
}

// A value axis: the range it shows, its ticks, and where a value falls on it.
class ValueAxis {
 public:
  // About `target_ticks` intervals of a round step over [min, max]; with `round_limits` the axis ends on ticks
  // too, else exactly at min and max. A range of zero width gets one around its value ([0, 1] for 0).
  static ValueAxis Linear(double min, double max, int target_ticks, bool round_limits = true) {
    if (!(max - min > 1e-12 * std::max(1.0, std::abs(max)))) {
      if (min == 0.0) {
        max = 1.0;
      } else {
        const double pad = 0.1 * std::abs(min);
        min -= pad;
        max += pad;
      }
    }
    const double step = NiceStep((max - min) / target_ticks);
    if (!round_limits) return Fixed(min, max, step);
    return Fixed(std::floor(min / step + 1e-9) * step, std::ceil(max / step - 1e-9) * step, step);
  }

  // Whole decades around [min, max] (both > 0), with ticks at 1, 2 and 5 times a power of ten when there are
  // few decades.
  static ValueAxis Log(double min, double max) {
    ValueAxis axis;
    axis.log_ = true;
    const int first = static_cast<int>(std::floor(std::log10(min) + 1e-9));
    const int last = std::max(first + 1, static_cast<int>(std::ceil(std::log10(max) - 1e-9)));
    axis.lo_ = std::pow(10.0, first);
    axis.hi_ = std::pow(10.0, last);
    for (int decade = first; decade <= last; ++decade) {
      for (const double factor : {1.0, 2.0, 5.0}) {
        if (factor != 1.0 && (last - first > 2 || decade == last)) continue;
        axis.ticks_.push_back(factor * std::pow(10.0, decade));
      }
    }
    return axis;
  }

  // Exactly [lo, hi], with ticks at the multiples of `step` inside it.
  static ValueAxis Fixed(double lo, double hi, double step) {
    ValueAxis axis;
    axis.lo_ = lo;
    axis.hi_ = hi;
    axis.decimals_ = DecimalsOf(step);
    for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0) {
      axis.ticks_.push_back(k * step == 0.0 ? 0.0 : k * step);  // no "-0"
    }
    return axis;
  }

  // 0 at the low end, 1 at the high end.
  double Fraction(double value) const {
    if (log_) return (std::log10(value) - std::log10(lo_)) / (std::log10(hi_) - std::log10(lo_));
    return (value - lo_) / (hi_ - lo_);
  }
  // Whether `value` can be placed on this axis.
  bool Shows(double value) const { return std::isfinite(value) && (!log_ || value > 0.0); }
  double lo() const { return lo_; }
  const std::vector<double>& ticks() const { return ticks_; }
  std::string TickLabel(double value) const {
    return log_ ? FormatSignificant(value, 1) : fmt::format("{:.{}f}", value, decimals_);
  }
  double WidestTickLabel() const {
    double widest = 0.0;
    for (const double tick : ticks_) widest = std::max(widest, TextWidth(TickLabel(tick)));
    return widest;
  }

 private:
  double lo_ = 0.0;
  double hi_ = 1.0;
  bool log_ = false;
  int decimals_ = 0;
  std::vector<double> ticks_;
};

// The value axis of data spanning [min, max] (only the values the axis Shows(); none: min > max).
ValueAxis ValueAxisFor(double min, double max, bool log, bool from_zero) {
  if (min > max) return log ? ValueAxis::Log(1.0, 10.0) : ValueAxis::Linear(0.0, 1.0, 5);
  if (log) return ValueAxis::Log(min, max);
  if (from_zero) {
    min = std::min(min, 0.0);
    max = std::max(max, 0.0);
  }
  return ValueAxis::Linear(min, max, 5);
}

// The plotting area inside the margins; fractions of an axis map to pixels, y upwards.
struct Area {
  double left = 0, top = 0, width = 0, height = 0;
  double X(double fraction) const { return left + fraction * width; }
  double Y(double fraction) const { return top + (1.0 - fraction) * height; }
  double bottom() const { return top + height; }
};

struct LegendEntry {
  std::string name;
  std::string colour;
  bool dashed = false;
  bool box = false;  // a filled square (bars) rather than a line
};

// The legend entries laid out in rows no wider than `width`: the row of each entry.
std::vector<int> LegendRows(const std::vector<LegendEntry>& entries, double width) {
  std::vector<int> rows;
  double x = 0.0;
  int row = 0;
  for (const LegendEntry& entry : entries) {
    const double entry_width = kLegendSwatch + 6.0 + TextWidth(entry.name) + 18.0;
    if (x > 0.0 && x + entry_width > width) {
      ++row;
      x = 0.0;
    }
    rows.push_back(row);
    x += entry_width;
  }
  return rows;
}

// A chart being laid out: a drawing of the chart's size with its title on top.
class ChartDrawing {
 public:
  explicit ChartDrawing(const ChartOptions& options) : options_(options), drawing_(Checked(options)) {
    if (!options.title.empty()) Text({.baseline = {kPadding, 18.0}, .text = options.title, .size = 14.0, .bold = true});
  }

  template <typename ShapeType>
  void Add(ShapeType shape) {
    drawing_.Add(std::move(shape));
  }
  void Text(TextShape text) { drawing_.Add(std::move(text)); }
  void Line(double x1, double y1, double x2, double y2, std::string_view colour) {
    drawing_.Add(LineShape{{x1, y1}, {x2, y2}, {.colour = std::string(colour)}});
  }

  // The legend under the title, wrapped to the chart's width; returns the y below it.
  double Legend(const std::vector<LegendEntry>& entries) {
    const double top = options_.title.empty() ? kPadding : kTitleHeight + 4.0;
    const bool any_name = std::any_of(entries.begin(), entries.end(), [](const auto& e) { return !e.name.empty(); });
    if (!any_name) return top;
    const std::vector<int> rows = LegendRows(entries, options_.width - 2.0 * kPadding);
    double x = kPadding;
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (i > 0 && rows[i] != rows[i - 1]) x = kPadding;
      const LegendEntry& entry = entries[i];
      const double y = top + rows[i] * kLegendRowHeight + 9.0;
      if (entry.box) {
        Add(RectShape{.top_left = {x + 3.0, y - 6.0}, .width = 12.0, .height = 12.0, .fill = entry.colour});
      } else {
        // Thick enough that its colour survives anti-aliasing in screenshots and prints.
        Add(LineShape{{x, y}, {x + kLegendSwatch, y}, {.colour = entry.colour, .width = 4.0, .dashed = entry.dashed}});
      }
      Text({.baseline = {x + kLegendSwatch + 6.0, y + 4.0}, .text = entry.name});
      x += kLegendSwatch + 6.0 + TextWidth(entry.name) + 18.0;
    }
    return top + (rows.back() + 1) * kLegendRowHeight;
  }

  // Horizontal grid lines and tick labels of the vertical axis, and its label.
  void ValueAxisLines(const Area& area, const ValueAxis& axis, std::string_view label) {
    for (const double tick : axis.ticks()) {
      const double y = area.Y(axis.Fraction(tick));
      Line(area.left, y, area.left + area.width, y, kGridColour);
      Text({.baseline = {area.left - 6.0, y + 4.0}, .text = axis.TickLabel(tick), .anchor = TextAnchor::kEnd});
    }
    if (!label.empty()) {
      Text({.baseline = {kPadding + kFontSize, area.top + area.height / 2.0},
            .text = std::string(label),
            .anchor = TextAnchor::kMiddle,
            .angle = 90.0});
    }
  }

  // Vertical grid lines and tick labels of a numeric horizontal axis, and its label.
  void HorizontalAxisLines(const Area& area, const ValueAxis& axis, std::string_view label) {
    for (const double tick : axis.ticks()) {
      const double x = area.X(axis.Fraction(tick));
      Line(x, area.top, x, area.bottom(), kGridColour);
      Text({.baseline = {x, area.bottom() + 16.0}, .text = axis.TickLabel(tick), .anchor = TextAnchor::kMiddle});
    }
    if (!label.empty()) {
      Text({.baseline = {area.left + area.width / 2.0, area.bottom() + 34.0},
            .text = std::string(label),
            .anchor = TextAnchor::kMiddle});
    }
  }

  void Frame(const Area& area) {
    Line(area.left, area.top, area.left, area.bottom(), kAxisColour);
    Line(area.left, area.bottom(), area.left + area.width, area.bottom(), kAxisColour);
  }

  Drawing Finish() { return std::move(drawing_); }

 private:
  static Drawing Checked(const ChartOptions& options) {
    if (options.width < 100 || options.height < 100) {
      throw std::invalid_argument(fmt::format("chart size {}x{}: both must be at least 100 pixels", options.width,
                                              options.height));
    }
    return Drawing(options.width, options.height, options.title);
  }

  const ChartOptions& options_;
  Drawing drawing_;
};

// The area left by a title and legend ending at `top`, value-axis tick labels `tick_width` wide, `bottom_extra`
// pixels of labels under the horizontal axis and `right_extra` pixels beside it on the right (a colour bar).
Area PlotArea(const ChartOptions& options, double top, double tick_width, double bottom_extra,
              double right_extra = 0.0) {
  Area area;
  area.left = kPadding + (options.y_label.empty() ? 0.0 : kFontSize + 10.0) + tick_width + 8.0;
  area.top = top + 8.0;
  area.width = std::max(10.0, options.width - area.left - 16.0 - right_extra);
  area.height = std::max(10.0, options.height - area.top - bottom_extra);
  return area;
}

// Consecutive points of a line in pixels; a value that cannot be drawn ends a run.
using PixelRun = std::vector<PixelPoint>;

// The runs of points 0 .. count-1, where `pixel` gives a point's position or nullopt when it cannot be drawn.
std::vector<PixelRun> SplitRuns(std::size_t count, const std::function<std::optional<PixelPoint>(std::size_t)>& pixel) {
  std::vector<PixelRun> runs(1);
  for (std::size_t i = 0; i < count; ++i) {
    if (const auto p = pixel(i)) {
      runs.back().push_back(*p);
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  if (runs.back().empty()) runs.pop_back();
  return runs;
}

void DrawRuns(ChartDrawing& chart, const std::vector<PixelRun>& runs, const Stroke& stroke) {
  for (const PixelRun& run : runs) {
    if (run.size() == 1) {
      chart.Add(CircleShape{.centre = run[0], .radius = std::max(2.5, stroke.width), .fill = stroke.colour});
    } else {
      chart.Add(PolylineShape{run, stroke});
    }
  }
}

// A path plot's frame: the two world axes shown, one scale for both, and the axes drawn.
class PathView {
 public:
  // Lays out the axes for `paths` (the view axes picked by the first path's extent) in `chart` below `top`, leaving
  // `right_extra` pixels on the right; `labelled` is the chart's options with the world axes as labels.
  PathView(ChartDrawing& chart, std::span<const Path3d> paths, const ChartOptions& labelled, std::array<int, 2> axes,
           double top, double right_extra)
      : axes_(axes) {
    Eigen::Vector2d lo(kInf, kInf), hi(-kInf, -kInf);
    for (const Path3d& path : paths) {
      for (const Eigen::Vector3d& p : path.points) {
        if (!p.allFinite()) continue;
        const Eigen::Vector2d q(p[axes[0]], p[axes[1]]);
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    }
    if (lo.x() > hi.x()) lo = hi = Eigen::Vector2d::Zero();  // nothing to draw: an empty metre around 0
    // Tick labels of a room-sized trajectory ("-12.5") are at most this wide; the area is fixed before the ticks
    // are, since the scale depends on the area's shape.
    area_ = PlotArea(labelled, top, TextWidth("-12.50"), 44.0, right_extra);
    // One scale for both axes: the larger of what each axis needs, with 6 % of the larger extent to spare.
    const Eigen::Vector2d extent = hi - lo;
    const double span = extent.maxCoeff() > 0.0 ? extent.maxCoeff() : 1.0;
    const double metres_per_pixel = std::max((extent.x() + 0.12 * span) / area_.width,
                                             (extent.y() + 0.12 * span) / area_.height);
    const Eigen::Vector2d centre = (lo + hi) / 2.0;
    const Eigen::Vector2d half(area_.width * metres_per_pixel / 2.0, area_.height * metres_per_pixel / 2.0);
    const double step = NiceStep(2.0 * half.minCoeff() / 5.0);
    x_axis_ = ValueAxis::Fixed(centre.x() - half.x(), centre.x() + half.x(), step);
    y_axis_ = ValueAxis::Fixed(centre.y() - half.y(), centre.y() + half.y(), step);
    chart.ValueAxisLines(area_, y_axis_, labelled.y_label);
    chart.HorizontalAxisLines(area_, x_axis_, labelled.x_label);
    chart.Frame(area_);
  }

  // Where a world point falls; nullopt for one that is not finite.
  std::optional<PixelPoint> Project(const Eigen::Vector3d& p) const {
    if (!p.allFinite()) return std::nullopt;
    return PixelPoint{area_.X(x_axis_.Fraction(p[axes_[0]])), area_.Y(y_axis_.Fraction(p[axes_[1]]))};
  }

  const Area& area() const { return area_; }

 private:
  std::array<int, 2> axes_;
  Area area_;
  ValueAxis x_axis_;
  ValueAxis y_axis_;
};

// `options` with the world axes LargestExtentAxes picks for the first path as its axis labels.
ChartOptions WorldAxisLabels(const ChartOptions& options, const std::array<int, 2>& axes) {
  constexpr std::string_view kAxisNames[] = {"x", "y", "z"};
  ChartOptions labelled = options;
  labelled.x_label = fmt::format("world {} (m)", kAxisNames[axes[0]]);
  labelled.y_label = fmt::format("world {} (m)", kAxisNames[axes[1]]);
  return labelled;
}

std::array<int, 2> ViewAxes(std::span<const Path3d> paths) {
  return paths.empty() ? std::array<int, 2>{0, 1} : LargestExtentAxes(paths.front().points);
}

// Each path as a line (a dot where it starts), in the order given.
void DrawPaths(ChartDrawing& chart, const PathView& view, std::span<const Path3d> paths,
               const std::vector<LegendEntry>& legend) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::vector<Eigen::Vector3d>& points = paths[i].points;
    const std::vector<PixelRun> runs =
        SplitRuns(points.size(), [&](std::size_t k) { return view.Project(points[k]); });
    DrawRuns(chart, runs, {.colour = legend[i].colour, .width = paths[i].width, .dashed = paths[i].dashed});
    if (!runs.empty()) {
      // A white ring sets the dot off from the line it starts.
      chart.Add(CircleShape{.centre = runs.front().front(),
                            .radius = 4.0,
                            .fill = legend[i].colour,
                            .ring = "#ffffff",
                            .ring_width = 1.5,
                            .tooltip = "start"});
    }
  }
}

std::vector<LegendEntry> PathLegend(std::span<const Path3d> paths) {
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    legend.push_back({paths[i].name, ColourOf(paths[i].colour, i), paths[i].dashed});
  }
  return legend;
}

// Linear interpolation between two "#rrggbb" colours.
std::string MixColours(std::string_view a, std::string_view b, double t) {
  const auto channel = [t](std::string_view x, std::string_view y) {
    const double from = std::stoi(std::string(x), nullptr, 16);
    const double to = std::stoi(std::string(y), nullptr, 16);
    return static_cast<int>(std::lround(from + t * (to - from)));
  };
  return fmt::format("#{:02x}{:02x}{:02x}", channel(a.substr(1, 2), b.substr(1, 2)),
                     channel(a.substr(3, 2), b.substr(3, 2)), channel(a.substr(5, 2), b.substr(5, 2)));
}

constexpr double kColourBarWidth = 14.0;

// The colour bar of `scale` right of `area`: the colours from the low end (bottom) to the high end, ticks, label.
void DrawColourBar(ChartDrawing& chart, const Area& area, const ColourScale& scale) {
  constexpr int kSteps = 64;
  const double left = area.left + area.width + 14.0;
  const double step_height = area.height / kSteps;
  for (int i = 0; i < kSteps; ++i) {
    chart.Add(RectShape{.top_left = {left, area.bottom() - (i + 1) * step_height},
                        .width = kColourBarWidth,
                        .height = step_height + 0.5,  // overlapping the next: no seam where edges blend
                        .fill = SequentialColour((i + 0.5) / kSteps)});
  }
  const ValueAxis axis = ValueAxis::Fixed(scale.low, scale.high, NiceStep((scale.high - scale.low) / 5.0));
  for (const double tick : axis.ticks()) {
    const double y = area.Y(axis.Fraction(tick));
    chart.Line(left + kColourBarWidth, y, left + kColourBarWidth + 4.0, y, kAxisColour);
    chart.Text({.baseline = {left + kColourBarWidth + 8.0, y + 4.0}, .text = axis.TickLabel(tick)});
  }
  if (!scale.label.empty()) {
    chart.Text({.baseline = {left + kColourBarWidth + 8.0 + axis.WidestTickLabel() + 6.0 + kFontSize,
                             area.top + area.height / 2.0},
                .text = scale.label,
                .anchor = TextAnchor::kMiddle,
                .angle = 90.0});
  }
}

}  // namespace

std::string_view PaletteColour(std::size_t index) { return kPalette[index % kPalette.size()]; }

std::string SequentialColour(double fraction) {
  // Dark blue through green to yellow, evenly brighter: the order reads in grey too, and for colour-blind eyes.
  static constexpr std::array<std::string_view, 9> kStops = {"#440154", "#472d7b", "#3b528b", "#2c728e", "#21918c",
                                                             "#28ae80", "#5ec962", "#addc30", "#fde725"};
  const double t = std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0;
  const double position = t * (kStops.size() - 1);
  const auto below = std::min(static_cast<std::size_t>(position), kStops.size() - 2);
  return MixColours(kStops[below], kStops[below + 1], position - static_cast<double>(below));
}

std::string FormatSignificant(double value, int significant) {
  if (!std::isfinite(value)) return "–";
  if (value == 0.0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::abs(value))));
  const int decimals = std::clamp(significant - 1 - magnitude, 0, 12);
  std::string text = fmt::format("{:.{}f}", value, decimals);
  if (decimals > 0) {
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
  }
  return text;
}

Drawing LineChartDrawing(std::span<const LineSeries> series, const ChartOptions& options) {
  double x_min = kInf, x_max = -kInf, y_min = kInf, y_max = -kInf;
  const auto usable = [&options](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && (!options.log_y || y > 0.0);
  };
  for (const LineSeries& s : series) {
    if (s.x.size() != s.y.size()) {
      throw std::invalid_argument(fmt::format("line series '{}': {} x values but {} y values", s.name, s.x.size(),
                                              s.y.size()));
    }
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!usable(s.x[i], s.y[i])) continue;
      x_min = std::min(x_min, s.x[i]);
      x_max = std::max(x_max, s.x[i]);
      y_min = std::min(y_min, s.y[i]);
      y_max = std::max(y_max, s.y[i]);
    }
  }
  // The horizontal axis (usually time) ends where the data does: no empty seconds after the last frame.
  const ValueAxis x_axis =
      x_min > x_max ? ValueAxis::Linear(0.0, 1.0, 8) : ValueAxis::Linear(x_min, x_max, 8, /*round_limits=*/false);
  const ValueAxis y_axis = ValueAxisFor(y_min, y_max, options.log_y, options.y_from_zero);

  ChartDrawing chart(options);
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < series.size(); ++i) legend.push_back({series[i].name, ColourOf(series[i].colour, i)});
  const double top = chart.Legend(legend);
  const Area area = PlotArea(options, top, y_axis.WidestTickLabel(), options.x_label.empty() ? 26.0 : 44.0);
  chart.ValueAxisLines(area, y_axis, options.y_label);
  chart.HorizontalAxisLines(area, x_axis, options.x_label);
  chart.Frame(area);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const LineSeries& s = series[i];
    const std::vector<PixelRun> runs = SplitRuns(s.x.size(), [&](std::size_t k) -> std::optional<PixelPoint> {
      if (!usable(s.x[k], s.y[k])) return std::nullopt;
      return PixelPoint{area.X(x_axis.Fraction(s.x[k])), area.Y(y_axis.Fraction(s.y[k]))};
    });
    DrawRuns(chart, runs, {.colour = legend[i].colour, .width = 2.0});
  }
  return chart.Finish();
}

std::string LineChart(std::span<const LineSeries> series, const ChartOptions& options) {
  return ToSvg(LineChartDrawing(series, options));
}

std::array<int, 2> LargestExtentAxes(std::span<const Eigen::Vector3d> points) {
  if (points.size() < 2) return {0, 1};
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d extent = hi - lo;
  int smallest = 2;  // the axis left out; on a tie the later one, so a flat path keeps x and y
  for (int axis = 1; axis >= 0; --axis) {
    if (extent[axis] < extent[smallest]) smallest = axis;
  }
  if (smallest == 0) return {1, 2};
  if (smallest == 1) return {0, 2};
  return {0, 1};
}

Drawing PathPlotDrawing(std::span<const Path3d> paths, const ChartOptions& options) {
  const std::array<int, 2> axes = ViewAxes(paths);
  const ChartOptions labelled = WorldAxisLabels(options, axes);
  ChartDrawing chart(labelled);
  const std::vector<LegendEntry> legend = PathLegend(paths);
  const PathView view(chart, paths, labelled, axes, chart.Legend(legend), 0.0);
  DrawPaths(chart, view, paths, legend);
  return chart.Finish();
}

std::string PathPlot(std::span<const Path3d> paths, const ChartOptions& options) {
  return ToSvg(PathPlotDrawing(paths, options));
}

Drawing ValuePathPlotDrawing(std::span<const Path3d> references, const ValuePath& path, const ColourScale& scale,
                             const ChartOptions& options) {
  if (path.points.size() != path.values.size()) {
    throw std::invalid_argument(fmt::format("value path '{}': {} points but {} values", path.name, path.points.size(),
                                            path.values.size()));
  }
  if (!(scale.high > scale.low)) {
    throw std::invalid_argument(fmt::format("colour scale [{}, {}] is empty", scale.low, scale.high));
  }
  std::vector<Path3d> all(references.begin(), references.end());
  all.push_back({path.name, path.points, SequentialColour(0.5)});  // its legend swatch: the middle of the scale
  const std::array<int, 2> axes = ViewAxes(all);
  const ChartOptions labelled = WorldAxisLabels(options, axes);
  ChartDrawing chart(labelled);
  const std::vector<LegendEntry> legend = PathLegend(all);
  const double tick_width = TextWidth(FormatSignificant(scale.high, 3)) + TextWidth("0");
  const double colour_bar_room = 14.0 + kColourBarWidth + 8.0 + tick_width + 6.0 + kFontSize + 4.0;
  const PathView view(chart, all, labelled, axes, chart.Legend(legend), colour_bar_room);
  DrawPaths(chart, view, references, legend);
  // One short line per step, in the colour of the value where it ends.
  for (std::size_t k = 1; k < path.points.size(); ++k) {
    const std::optional<PixelPoint> from = view.Project(path.points[k - 1]);
    const std::optional<PixelPoint> to = view.Project(path.points[k]);
    if (!from || !to || !std::isfinite(path.values[k])) continue;
    const std::string colour = SequentialColour((path.values[k] - scale.low) / (scale.high - scale.low));
    chart.Add(PolylineShape{{*from, *to}, {.colour = colour, .width = 3.0}});
  }
  DrawColourBar(chart, view.area(), scale);
  return chart.Finish();
}

std::string BarChart(std::span<const std::string> categories, std::span<const BarSeries> series,
                     const BarChartOptions& options) {
  if (options.significant_digits < 1) throw std::invalid_argument("BarChartOptions::significant_digits must be >= 1");
  const ChartOptions& chart_options = options.chart;
  const bool stacked = options.layout == BarLayout::kStacked;
  const auto shown = [&chart_options, stacked](double v) {
    return std::isfinite(v) && (!chart_options.log_y || v > 0.0) && (!stacked || v > 0.0);
  };
  double v_min = kInf, v_max = -kInf;
  for (const BarSeries& s : series) {
    if (s.values.size() != categories.size()) {
      throw std::invalid_argument(fmt::format("bar series '{}': {} values for {} categories", s.name, s.values.size(),
                                              categories.size()));
    }
  }
  std::vector<double> totals(categories.size(), 0.0);  // stacked: the height of each stack
  for (const BarSeries& s : series) {
    for (std::size_t c = 0; c < categories.size(); ++c) {
      if (!shown(s.values[c])) continue;
      totals[c] += s.values[c];
      v_min = std::min(v_min, s.values[c]);
      v_max = std::max(v_max, stacked ? totals[c] : s.values[c]);
    }
  }
  const ValueAxis axis = ValueAxisFor(v_min, v_max, chart_options.log_y, /*from_zero=*/true);

  ChartDrawing chart(chart_options);
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < series.size(); ++i) {
    legend.push_back({series[i].name, ColourOf(series[i].colour, i), false, true});
  }
  const double legend_bottom = chart.Legend(legend);
  const double label_room = options.value_labels ? 14.0 : 0.0;
  // Category labels slant when the widest does not fit under its group.
  double widest = 0.0;
  for (const std::string& c : categories) widest = std::max(widest, TextWidth(c));
  Area area = PlotArea(chart_options, legend_bottom + label_room, axis.WidestTickLabel(), 0.0);
  const double group = area.width / std::max<std::size_t>(1, categories.size());
  const bool slanted = widest > group - 6.0;
  const double category_height = slanted ? widest * 0.5 + 22.0 : 22.0;
  area.height = std::max(10.0, area.height - category_height - (chart_options.x_label.empty() ? 6.0 : 24.0));

  chart.ValueAxisLines(area, axis, chart_options.y_label);
  chart.Frame(area);
  const double base = area.Y(chart_options.log_y ? 0.0 : axis.Fraction(0.0));
  const double inner = group * 0.78;
  const double slot = stacked ? std::min(inner, 64.0) : std::min(inner / std::max<std::size_t>(1, series.size()), 48.0);
  for (std::size_t c = 0; c < categories.size(); ++c) {
    const double centre = area.left + (c + 0.5) * group;
    if (slanted) {
      chart.Text({.baseline = {centre, area.bottom() + 14.0},
                  .text = categories[c],
                  .anchor = TextAnchor::kEnd,
                  .angle = 30.0});
    } else {
      chart.Text({.baseline = {centre, area.bottom() + 16.0}, .text = categories[c], .anchor = TextAnchor::kMiddle});
    }
    double below = 0.0;  // stacked: the sum of the values drawn under this one
    for (std::size_t s = 0; s < series.size(); ++s) {
      const double value = series[s].values[c];
      const double x = stacked ? centre - slot / 2.0 : centre - slot * series.size() / 2.0 + s * slot;
      const std::string label = FormatSignificant(value, options.significant_digits);
      const std::string tooltip = fmt::format("{} · {}: {}", series[s].name, categories[c], label);
      if (!shown(value)) {
        if (!stacked) {
          chart.Text({.baseline = {x + slot / 2.0, base - 4.0},
                      .text = "×",
                      .anchor = TextAnchor::kMiddle,
                      .tooltip = tooltip});
        }
        continue;
      }
      const double from = stacked && below > 0.0 ? area.Y(axis.Fraction(below)) : base;
      const double to = area.Y(axis.Fraction(stacked ? below + value : value));
      below += stacked ? value : 0.0;
      chart.Add(RectShape{.top_left = {x + 1.0, std::min(from, to)},
                          .width = std::max(1.0, slot - 2.0),
                          .height = std::abs(from - to),
                          .fill = legend[s].colour,
                          .tooltip = tooltip});
      if (options.value_labels && !stacked && TextWidth(label, 10.0) <= slot) {
        chart.Text({.baseline = {x + slot / 2.0, std::min(from, to) - 4.0},
                    .text = label,
                    .anchor = TextAnchor::kMiddle,
                    .size = 10.0});
      }
    }
    const std::string total = FormatSignificant(below, options.significant_digits);
    if (options.value_labels && stacked && below > 0.0 && TextWidth(total, 10.0) <= group) {
      chart.Text({.baseline = {centre, area.Y(axis.Fraction(below)) - 4.0},
                  .text = total,
                  .anchor = TextAnchor::kMiddle,
                  .size = 10.0});
    }
  }
  if (!chart_options.x_label.empty()) {
    chart.Text({.baseline = {area.left + area.width / 2.0, area.bottom() + category_height + 16.0},
                .text = chart_options.x_label,
                .anchor = TextAnchor::kMiddle});
  }
  return ToSvg(chart.Finish());
}

}  // namespace hoidslam::report
