#pragma once
// A Kinect-like sensor model applied to clean renderer output: colour noise and blur, and depth noise,
// quantisation, range limits and holes. Pure functions; each call is seeded by the caller (use
// FrameSeed(scenario seed, frame index, purpose) from random.h) so frames are independent and reproducible.
// Both apply options.Check() first.

#include <cstdint>

#include <opencv2/core/mat.hpp>

namespace hoidslam::synth {

struct SensorNoiseOptions {
  // Colour. Noise first, then blur (like demosaicing, the blur makes the noise spatially correlated); after
  // the blur the per-pixel noise std is about 0.45 x rgb_noise_sigma.
  double rgb_noise_sigma = 2.5;  // grey levels, >= 0: std of the per-pixel, per-channel noise before the blur
  double rgb_blur_sigma = 0.8;   // pixels, >= 0: sigma of the 3x3 Gaussian blur; 0 = no blur

  // Depth, after Nguyen, Izadi & Lovell (2012): sigma_z(z) = depth_noise_scale * core::KinectDepthSigma(z).
  double depth_noise_scale = 1.0;     // >= 0: 0 = no depth noise, 1 = the published model
  double depth_factor = 5000.0;       // PNG units per metre, > 0 (TUM: 5000); also the quantisation step
  double disparity_step = 0.0;        // 1/m, >= 0: quantise 1/z in steps of this size (Kinect-like: 2.85e-3);
                                      // 0 = off
  double min_range = 0.4;             // metres, >= 0: nearer measurements give no depth
  double max_range = 4.5;             // metres, > min_range: farther measurements give no depth
  double edge_jump_ratio = 0.1;       // > 0: a pixel whose 3x3 neighbourhood spans more than this x z is a hole
  double edge_erosion_probability = 0.3;  // [0, 1]: chance that a pixel beside an edge hole is a hole too
  double dropout_probability = 0.002;     // [0, 1]: chance that any pixel gives no depth

  // Throws InputError naming the parameter ("noise.rgb_noise_sigma", ...).
  void Check() const;
};

// Colour as the sensor delivers it: `bgr` (CV_8UC3) plus noise, then blurred. Returns a new image.
cv::Mat ApplyRgbNoise(const cv::Mat& bgr, const SensorNoiseOptions& options, std::uint64_t seed);

// Depth as the sensor delivers it, as a 16-bit PNG-ready image (CV_16U, depth_factor units per metre,
// 0 = no depth), from clean depth `depth` (CV_32F metres, 0 = nothing). In order: edge holes (from the clean
// depth, eroded at random), random dropout, noise, disparity quantisation, range limits on the noisy value,
// rounding to the depth_factor step.
cv::Mat ApplyDepthNoise(const cv::Mat& depth, const SensorNoiseOptions& options, std::uint64_t seed);

}  // namespace hoidslam::synth
