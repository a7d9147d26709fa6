#include "hoidslam/synth/sensor_noise.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/error.h"
#include "hoidslam/synth/option_checks.h"
#include "hoidslam/synth/random.h"

namespace hoidslam::synth {
namespace {

// Gaussian-ish samples from the bytes of one 64-bit draw (Irwin-Hall sums of uniform bytes): cheap enough for
// a million samples a frame, and exact in mean (0) and variance.
// A byte is uniform on 0..255: mean 127.5, variance (256^2 - 1) / 12.
constexpr double kByteVariance = (256.0 * 256.0 - 1.0) / 12.0;

// Sum of bytes [first, first + count) of `bits`.
int ByteSum(std::uint64_t bits, int first, int count) {
  int sum = 0;
  for (int i = first; i < first + count; ++i) sum += static_cast<int>((bits >> (8U * static_cast<unsigned>(i))) & 0xFFU);
  return sum;
}

}  // namespace

void SensorNoiseOptions::Check() const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  CheckInRange(rgb_noise_sigma, 0.0, 255.0, "noise.rgb_noise_sigma");
  CheckInRange(rgb_blur_sigma, 0.0, 10.0, "noise.rgb_blur_sigma");
  CheckInRange(depth_noise_scale, 0.0, 100.0, "noise.depth_noise_scale");
  if (!(depth_factor > 0.0 && depth_factor <= 1e6)) {
    throw core::InputError::ForParameter("noise.depth_factor", fmt::format("must be in (0, 1e6], got {}", depth_factor));
  }
  CheckInRange(disparity_step, 0.0, 1.0, "noise.disparity_step");
  CheckInRange(min_range, 0.0, kInf, "noise.min_range");
  if (!(max_range > min_range) || !std::isfinite(max_range)) {
    throw core::InputError::ForParameter("noise.max_range",
                                         fmt::format("must be finite and > min_range ({}), got {}", min_range, max_range));
  }
  if (max_range * depth_factor > 65535.0) {
    throw core::InputError::ForParameter(
        "noise.max_range", fmt::format("{} m does not fit a 16-bit depth PNG at depth_factor {}", max_range, depth_factor));
  }
  if (!(edge_jump_ratio > 0.0)) {
    throw core::InputError::ForParameter("noise.edge_jump_ratio", fmt::format("must be > 0, got {}", edge_jump_ratio));
  }
  CheckInRange(edge_erosion_probability, 0.0, 1.0, "noise.edge_erosion_probability");
  CheckInRange(dropout_probability, 0.0, 1.0, "noise.dropout_probability");
}

cv::Mat ApplyRgbNoise(const cv::Mat& bgr, const SensorNoiseOptions& options, std::uint64_t seed) {
  options.Check();
  if (bgr.type() != CV_8UC3) throw core::Error("ApplyRgbNoise: expects an 8-bit BGR image");
  cv::Mat out = bgr.clone();
  if (options.rgb_noise_sigma > 0.0) {
    // Each draw gives two samples, each the sum of four bytes (standard deviation 2 sqrt(kByteVariance)).
    const double scale = options.rgb_noise_sigma / (2.0 * std::sqrt(kByteVariance));
    Random rng(seed);
    std::uint64_t bits = 0;
    int left = 0;
    for (int y = 0; y < out.rows; ++y) {
      auto* row = out.ptr<uchar>(y);
      for (int x = 0; x < out.cols * 3; ++x) {
        if (left == 0) {
          bits = rng.Next();
          left = 2;
        }
        --left;
        const double sample = (ByteSum(bits, 4 * left, 4) - 4 * 127.5) * scale;
        row[x] = cv::saturate_cast<uchar>(row[x] + sample);
      }
    }
  }
  if (options.rgb_blur_sigma > 0.0) {
    cv::GaussianBlur(out, out, {3, 3}, options.rgb_blur_sigma, options.rgb_blur_sigma, cv::BORDER_REFLECT_101);
  }
  return out;
}

cv::Mat ApplyDepthNoise(const cv::Mat& depth, const SensorNoiseOptions& options, std::uint64_t seed) {
  options.Check();
  if (depth.type() != CV_32F) throw core::Error("ApplyDepthNoise: expects a CV_32F depth image in metres");
  // Edge holes: the 3x3 neighbourhood spans a jump larger than edge_jump_ratio x z (empty pixels count as 0).
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::Mat local_min;
  cv::Mat local_max;
  cv::erode(depth, local_min, kernel, {-1, -1}, 1, cv::BORDER_REPLICATE);
  cv::dilate(depth, local_max, kernel, {-1, -1}, 1, cv::BORDER_REPLICATE);
  cv::Mat edge(depth.size(), CV_8U);
  for (int y = 0; y < depth.rows; ++y) {
    const auto* z = depth.ptr<float>(y);
    const auto* lo = local_min.ptr<float>(y);
    const auto* hi = local_max.ptr<float>(y);
    auto* e = edge.ptr<uchar>(y);
    for (int x = 0; x < depth.cols; ++x) e[x] = (z[x] > 0.0F && hi[x] - lo[x] > options.edge_jump_ratio * z[x]) ? 255 : 0;
  }
  // Pixels beside an edge hole (4-neighbours) become holes at random: ragged edges like the real sensor's.
  cv::Mat near_edge;
  cv::dilate(edge, near_edge, cv::getStructuringElement(cv::MORPH_CROSS, {3, 3}));

  // Each draw gives one sample, the sum of eight bytes.
  const double unit = 1.0 / std::sqrt(8.0 * kByteVariance);
  const double step = 1.0 / options.depth_factor;
  Random rng(seed);
  cv::Mat out(depth.size(), CV_16U);
  for (int y = 0; y < depth.rows; ++y) {
    const auto* z = depth.ptr<float>(y);
    const auto* e = edge.ptr<uchar>(y);
    const auto* ne = near_edge.ptr<uchar>(y);
    auto* o = out.ptr<std::uint16_t>(y);
    for (int x = 0; x < depth.cols; ++x) {
      o[x] = 0;
      const std::uint64_t bits = rng.Next();
      if (z[x] <= 0.0F || e[x] != 0) continue;
      if (ne[x] != 0 && rng.Bernoulli(options.edge_erosion_probability)) continue;
      if (options.dropout_probability > 0.0 && rng.Bernoulli(options.dropout_probability)) continue;
      const double truth = z[x];
      double measured =
          truth + options.depth_noise_scale * core::KinectDepthSigma(truth) * (ByteSum(bits, 0, 8) - 8 * 127.5) * unit;
      if (options.disparity_step > 0.0 && measured > 0.0) {
        const double disparity = std::round(1.0 / measured / options.disparity_step) * options.disparity_step;
        measured = disparity > 0.0 ? 1.0 / disparity : 0.0;
      }
      if (measured < options.min_range || measured > options.max_range) continue;
      o[x] = cv::saturate_cast<std::uint16_t>(std::round(measured / step));
    }
  }
  return out;
}

}  // namespace hoidslam::synth
