#include "hoidslam/report/raster.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace hoidslam::report {
namespace {

// OpenCV draws at fractional positions given as integers scaled by 2^kShift.
constexpr int kShift = 4;
constexpr double kSubpixel = 1 << kShift;
constexpr double kDashOn = 6.0;  // as ToSvg's stroke-dasharray="6 4"
constexpr double kDashOff = 4.0;
// The height of a capital over the font size, for a sans-serif font as browsers draw it.
constexpr double kCapHeightPerFontSize = 0.7;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

cv::Point Fixed(PixelPoint p) {
  return {static_cast<int>(std::lround(p.x * kSubpixel)), static_cast<int>(std::lround(p.y * kSubpixel))};
}

int Thickness(double width) { return std::max(1, static_cast<int>(std::lround(width))); }

cv::Scalar ParseColour(const std::string& colour) {
  const auto hex = [&colour](std::size_t at) {
    std::size_t used = 0;
    const int value = std::stoi(colour.substr(at, 2), &used, 16);
    if (used != 2) throw std::invalid_argument("");
    return value;
  };
  try {
    if (colour.size() == 7 && colour[0] == '#') return cv::Scalar(hex(5), hex(3), hex(1));
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(fmt::format("colour '{}': images take \"#rrggbb\" colours only", colour));
}

// The pieces of a polyline that a dash pattern draws.
std::vector<std::vector<PixelPoint>> Dashes(const std::vector<PixelPoint>& points) {
  std::vector<std::vector<PixelPoint>> dashes;
  bool on = true;
  double left = kDashOn;  // of the current dash or gap
  std::vector<PixelPoint> current;
  for (std::size_t i = 1; i < points.size(); ++i) {
    PixelPoint from = points[i - 1];
    const PixelPoint to = points[i];
    double length = std::hypot(to.x - from.x, to.y - from.y);
    if (on && current.empty()) current.push_back(from);
    while (length > left) {
      const double t = left / length;
      const PixelPoint cut{from.x + t * (to.x - from.x), from.y + t * (to.y - from.y)};
      if (on) {
        current.push_back(cut);
        dashes.push_back(std::move(current));
        current.clear();
      } else {
        current.push_back(cut);
      }
      length -= left;
      from = cut;
      on = !on;
      left = on ? kDashOn : kDashOff;
    }
    left -= length;
    if (on) current.push_back(to);
  }
  if (on && current.size() >= 2) dashes.push_back(std::move(current));
  return dashes;
}

void DrawPolyline(cv::Mat& image, const std::vector<PixelPoint>& points, const Stroke& stroke) {
  const cv::Scalar colour = ParseColour(stroke.colour);
  const std::vector<std::vector<PixelPoint>> pieces =
      stroke.dashed ? Dashes(points) : std::vector<std::vector<PixelPoint>>{points};
  std::vector<std::vector<cv::Point>> fixed;
  for (const std::vector<PixelPoint>& piece : pieces) {
    std::vector<cv::Point>& line = fixed.emplace_back();
    for (const PixelPoint& p : piece) line.push_back(Fixed(p));
  }
  cv::polylines(image, fixed, false, colour, Thickness(stroke.width), cv::LINE_AA, kShift);
}

// The text with every character outside ASCII replaced by its nearest ASCII, or '?'.
std::string Ascii(std::string_view utf8) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 5> kNearest = {
      {{"×", "x"}, {"–", "-"}, {"—", "-"}, {"·", "."}, {"°", " deg"}}};
  std::string out;
  for (std::size_t i = 0; i < utf8.size();) {
    const auto byte = static_cast<unsigned char>(utf8[i]);
    if (byte < 0x80) {
      out += utf8[i++];
      continue;
    }
    const std::size_t length = byte >= 0xF0 ? 4 : byte >= 0xE0 ? 3 : byte >= 0xC0 ? 2 : 1;
    const std::string_view character = utf8.substr(i, length);
    const auto nearest = std::find_if(kNearest.begin(), kNearest.end(),
                                      [&](const auto& entry) { return entry.first == character; });
    out += nearest == kNearest.end() ? "?" : nearest->second;
    i += length;
  }
  return out;
}

// `colour` blended into `image` through `coverage` (0..255), whose top left corner lands at `corner`.
void Blend(cv::Mat& image, const cv::Mat& coverage, cv::Point corner, const cv::Scalar& colour) {
  const cv::Rect placed(corner, coverage.size());
  const cv::Rect visible = placed & cv::Rect(0, 0, image.cols, image.rows);
  for (int y = visible.y; y < visible.y + visible.height; ++y) {
    for (int x = visible.x; x < visible.x + visible.width; ++x) {
      const double alpha = coverage.at<unsigned char>(y - corner.y, x - corner.x) / 255.0;
      if (alpha == 0.0) continue;
      cv::Vec3b& pixel = image.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) {
        pixel[c] = cv::saturate_cast<unsigned char>(pixel[c] * (1.0 - alpha) + colour[c] * alpha);
      }
    }
  }
}

