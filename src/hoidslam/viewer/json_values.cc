#include "hoidslam/viewer/json_values.h"

namespace hoidslam::viewer {

nlohmann::json PoseJson(const core::Pose& pose) {
  nlohmann::json values = nlohmann::json::array();
  const Eigen::Matrix4d m = pose.matrix();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) values.push_back(Rounded(m(r, c), c == 3 ? 1e4 : 1e6));
  }
  return values;
}

}  // namespace hoidslam::viewer
