#include "hoidslam/eval/person_surface.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <opencv2/core.hpp>

namespace hoidslam::eval {

namespace {

// The median of the measured depth in the middle of the box: people fill the middle of their boxes, and what is
// beside them the corners. Nullopt without measured depth there.
std::optional<float> PersonDepth(const cv::Mat& depth, double core_fraction) {
  const int w = std::max(1, static_cast<int>(std::lround(depth.cols * core_fraction)));
  const int h = std::max(1, static_cast<int>(std::lround(depth.rows * core_fraction)));
  const cv::Mat middle = depth(cv::Rect((depth.cols - w) / 2, (depth.rows - h) / 2, w, h));
  std::vector<float> measured;
  for (int y = 0; y < middle.rows; ++y) {
    for (int x = 0; x < middle.cols; ++x) {
      if (const float d = middle.at<float>(y, x); d > 0.0F) measured.push_back(d);
    }
  }
  if (measured.empty()) return std::nullopt;
  const auto mid = measured.begin() + static_cast<std::ptrdiff_t>(measured.size() / 2);
  std::nth_element(measured.begin(), mid, measured.end());
  return *mid;
}

}  // namespace

PersonSurface MeasurePersonSurface(const std::vector<Eigen::Vector3f>& vertices, double spacing,
                                   const std::vector<PersonView>& views, const core::CameraIntrinsics& camera,
                                   const PersonSurfaceOptions& options) {
  PersonSurface surface;
  for (const PersonView& view : views) {
    const std::optional<float> person_depth = PersonDepth(view.depth, options.core_fraction);
    if (!person_depth) continue;
    ++surface.boxes;
    cv::Mat person(view.depth.size(), CV_8UC1, cv::Scalar(0));
    for (int y = 0; y < person.rows; ++y) {
      for (int x = 0; x < person.cols; ++x) {
        const float d = view.depth.at<float>(y, x);
        if (d > 0.0F && std::abs(d - *person_depth) <= options.person_band) person.at<unsigned char>(y, x) = 1;
      }
    }
    cv::Mat fused(view.depth.size(), CV_8UC1, cv::Scalar(0));
    const Eigen::Isometry3f T_cw = view.T_wc.inverse().cast<float>();
    for (const Eigen::Vector3f& vertex : vertices) {
      const Eigen::Vector3f p = T_cw * vertex;
      if (p.z() <= 0.0F) continue;
      const double u = camera.fx * p.x() / p.z() + camera.cx - view.box.x;
      const double v = camera.fy * p.y() / p.z() + camera.cy - view.box.y;
      // The pixels the vertex covers: a sample stands for `spacing` of surface, fx·spacing/z pixels wide.
      const int reach = static_cast<int>(std::ceil(0.5 * camera.fx * spacing / p.z()));
      const int x0 = static_cast<int>(std::lround(u)), y0 = static_cast<int>(std::lround(v));
      if (x0 + reach < 0 || y0 + reach < 0 || x0 - reach >= fused.cols || y0 - reach >= fused.rows) continue;
      for (int y = std::max(0, y0 - reach); y <= std::min(fused.rows - 1, y0 + reach); ++y) {
        for (int x = std::max(0, x0 - reach); x <= std::min(fused.cols - 1, x0 + reach); ++x) {
          const float d = view.depth.at<float>(y, x);
          if (d > 0.0F && std::abs(d - p.z()) <= options.depth_tolerance) fused.at<unsigned char>(y, x) = 1;
        }
      }
    }
    surface.person_pixels += static_cast<std::size_t>(cv::countNonZero(person));
    surface.fused_pixels += static_cast<std::size_t>(cv::countNonZero(person & fused));
  }
  return surface;
}

nlohmann::json PersonSurfaceJson(const PersonSurface& surface, const PersonSurfaceOptions& options) {
  return {{"share", surface.Share()},
          {"boxes", surface.boxes},
          {"person_pixels", surface.person_pixels},
          {"fused_pixels", surface.fused_pixels},
          {"options",
           {{"person_band", options.person_band},
            {"core_fraction", options.core_fraction},
            {"depth_tolerance", options.depth_tolerance}}}};
}

}  // namespace hoidslam::eval
