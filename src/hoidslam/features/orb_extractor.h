#pragma once
// ORB features as ORB-SLAM extracts them: a scale pyramid, FAST corners found per grid cell with a high and,
// where a cell has none, a low threshold, the requested number spread evenly over each level with a quadtree,
// orientation by intensity centroid and rotated BRIEF descriptors (256 bits).
//
// A second call, ExtractOutside, spends the same budget again on the part of the image a mask leaves: once the
// exclusion filter knows which regions it drops (people, the things they carry), the frame's keypoints go to the
// static world instead of being dropped with the people. It reuses the pyramid and the FAST corners of the first
// call, and the orientation and descriptor of every corner the first call kept too, so it costs the selection and
// the descriptors of the new corners only.

#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "hoidslam/core/descriptor_distance.h"
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
  // A dim `gray` is brightened first (core::OrbOptions::dim_mean, max_gain).
  // The extractor holds on to `gray` (not a copy) until the next call, for ExtractOutside.
  // Throws std::invalid_argument when `gray` is empty or not CV_8UC1.
  void Extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  // Extracts again from the image of the last Extract call (which must not have changed since), with no keypoint
  // on the pixels `excluded` marks (CV_8UC1 of the image's size, non-zero = excluded; a keypoint is excluded when
  // the pixel its level-0 position rounds to is), nor within 8 pixels of them: a corner by a person's outline moves
  // with the person. The budget is spread over what is left as Extract spreads it over
  // the image: per level by the quadtree, each cell's FAST threshold chosen among its corners outside the mask (so
  // a cell whose strong corners all lie on a person is searched again at minThFAST), and a level whose part
  // outside the mask has fewer corners than its share hands what it cannot use on to the levels that have more
  // (finest first), so that a frame full of people gets about the whole budget on what remains. Unlike Extract,
  // which keeps ORB-SLAM's fixed shares. (Lowering the threshold over all of a level short of strong corners was
  // tried: the weak corners it adds on smooth walls made walking_xyz drift, 3.1 → 15 mm.) Same order and fields as
  // Extract. Throws std::logic_error before any Extract, std::invalid_argument for a mask of the wrong size or type.
  void ExtractOutside(const cv::Mat& excluded, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors);

  const ScalePyramid& pyramid() const { return pyramid_; }
  const core::OrbOptions& options() const { return options_; }
  // How many keypoints each level may give (ORB-SLAM's split of n_features over the levels).
  const std::vector<int>& features_per_level() const { return features_per_level_; }

 private:
  // The keypoints one call keeps on a level, in level pixels, and their descriptors.
  struct Described {
    std::vector<cv::KeyPoint> keypoints;
    cv::Mat descriptors;
  };

  // One pyramid level: its image and the buffers its work reuses from frame to frame.
  struct Level {
    cv::Mat image;                          // level 0 is the input itself, or brightened_ when it was dim
    cv::Mat blurred;                        // smoothed image inside a reflected border, for the descriptors
    bool blurred_ready = false;             // blurred holds this frame's image
    cv::Mat excluded;                       // ExtractOutside's mask, grown by the margin, at this level's size
    std::vector<cv::KeyPoint> fast;         // cv::FAST's output
    std::vector<Corner> strong;             // the FAST corners scoring >= iniThFAST in the band, kept for ExtractOutside
    std::vector<Corner> corners;            // the FAST corners kept after the per-cell thresholds
    std::vector<std::uint8_t> cell_strong;  // whether each cell has a corner at iniThFAST
    std::vector<int> selected;              // indices into corners the quadtree keeps
    std::vector<int> reused;                // per selected corner, its index in `extracted`, or -1
    QuadtreeDistributor distributor;
    Described extracted;                    // Extract's result
    Described outside;                      // ExtractOutside's result
    std::vector<std::pair<int, int>> extracted_at;  // (y * cols + x, index into extracted), sorted: ExtractOutside's
  };

  core::OrbOptions options_;
  ScalePyramid pyramid_;
  std::vector<int> features_per_level_;
  std::vector<Level> levels_;
  cv::Mat brightened_;  // a dim input scaled up (options_.dim_mean)

  // `gray`, or when its mean grey is below options_.dim_mean, a copy scaled towards it (in brightened_).
  const cv::Mat& Brightened(const cv::Mat& gray);
  void BuildPyramid(const cv::Mat& gray);
  // Runs `work(level index)` for every level, spread over OpenCV's threads: levels share nothing.
  template <typename Work>
  void ForEachLevel(const Work& work);
  // Fills level.corners with the level's FAST corners as the per-cell thresholds choose them; with `excluded`
  // (level 0's mask), among the corners outside it only, and no cell lying wholly inside it is searched.
  void DetectCorners(int index, const cv::Mat& excluded);
  // Spreads `budget` keypoints over the level's corners into `out`, orients and describes them. Into `outside`,
  // a corner Extract kept too takes its orientation and descriptor from there (the same pixels give the same).
  void SelectAndDescribe(int index, int budget, Described Level::*out);
  // The keypoints of all levels' `result`, level by level, in level-0 pixels.
  void Collect(Described Level::*result, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const;
};

// Hamming distance between two 32-byte ORB descriptors (core/descriptor_distance.h).
using core::DescriptorDistance;

}  // namespace hoidslam::features
