#include "hoidslam/report/drawing.h"

#include <iterator>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

namespace hoidslam::report {
namespace {

constexpr std::string_view kFont = "system-ui, -apple-system, 'Segoe UI', Roboto, Helvetica, Arial, sans-serif";
constexpr double kDefaultFontSize = 12.0;

// Pixel coordinates with one decimal: enough for any screen, and short.
std::string Px(double value) { return fmt::format("{:.1f}", value); }

PixelPoint Moved(PixelPoint p, PixelPoint offset) { return {p.x + offset.x, p.y + offset.y}; }

// The stroke's attributes after stroke="...": width when not 1 pixel, the dash pattern when dashed.
std::string StrokeAttributes(const Stroke& stroke) {
  std::string attributes = fmt::format(R"( stroke="{}")", stroke.colour);
  if (stroke.width != 1.0) attributes += fmt::format(R"( stroke-width="{}")", Px(stroke.width));
  if (stroke.dashed) attributes += R"( stroke-dasharray="6 4")";
  return attributes;
}

// An element that may carry a tooltip: `<name attributes/>`, or with a <title> child.
std::string Element(std::string_view name, const std::string& attributes, const std::string& tooltip) {
  if (tooltip.empty()) return fmt::format("<{}{}/>", name, attributes);
  return fmt::format("<{0}{1}><title>{2}</title></{0}>", name, attributes, EscapeXml(tooltip));
}

std::string_view AnchorName(TextAnchor anchor) {
  switch (anchor) {
    case TextAnchor::kStart: return "start";
    case TextAnchor::kMiddle: return "middle";
    case TextAnchor::kEnd: return "end";
  }
  return "start";
}

struct SvgShapeWriter {
  std::string& out;

  void operator()(const LineShape& line) const {
    fmt::format_to(std::back_inserter(out), R"(<line x1="{}" y1="{}" x2="{}" y2="{}"{}/>)", Px(line.from.x),
                   Px(line.from.y), Px(line.to.x), Px(line.to.y), StrokeAttributes(line.stroke));
  }
  void operator()(const PolylineShape& polyline) const {
    std::string points;
    for (const PixelPoint& p : polyline.points) fmt::format_to(std::back_inserter(points), "{},{} ", Px(p.x), Px(p.y));
    if (!points.empty()) points.pop_back();
    // The width is always written: a polyline's default of 1 would otherwise hide it among the grid lines.
    fmt::format_to(std::back_inserter(out),
                   R"(<polyline fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round" )"
                   R"(stroke-linecap="round"{} points="{}"/>)",
                   polyline.stroke.colour, Px(polyline.stroke.width),
                   polyline.stroke.dashed ? R"( stroke-dasharray="6 4")" : "", points);
  }
  void operator()(const CircleShape& circle) const {
    std::string attributes = fmt::format(R"( cx="{}" cy="{}" r="{}" fill="{}")", Px(circle.centre.x),
                                         Px(circle.centre.y), Px(circle.radius), circle.fill);
    if (!circle.ring.empty()) attributes += StrokeAttributes({.colour = circle.ring, .width = circle.ring_width});
    out += Element("circle", attributes, circle.tooltip);
  }
  void operator()(const RectShape& rect) const {
    out += Element("rect",
                   fmt::format(R"( x="{}" y="{}" width="{}" height="{}" fill="{}")", Px(rect.top_left.x),
                               Px(rect.top_left.y), Px(rect.width), Px(rect.height), rect.fill),
                   rect.tooltip);
  }
  void operator()(const TextShape& text) const {
    std::string attributes = fmt::format(R"( x="{}" y="{}" text-anchor="{}")", Px(text.baseline.x),
                                         Px(text.baseline.y), AnchorName(text.anchor));
    if (text.size != kDefaultFontSize) attributes += fmt::format(R"( font-size="{}")", text.size);
    if (text.bold) attributes += R"( font-weight="600")";
    if (text.angle != 0.0) {
      attributes += fmt::format(R"x( transform="rotate({} {} {})")x", -text.angle, Px(text.baseline.x),
                                Px(text.baseline.y));
    }
    const std::string tooltip = text.tooltip.empty() ? "" : fmt::format("<title>{}</title>", EscapeXml(text.tooltip));
    fmt::format_to(std::back_inserter(out), "<text{}>{}{}</text>", attributes, tooltip, EscapeXml(text.text));
  }
};

}  // namespace

Drawing::Drawing(int width, int height, std::string title) : width_(width), height_(height), title_(std::move(title)) {
  if (width < 1 || height < 1) throw std::invalid_argument(fmt::format("drawing size {}x{}", width, height));
}

void Drawing::Place(const Drawing& other, PixelPoint offset) {
  for (Shape shape : other.shapes_) {
    std::visit(
        [offset](auto& s) {
          using S = std::decay_t<decltype(s)>;
          if constexpr (std::is_same_v<S, LineShape>) {
            s.from = Moved(s.from, offset);
            s.to = Moved(s.to, offset);
          } else if constexpr (std::is_same_v<S, PolylineShape>) {
            for (PixelPoint& p : s.points) p = Moved(p, offset);
          } else if constexpr (std::is_same_v<S, CircleShape>) {
            s.centre = Moved(s.centre, offset);
          } else if constexpr (std::is_same_v<S, RectShape>) {
            s.top_left = Moved(s.top_left, offset);
          } else {
            s.baseline = Moved(s.baseline, offset);
          }
        },
        shape);
    shapes_.push_back(std::move(shape));
  }
}

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

std::string ToSvg(const Drawing& drawing) {
  std::string out = fmt::format(
      R"(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {0} {1}" width="{0}" height="{1}" )"
      R"(font-family="{2}" font-size="{3}" fill="{4}" role="img">)",
      drawing.width(), drawing.height(), kFont, kDefaultFontSize, kTextColour);
  if (!drawing.title().empty()) out += fmt::format("<title>{}</title>", EscapeXml(drawing.title()));
  out += fmt::format(R"(<rect width="{}" height="{}" fill="#ffffff"/>)", drawing.width(), drawing.height());
  const SvgShapeWriter writer{out};
  for (const Shape& shape : drawing.shapes()) std::visit(writer, shape);
  return out + "</svg>";
}

}  // namespace hoidslam::report
