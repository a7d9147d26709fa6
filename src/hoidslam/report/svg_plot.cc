#include "hoidslam/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

namespace hoidslam::report {
namespace {

// Okabe and Ito's colour-blind safe palette, yellow last (it is hard to see on white).
constexpr std::array<std::string_view, 8> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                      "#E69F00", "#56B4E9", "#000000", "#F0E442"};
constexpr std::string_view kFont = "system-ui, -apple-system, 'Segoe UI', Roboto, Helvetica, Arial, sans-serif";
constexpr std::string_view kTextColour = "#333333";
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

// Pixel coordinates with one decimal: enough for any screen, and short.
std::string Px(double value) { return fmt::format("{:.1f}", value); }

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

// A chart being written: the SVG element, a white background and the title.
class Svg {
 public:
  explicit Svg(const ChartOptions& options) : options_(options) {
    if (options.width < 100 || options.height < 100) {
      throw std::invalid_argument(fmt::format("chart size {}x{}: both must be at least 100 pixels", options.width,
                                              options.height));
    }
    Add(R"(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {0} {1}" width="{0}" height="{1}" )"
        R"(font-family="{2}" font-size="{3}" fill="{4}" role="img">)",
        options.width, options.height, kFont, kFontSize, kTextColour);
    if (!options.title.empty()) Add("<title>{}</title>", EscapeXml(options.title));
    Add(R"(<rect width="{}" height="{}" fill="#ffffff"/>)", options.width, options.height);
    if (!options.title.empty()) {
      Text(kPadding, 18.0, options.title, "start", R"( font-size="14" font-weight="600")");
    }
  }

  template <typename... Args>
  void Add(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(text_), format, std::forward<Args>(args)...);
  }

  // Text at (x, y) (the baseline); `extra` holds further attributes, each with a leading space.
  void Text(double x, double y, std::string_view text, std::string_view anchor, std::string_view extra = "") {
    Add(R"(<text x="{}" y="{}" text-anchor="{}"{}>{}</text>)", Px(x), Px(y), anchor, extra, EscapeXml(text));
  }

  void Line(double x1, double y1, double x2, double y2, std::string_view colour) {
    Add(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{}"/>)", Px(x1), Px(y1), Px(x2), Px(y2), colour);
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
        Add(R"(<rect x="{}" y="{}" width="12" height="12" fill="{}"/>)", Px(x + 3.0), Px(y - 6.0), entry.colour);
      } else {
        // Thick enough that its colour survives anti-aliasing in screenshots and prints.
        Add(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{}" stroke-width="4"{}/>)", Px(x), Px(y),
            Px(x + kLegendSwatch), Px(y), entry.colour, entry.dashed ? R"( stroke-dasharray="5 3")" : "");
      }
      Text(x + kLegendSwatch + 6.0, y + 4.0, entry.name, "start");
      x += kLegendSwatch + 6.0 + TextWidth(entry.name) + 18.0;
    }
    return top + (rows.back() + 1) * kLegendRowHeight;
  }

  // Horizontal grid lines and tick labels of the vertical axis, and its label.
  void ValueAxisLines(const Area& area, const ValueAxis& axis, std::string_view label) {
    for (const double tick : axis.ticks()) {
      const double y = area.Y(axis.Fraction(tick));
      Line(area.left, y, area.left + area.width, y, kGridColour);
      Text(area.left - 6.0, y + 4.0, axis.TickLabel(tick), "end");
    }
    if (!label.empty()) {
      const double x = kPadding + kFontSize;
      const double y = area.top + area.height / 2.0;
      Text(x, y, label, "middle", fmt::format(R"x( transform="rotate(-90 {} {})")x", Px(x), Px(y)));
    }
  }

  // Vertical grid lines and tick labels of a numeric horizontal axis, and its label.
  void HorizontalAxisLines(const Area& area, const ValueAxis& axis, std::string_view label) {
    for (const double tick : axis.ticks()) {
      const double x = area.X(axis.Fraction(tick));
      Line(x, area.top, x, area.bottom(), kGridColour);
      Text(x, area.bottom() + 16.0, axis.TickLabel(tick), "middle");
    }
    if (!label.empty()) Text(area.left + area.width / 2.0, area.bottom() + 34.0, label, "middle");
  }

  void Frame(const Area& area) {
    Line(area.left, area.top, area.left, area.bottom(), kAxisColour);
    Line(area.left, area.bottom(), area.left + area.width, area.bottom(), kAxisColour);
  }

  std::string Finish() {
    text_ += "</svg>";
    return std::move(text_);
  }

 private:
  const ChartOptions& options_;
  std::string text_;
};

// The area left by a title and legend ending at `top`, value-axis tick labels `tick_width` wide, and
// `bottom_extra` pixels of labels under the horizontal axis.
Area PlotArea(const ChartOptions& options, double top, double tick_width, double bottom_extra) {
  Area area;
  area.left = kPadding + (options.y_label.empty() ? 0.0 : kFontSize + 10.0) + tick_width + 8.0;
  area.top = top + 8.0;
  area.width = std::max(10.0, options.width - area.left - 16.0);
  area.height = std::max(10.0, options.height - area.top - bottom_extra);
  return area;
}

