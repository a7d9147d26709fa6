#pragma once
// A small bag-of-words vocabulary for tests and fuzz targets that need words but not good ones: k = 4, L = 2,
// trained on one thread, so the same descriptors always give the same vocabulary. Header-only: its users link
// hoidslam_bow, which the test support library does not.

#include <vector>

#include <opencv2/core.hpp>

#include "hoidslam/bow/vocabulary.h"

namespace hoidslam::testing {

// A vocabulary of k = 4, L = 2 trained on `descriptors_per_image` (CV_8U, one row of bow::kDescriptorBytes per
// descriptor).
inline bow::Vocabulary TrainSmallVocabulary(const std::vector<cv::Mat>& descriptors_per_image) {
  bow::VocabularyOptions options;
  options.branching = 4;
  options.levels = 2;
  options.threads = 1;
  return bow::Vocabulary::Train(descriptors_per_image, options);
}

}  // namespace hoidslam::testing
