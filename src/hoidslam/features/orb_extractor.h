#pragma once
// ORB features as ORB-SLAM extracts them: a scale pyramid, FAST corners found per grid cell with a high and,
// where a cell has none, a low threshold, the requested number spread evenly over each level with a quadtree,
// orientation by intensity centroid and rotated BRIEF descriptors (256 bits).

#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/options.h"
#include "hoidslam/features/quadtree.h"

namespace hoidslam::features {

// Per-level factors of a scale pyramid: level l is the image scaled by 1 / scale[l], scale[l] = factor^l.
// sigma2[l] = scale[l]^2 is the variance (pixels² at level 0) of a keypoint position found at level l.
struct ScalePyramid {
  std::vector<float> scale;
  std::vector<float> inv_scale;
  std::vector<float> sigma2;
  std::vector<float> inv_sigma2;

  static ScalePyramid Make(int levels, double factor);
  int levels() const { return static_cast<int>(scale.size()); }
};

// One extractor per thread: it reuses its buffers from call to call.
class OrbExtractor {
 public:
  // Throws core::InputError when options.Check() fails.
  explicit OrbExtractor(const core::OrbOptions& options);

  // Extracts up to options.n_features keypoints from `gray` (CV_8UC1) and their descriptors (one CV_8UC1 row of
  // 32 bytes each). Keypoints are in pixels of `gray` (level 0); `octave` is the pyramid level, `angle` the
  // orientation in degrees [0, 360), `size` the patch diameter at level 0 and `response` the FAST score.
  // Deterministic: the same image gives the same keypoints in the same order, level by level. `descriptors`
  // always gets a new buffer, so descriptors kept from an earlier call are never overwritten.
  // The levels are spread over OpenCV's threads (cv::setNumThreads; 1 runs them in turn), with the same result.
  // Throws std::invalid_argument when `gray` is empty or not CV_8UC1.
  void Extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  const ScalePyramid& pyramid() const { return pyramid_; }
  const core::OrbOptions& options() const { return options_; }
  // How many keypoints each level may give (ORB-SLAM's split of n_features over the levels).
  const std::vector<int>& features_per_level() const { return features_per_level_; }

 private:
  // One pyramid level: its image and the buffers its work reuses from frame to frame.
  struct Level {
    cv::Mat image;                          // level 0 is the input itself
    cv::Mat blurred;                        // smoothed image inside a reflected border, for the descriptors
    std::vector<cv::KeyPoint> fast;         // cv::FAST's output
    std::vector<Corner> corners;            // the FAST corners kept after the per-cell thresholds
    std::vector<std::uint8_t> cell_strong;  // whether each cell has a corner at iniThFAST
    std::vector<int> selected;              // indices into corners the quadtree keeps
    QuadtreeDistributor distributor;
    std::vector<cv::KeyPoint> keypoints;  // the level's result, in level pixels
    cv::Mat descriptors;
  };

  core::OrbOptions options_;
  ScalePyramid pyramid_;
  std::vector<int> features_per_level_;
  std::vector<Level> levels_;

  void BuildPyramid(const cv::Mat& gray);
  // Finds, orients and describes the keypoints of one level; levels share nothing, so they run in parallel.
  void ProcessLevel(int level);
  // Fills level.corners with the level's FAST corners as the per-cell thresholds choose them.
  void DetectCorners(Level& level) const;
};

// Hamming distance between two 32-byte ORB descriptors.
int DescriptorDistance(const std::uint8_t* a, const std::uint8_t* b);
inline int DescriptorDistance(const cv::Mat& a, const cv::Mat& b) { return DescriptorDistance(a.ptr(), b.ptr()); }

}  // namespace hoidslam::features