// Consecutive points of a line in pixels; a value that cannot be drawn ends a run.
using PixelRun = std::vector<std::pair<double, double>>;

// The runs of points 0 .. count-1, where `pixel` gives a point's position or nullopt when it cannot be drawn.
std::vector<PixelRun> SplitRuns(std::size_t count,
                                const std::function<std::optional<std::pair<double, double>>(std::size_t)>& pixel) {
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

void DrawRuns(Svg& svg, const std::vector<PixelRun>& runs, std::string_view colour, double width, bool dashed) {
  for (const PixelRun& run : runs) {
    if (run.size() == 1) {
      svg.Add(R"(<circle cx="{}" cy="{}" r="{}" fill="{}"/>)", Px(run[0].first), Px(run[0].second),
              Px(std::max(2.5, width)), colour);
      continue;
    }
    std::string points;
    for (const auto& [x, y] : run) fmt::format_to(std::back_inserter(points), "{},{} ", Px(x), Px(y));
    points.pop_back();
    svg.Add(R"(<polyline fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round"{} )"
            R"(points="{}"/>)",
            colour, Px(width), dashed ? R"( stroke-dasharray="6 4")" : "", points);
  }
}

}  // namespace

std::string_view PaletteColour(std::size_t index) { return kPalette[index % kPalette.size()]; }

std::string EscapeXml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
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

std::string LineChart(std::span<const LineSeries> series, const ChartOptions& options) {
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

  Svg svg(options);
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < series.size(); ++i) legend.push_back({series[i].name, ColourOf(series[i].colour, i)});
  const double top = svg.Legend(legend);
  const Area area = PlotArea(options, top, y_axis.WidestTickLabel(), options.x_label.empty() ? 26.0 : 44.0);
  svg.ValueAxisLines(area, y_axis, options.y_label);
  svg.HorizontalAxisLines(area, x_axis, options.x_label);
  svg.Frame(area);
  for (std::size_t i = 0; i < series.size(); ++i) {
    const LineSeries& s = series[i];
    const std::vector<PixelRun> runs =
        SplitRuns(s.x.size(), [&](std::size_t k) -> std::optional<std::pair<double, double>> {
          if (!usable(s.x[k], s.y[k])) return std::nullopt;
          return std::pair(area.X(x_axis.Fraction(s.x[k])), area.Y(y_axis.Fraction(s.y[k])));
        });
    DrawRuns(svg, runs, legend[i].colour, 2.0, false);
  }
  return svg.Finish();
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

std::string PathPlot(std::span<const Path3d> paths, const ChartOptions& options) {
  constexpr std::string_view kAxisNames[] = {"x", "y", "z"};
  const std::array<int, 2> axes =
      paths.empty() ? std::array<int, 2>{0, 1} : LargestExtentAxes(paths.front().points);
  ChartOptions labelled = options;
  labelled.x_label = fmt::format("world {} (m)", kAxisNames[axes[0]]);
  labelled.y_label = fmt::format("world {} (m)", kAxisNames[axes[1]]);

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

  Svg svg(labelled);
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    legend.push_back({paths[i].name, ColourOf(paths[i].colour, i), paths[i].dashed});
  }
  const double top = svg.Legend(legend);
  // Tick labels of a room-sized trajectory ("-12.5") are at most this wide; the area is fixed before the ticks
  // are, since the scale depends on the area's shape.
  const Area area = PlotArea(labelled, top, TextWidth("-12.50"), 44.0);
  // One scale for both axes: the larger of what each axis needs, with 6 % of the larger extent to spare.
  const Eigen::Vector2d extent = hi - lo;
  const double span = extent.maxCoeff() > 0.0 ? extent.maxCoeff() : 1.0;
  const double metres_per_pixel = std::max((extent.x() + 0.12 * span) / area.width,
                                           (extent.y() + 0.12 * span) / area.height);
  const Eigen::Vector2d centre = (lo + hi) / 2.0;
  const Eigen::Vector2d half(area.width * metres_per_pixel / 2.0, area.height * metres_per_pixel / 2.0);
  const double step = NiceStep(2.0 * half.minCoeff() / 5.0);
  const ValueAxis x_axis = ValueAxis::Fixed(centre.x() - half.x(), centre.x() + half.x(), step);
  const ValueAxis y_axis = ValueAxis::Fixed(centre.y() - half.y(), centre.y() + half.y(), step);
  svg.ValueAxisLines(area, y_axis, labelled.y_label);
  svg.HorizontalAxisLines(area, x_axis, labelled.x_label);
  svg.Frame(area);

  for (std::size_t i = 0; i < paths.size(); ++i) {
    const std::vector<Eigen::Vector3d>& points = paths[i].points;
    const std::vector<PixelRun> runs =
        SplitRuns(points.size(), [&](std::size_t k) -> std::optional<std::pair<double, double>> {
          if (!points[k].allFinite()) return std::nullopt;
          return std::pair(area.X(x_axis.Fraction(points[k][axes[0]])), area.Y(y_axis.Fraction(points[k][axes[1]])));
        });
    DrawRuns(svg, runs, legend[i].colour, paths[i].width, paths[i].dashed);
    if (!runs.empty()) {
      svg.Add(R"(<circle cx="{}" cy="{}" r="4" fill="{}" stroke="#ffffff" stroke-width="1.5"><title>start</title>)"
              R"(</circle>)",
              Px(runs.front().front().first), Px(runs.front().front().second), legend[i].colour);
    }
  }
  return svg.Finish();
}

