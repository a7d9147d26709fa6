#include "hoidslam/pipeline/depth_units.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace hoidslam::pipeline {
namespace {

// A room: half its valid depth between 0.3 and 12 m, and a tenth of it beyond a metre.
constexpr double kMinMedianM = 0.3;
constexpr double kMaxMedianM = 12.0;
constexpr double kMinP90M = 1.0;
constexpr double kMinValidShare = 0.2;
// The units a metre of the cameras users have: millimetres, TUM's and Bonn's fifths of one, tenths of one.
constexpr std::array kUsualFactors = {1000.0, 5000.0, 10000.0};

}  // namespace

std::optional<DepthSpread> MeasureDepth(const cv::Mat& depth_m) {
  if (depth_m.empty()) return std::nullopt;
  CV_Assert(depth_m.type() == CV_32FC1);
  std::vector<float> valid;
  valid.reserve(depth_m.total());
  for (int r = 0; r < depth_m.rows; ++r) {
    const float* row = depth_m.ptr<float>(r);
    for (int c = 0; c < depth_m.cols; ++c) {
      if (row[c] > 0.0F && std::isfinite(row[c])) valid.push_back(row[c]);
    }
  }
  const double share = depth_m.total() == 0 ? 0.0 : static_cast<double>(valid.size()) / depth_m.total();
  if (share < kMinValidShare) return std::nullopt;
  const auto quantile = [&valid](double q) {
    const auto k = valid.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(valid.size() - 1));
    std::nth_element(valid.begin(), k, valid.end());
    return static_cast<double>(*k);
  };
  return DepthSpread{share, quantile(0.5), quantile(0.9)};
}

std::string DepthUnitsProblem(const DepthSpread& spread, double depth_factor) {
  const bool too_near = spread.median_m < kMinMedianM || spread.p90_m < kMinP90M;
  if (!too_near && spread.median_m <= kMaxMedianM) return {};
  // The factor that would put the median at a room's 2.5 m, rounded to the units cameras use.
  const double suggested = depth_factor * spread.median_m / 2.5;
  const double nearest = *std::min_element(kUsualFactors.begin(), kUsualFactors.end(), [&](double a, double b) {
    return std::abs(std::log(a / suggested)) < std::abs(std::log(b / suggested));
  });
  return fmt::format(
      "the depth looks {} for a room: read with {:g} units a metre (DepthMapFactor), the first frame's median depth "
      "is {:.2f} m and 90 % of it is nearer than {:.2f} m. Is the depth in another unit? {} units a metre would put "
      "it where a room is (1000 for millimetres: RealSense, Azure Kinect, Orbbec, OpenNI; 5000 for TUM and Bonn): "
      "give it with --depth-factor, DepthMapFactor in the settings, or the API camera's depth_scale. If the scene "
      "really is that {}, set Depth.checkUnits: 0 in the settings",
      too_near ? "too near" : "too far", depth_factor, spread.median_m, spread.p90_m, nearest,
      too_near ? "near" : "far");
}

}  // namespace hoidslam::pipeline
