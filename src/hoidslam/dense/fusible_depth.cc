#include "hoidslam/dense/fusible_depth.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace hoidslam::dense {

cv::Mat FusibleDepth(const cv::Mat& depth, const cv::Mat& dropped, const DenseOptions& options) {
  if (depth.type() != CV_32FC1) throw std::invalid_argument("FusibleDepth: depth must be CV_32FC1");
  if (!dropped.empty() && (dropped.type() != CV_8UC1 || dropped.size() != depth.size())) {
    throw std::invalid_argument("FusibleDepth: the dropped mask must be CV_8UC1 of the depth's size");
  }
  cv::Mat fused;
  depth.copyTo(fused);
  cv::patchNaNs(fused, 0.0);
  // Beyond max_depth the depth stays: too noisy for a surface, it still says the space before max_depth is free.
  cv::Mat out_of_range = fused < options.min_depth;
  // A neighbourhood with a missing depth counts as an edge too: holes border on what the sensor could not resolve.
  cv::Mat nearest, farthest;
  cv::Mat missing_as_far;
  fused.copyTo(missing_as_far);
  missing_as_far.setTo(1e6, fused <= 0.0F);
  cv::erode(missing_as_far, nearest, cv::Mat());
  cv::dilate(missing_as_far, farthest, cv::Mat());
  cv::Mat edge = (farthest - nearest) > (fused * options.depth_edge);
  cv::Mat left_out = out_of_range | edge;
  if (!dropped.empty()) {
    cv::Mat grown;
    if (options.mask_margin > 0) {
      const int size = 2 * options.mask_margin + 1;
      cv::dilate(dropped, grown, cv::getStructuringElement(cv::MORPH_RECT, {size, size}));
    } else {
      grown = dropped;
    }
    left_out |= grown != 0;
  }
  fused.setTo(0.0F, left_out);
  return fused;
}

}  // namespace hoidslam::dense
