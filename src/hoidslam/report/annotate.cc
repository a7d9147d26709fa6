#include "hoidslam/report/annotate.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace hoidslam::report {
namespace {

const cv::Scalar kDynamicColour(40, 40, 230);  // BGR red
const cv::Scalar kStaticColour(60, 200, 60);   // BGR green

void DrawOne(cv::Mat& image, const BoxAnnotation& annotation) {
  const cv::Scalar colour = annotation.dynamic ? kDynamicColour : kStaticColour;
  const cv::Rect box = cv::Rect(annotation.box) & cv::Rect(0, 0, image.cols, image.rows);
  cv::rectangle(image, box, colour, 2);
  if (annotation.caption.empty()) return;
  constexpr double kScale = 0.45;
  int baseline = 0;
  const cv::Size text = cv::getTextSize(annotation.caption, cv::FONT_HERSHEY_SIMPLEX, kScale, 1, &baseline);
  // Above the box when there is room, else just inside its top edge; never past the right border.
  const int x = std::clamp(box.x, 0, std::max(0, image.cols - text.width - 4));
  const int y = box.y - text.height - 6 >= 0 ? box.y - text.height - 6 : box.y + 1;
  cv::rectangle(image, cv::Rect(x, y, text.width + 4, text.height + 6), colour, cv::FILLED);
  cv::putText(image, annotation.caption, {x + 2, y + text.height + 2}, cv::FONT_HERSHEY_SIMPLEX, kScale,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace

cv::Mat DrawBoxAnnotations(const cv::Mat& bgr, std::span<const BoxAnnotation> annotations) {
  cv::Mat image = bgr.clone();
  for (const bool dynamic_pass : {false, true}) {
    for (const BoxAnnotation& annotation : annotations) {
      if (annotation.dynamic == dynamic_pass) DrawOne(image, annotation);
    }
  }
  return image;
}

void DrawKeptAndDropped(cv::Mat& image, std::span<const cv::KeyPoint> keypoints, std::span<const std::uint8_t> keep) {
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    cv::circle(image, keypoints[i].pt, 3, keep[i] != 0 ? kStaticColour : kDynamicColour, 1, cv::LINE_AA);
  }
}

}  // namespace hoidslam::report