std::string BarChart(std::span<const std::string> categories, std::span<const BarSeries> series,
                     const BarChartOptions& options) {
  if (options.significant_digits < 1) throw std::invalid_argument("BarChartOptions::significant_digits must be >= 1");
  const ChartOptions& chart = options.chart;
  const bool stacked = options.layout == BarLayout::kStacked;
  const auto shown = [&chart, stacked](double v) {
    return std::isfinite(v) && (!chart.log_y || v > 0.0) && (!stacked || v > 0.0);
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
  const ValueAxis axis = ValueAxisFor(v_min, v_max, chart.log_y, /*from_zero=*/true);

  Svg svg(chart);
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < series.size(); ++i) {
    legend.push_back({series[i].name, ColourOf(series[i].colour, i), false, true});
  }
  const double legend_bottom = svg.Legend(legend);
  const double label_room = options.value_labels ? 14.0 : 0.0;
  // Category labels slant when the widest does not fit under its group.
  double widest = 0.0;
  for (const std::string& c : categories) widest = std::max(widest, TextWidth(c));
  Area area = PlotArea(chart, legend_bottom + label_room, axis.WidestTickLabel(), 0.0);
  const double group = area.width / std::max<std::size_t>(1, categories.size());
  const bool slanted = widest > group - 6.0;
  const double category_height = slanted ? widest * 0.5 + 22.0 : 22.0;
  area.height = std::max(10.0, area.height - category_height - (chart.x_label.empty() ? 6.0 : 24.0));

  svg.ValueAxisLines(area, axis, chart.y_label);
  svg.Frame(area);
  const double base = area.Y(chart.log_y ? 0.0 : axis.Fraction(0.0));
  const double inner = group * 0.78;
  const double slot = stacked ? std::min(inner, 64.0) : std::min(inner / std::max<std::size_t>(1, series.size()), 48.0);
  for (std::size_t c = 0; c < categories.size(); ++c) {
    const double centre = area.left + (c + 0.5) * group;
    if (slanted) {
      const double y = area.bottom() + 14.0;
      svg.Text(centre, y, categories[c], "end", fmt::format(R"x( transform="rotate(-30 {} {})")x", Px(centre), Px(y)));
    } else {
      svg.Text(centre, area.bottom() + 16.0, categories[c], "middle");
    }
    double below = 0.0;  // stacked: the sum of the values drawn under this one
    for (std::size_t s = 0; s < series.size(); ++s) {
      const double value = series[s].values[c];
      const double x = stacked ? centre - slot / 2.0 : centre - slot * series.size() / 2.0 + s * slot;
      const std::string label = FormatSignificant(value, options.significant_digits);
      const std::string tooltip = EscapeXml(fmt::format("{} · {}: {}", series[s].name, categories[c], label));
      if (!shown(value)) {
        if (!stacked) {
          svg.Add(R"(<text x="{}" y="{}" text-anchor="middle" fill="{}"><title>{}</title>×</text>)",
                  Px(x + slot / 2.0), Px(base - 4.0), kAxisColour, tooltip);
        }
        continue;
      }
      const double from = stacked && below > 0.0 ? area.Y(axis.Fraction(below)) : base;
      const double to = area.Y(axis.Fraction(stacked ? below + value : value));
      below += stacked ? value : 0.0;
      svg.Add(R"(<rect x="{}" y="{}" width="{}" height="{}" fill="{}"><title>{}</title></rect>)", Px(x + 1.0),
              Px(std::min(from, to)), Px(std::max(1.0, slot - 2.0)), Px(std::abs(from - to)), legend[s].colour,
              tooltip);
      if (options.value_labels && !stacked && TextWidth(label, 10.0) <= slot) {
        svg.Text(x + slot / 2.0, std::min(from, to) - 4.0, label, "middle", R"( font-size="10")");
      }
    }
    const std::string total = FormatSignificant(below, options.significant_digits);
    if (options.value_labels && stacked && below > 0.0 && TextWidth(total, 10.0) <= group) {
      svg.Text(centre, area.Y(axis.Fraction(below)) - 4.0, total, "middle", R"( font-size="10")");
    }
  }
  if (!chart.x_label.empty()) {
    svg.Text(area.left + area.width / 2.0, area.bottom() + category_height + 16.0, chart.x_label, "middle");
  }
  return svg.Finish();
}

}  // namespace hoidslam::report
