#pragma once
// A chart as a list of shapes (lines, polylines, circles, rectangles, text) in pixel coordinates, drawn in order
// on a white background. The charts (svg_plot.h) lay themselves out once, into a Drawing; the Drawing is then
// written as SVG text (ToSvg) or painted into an image (raster.h), so the page and the PNG of a figure agree to
// the pixel on where everything is.

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace hoidslam::report {

// Pixels from the top left corner, y downwards.
struct PixelPoint {
  double x = 0.0;
  double y = 0.0;
};

// Colours are CSS "#rrggbb" strings (PaletteColour gives them), which both the SVG and the image backend read.
inline constexpr std::string_view kTextColour = "#333333";

struct Stroke {
  std::string colour{};
  double width = 1.0;   // pixels
  bool dashed = false;  // 6 px on, 4 px off
};

struct LineShape {
  PixelPoint from{};
  PixelPoint to{};
  Stroke stroke{};
};

// Joined with round joins and ends; at least two points.
struct PolylineShape {
  std::vector<PixelPoint> points{};
  Stroke stroke{};
};

struct CircleShape {
  PixelPoint centre{};
  double radius = 1.0;
  std::string fill{};
  std::string ring{};       // the colour of a line around it; empty: none
  double ring_width = 1.0;  // pixels
  std::string tooltip{};    // shown on hover in a browser; not in images
};

struct RectShape {
  PixelPoint top_left{};
  double width = 0.0;
  double height = 0.0;
  std::string fill{};
  std::string tooltip{};
};

enum class TextAnchor { kStart, kMiddle, kEnd };

struct TextShape {
  PixelPoint baseline{};  // where the anchor of the baseline is
  std::string text{};     // UTF-8
  TextAnchor anchor = TextAnchor::kStart;
  double size = 12.0;     // font size, pixels
  bool bold = false;
  double angle = 0.0;     // degrees, turned anticlockwise about `baseline` (90: read upwards, a value axis label)
  std::string tooltip{};
};

using Shape = std::variant<LineShape, PolylineShape, CircleShape, RectShape, TextShape>;

class Drawing {
 public:
  // `title`: the drawing's accessible name (the SVG's <title>); may be empty. Throws std::invalid_argument for a
  // size below 1 pixel.
  Drawing(int width, int height, std::string title = {});

  template <typename ShapeType>
  void Add(ShapeType shape) {
    shapes_.emplace_back(std::in_place_type<ShapeType>, std::move(shape));
  }
  // Every shape of `other`, moved by `offset`: panels side by side in one figure.
  void Place(const Drawing& other, PixelPoint offset);

  int width() const { return width_; }
  int height() const { return height_; }
  const std::string& title() const { return title_; }
  std::span<const Shape> shapes() const { return shapes_; }

 private:
  int width_;
  int height_;
  std::string title_;
  std::vector<Shape> shapes_;
};

// "&", "<", ">", '"' and "'" as entities: text safe inside SVG/HTML elements and attribute values.
std::string EscapeXml(std::string_view text);

// One <svg> element (inline in HTML, or a file of its own) with the drawing's size as its coordinate system.
std::string ToSvg(const Drawing& drawing);

}  // namespace hoidslam::report
