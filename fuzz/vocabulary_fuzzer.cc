// Vocabulary files: the bytes are a vocabulary file (.hbow, docs/vocabulary.md), read as bow::Vocabulary::Load
// reads a file's bytes. Each input is read twice: as it is, and with its last eight bytes made the checksum of the
// others, so that mutations reach the checks of the header and the tree behind the checksum.

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "fuzz/targets.h"
#include "hoidslam/bow/vocabulary.h"

namespace hoidslam::fuzz {
namespace {

// Descriptors for Transform to descend with: rows of repeated bytes, from all zeros to all ones.
cv::Mat ProbeDescriptors() {
  cv::Mat descriptors(9, bow::kDescriptorBytes, CV_8U);
  for (int row = 0; row < descriptors.rows; ++row) descriptors.row(row).setTo(cv::Scalar(row * 255 / 8));
  return descriptors;
}

void CheckVocabulary(Bytes bytes) {
  const std::string source = "vocabulary.hbow";
  const auto vocabulary = ParseOrReject([&] { return bow::Vocabulary::Load(bytes, source); }, source);
  if (!vocabulary) return;
  // Every byte of an accepted file is a field that is read, so writing it again gives the same bytes.
  const std::vector<std::uint8_t> written = vocabulary->Serialize();
  Require(std::equal(written.begin(), written.end(), bytes.begin(), bytes.end()), "saving does not give the file");
  Require(vocabulary->word_count() >= 1, "a vocabulary without words");

  const cv::Mat probes = ProbeDescriptors();
  const bow::ImageWords words = vocabulary->Transform(probes);
  double sum = 0.0;
  for (std::size_t i = 0; i < words.bow.size(); ++i) {
    Require(words.bow[i].word < vocabulary->word_count(), "a word beyond the vocabulary");
    Require(i == 0 || words.bow[i - 1].word < words.bow[i].word, "the bag of words is not sorted");
    Require(std::isfinite(words.bow[i].weight) && words.bow[i].weight > 0.0, "a word weight not finite and > 0");
    sum += words.bow[i].weight;
  }
  Require(words.bow.empty() || std::abs(sum - 1.0) < 1e-9, "the word weights do not sum to 1");
  std::vector<int> keypoints;
  for (const bow::NodeKeypoints& node : words.features) {
    Require(node.node < vocabulary->node_count(), "a direct index node beyond the tree");
    keypoints.insert(keypoints.end(), node.keypoints.begin(), node.keypoints.end());
  }
  std::sort(keypoints.begin(), keypoints.end());
  std::vector<int> every(static_cast<std::size_t>(probes.rows));
  std::iota(every.begin(), every.end(), 0);
  Require(keypoints == every, "the direct index does not hold every keypoint once");
}

}  // namespace

void FuzzVocabulary(Bytes input) {
  CheckVocabulary(input);
  if (const auto checksummed = WithChecksum(input)) CheckVocabulary(*checksummed);
}

}  // namespace hoidslam::fuzz