void DrawText(cv::Mat& image, const TextShape& text) {
  const std::string ascii = Ascii(text.text);
  if (ascii.empty()) return;
  const int font = text.bold ? cv::FONT_HERSHEY_DUPLEX : cv::FONT_HERSHEY_SIMPLEX;
  int unused = 0;
  const double cap_height_at_scale_1 = cv::getTextSize("X", font, 1.0, 1, &unused).height;
  const double scale = text.size * kCapHeightPerFontSize / cap_height_at_scale_1;
  int descent = 0;
  const cv::Size size = cv::getTextSize(ascii, font, scale, 1, &descent);
  // The text drawn level into a coverage mask with a little room around it, then turned about its anchor.
  constexpr int kMargin = 2;
  cv::Mat coverage = cv::Mat::zeros(size.height + descent + 2 * kMargin, size.width + 2 * kMargin, CV_8U);
  const cv::Point origin(kMargin, kMargin + size.height);  // the baseline's start inside the mask
  cv::putText(coverage, ascii, origin, font, scale, cv::Scalar(255), 1, cv::LINE_AA);
  const double along = text.anchor == TextAnchor::kStart   ? 0.0
                       : text.anchor == TextAnchor::kMiddle ? size.width / 2.0
                                                            : static_cast<double>(size.width);
  cv::Point2d anchor(origin.x + along, origin.y);
  if (text.angle != 0.0) {
    cv::Matx23d turn = cv::getRotationMatrix2D(anchor, text.angle, 1.0);  // positive: anticlockwise on screen
    double min_x = kInfinity, min_y = kInfinity, max_x = -kInfinity, max_y = -kInfinity;
    for (const cv::Point2d corner : {cv::Point2d(0, 0), cv::Point2d(coverage.cols, 0), cv::Point2d(0, coverage.rows),
                                     cv::Point2d(coverage.cols, coverage.rows)}) {
      const cv::Point2d turned(turn(0, 0) * corner.x + turn(0, 1) * corner.y + turn(0, 2),
                               turn(1, 0) * corner.x + turn(1, 1) * corner.y + turn(1, 2));
      min_x = std::min(min_x, turned.x);
      min_y = std::min(min_y, turned.y);
      max_x = std::max(max_x, turned.x);
      max_y = std::max(max_y, turned.y);
    }
    turn(0, 2) -= min_x;
    turn(1, 2) -= min_y;
    cv::Mat turned;
    cv::warpAffine(coverage, turned, turn,
                   cv::Size(static_cast<int>(std::ceil(max_x - min_x)), static_cast<int>(std::ceil(max_y - min_y))));
    coverage = turned;
    anchor -= cv::Point2d(min_x, min_y);  // the anchor is the centre of the turn: it stays, the mask moved
  }
  const cv::Point corner(static_cast<int>(std::lround(text.baseline.x - anchor.x)),
                         static_cast<int>(std::lround(text.baseline.y - anchor.y)));
  Blend(image, coverage, corner, ParseColour(std::string(kTextColour)));
}

struct ImageShapePainter {
  cv::Mat& image;

  void operator()(const LineShape& line) const { DrawPolyline(image, {line.from, line.to}, line.stroke); }
  void operator()(const PolylineShape& polyline) const { DrawPolyline(image, polyline.points, polyline.stroke); }
  void operator()(const CircleShape& circle) const {
    const int radius = static_cast<int>(std::lround(circle.radius * kSubpixel));
    cv::circle(image, Fixed(circle.centre), radius, ParseColour(circle.fill), cv::FILLED, cv::LINE_AA, kShift);
    if (!circle.ring.empty()) {
      cv::circle(image, Fixed(circle.centre), radius, ParseColour(circle.ring), Thickness(circle.ring_width),
                 cv::LINE_AA, kShift);
    }
  }
  void operator()(const RectShape& rect) const {
    // Corners on whole pixels, so that rectangles side by side (a colour bar) leave no seam between them.
    const cv::Point top_left(static_cast<int>(std::lround(rect.top_left.x)),
                             static_cast<int>(std::lround(rect.top_left.y)));
    const cv::Point bottom_right(static_cast<int>(std::lround(rect.top_left.x + rect.width)),
                                 static_cast<int>(std::lround(rect.top_left.y + rect.height)));
    if (bottom_right.x <= top_left.x || bottom_right.y <= top_left.y) return;
    cv::rectangle(image, cv::Rect(top_left, bottom_right), ParseColour(rect.fill), cv::FILLED);
  }
  void operator()(const TextShape& text) const { DrawText(image, text); }
};

}  // namespace

cv::Mat RenderImage(const Drawing& drawing) {
  cv::Mat image(drawing.height(), drawing.width(), CV_8UC3, cv::Scalar(255, 255, 255));
  const ImageShapePainter painter{image};
  for (const Shape& shape : drawing.shapes()) std::visit(painter, shape);
  return image;
}

}  // namespace hoidslam::report
