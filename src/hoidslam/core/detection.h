#pragma once
// One object found by a detector in one image.

#include <string>

#include <opencv2/core/types.hpp>

namespace hoidslam::core {

struct Detection {
  int class_id = -1;       // index in the detector's class list (COCO-80 order for the bundled backends), -1 if unknown
  std::string label;       // class name, e.g. "person", "cup", "tv"; the HOID filter matches classes by this name
  float score = 0.0F;      // confidence in [0, 1]
  cv::Rect2f box;          // pixels, top-left corner plus width and height, in the image the detector saw
};

}  // namespace hoidslam::core
