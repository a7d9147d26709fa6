#pragma once
// What a vocabulary makes of one image's descriptors: its bag of words, to compare images by, and its direct
// index, which groups the keypoints by a node of the tree so that matching compares only keypoints under the same
// node (ORB-SLAM's guided matching for relocalisation and loop closing).

#include <cstdint>
#include <vector>

namespace hoidslam::bow {

using WordId = std::uint32_t;  // 0 .. word_count() - 1
using NodeId = std::uint32_t;  // 0 is the root; nodes are numbered level by level

struct WordWeight {
  WordId word = 0;
  double weight = 0.0;
  bool operator==(const WordWeight&) const = default;
};

// TF-IDF weights of the image's words, sorted by word, each word once, every weight > 0; the weights sum to 1
// (an empty vector when no descriptor reached a word of weight > 0).
using BowVector = std::vector<WordWeight>;

struct NodeKeypoints {
  NodeId node = 0;
  std::vector<int> keypoints;  // rows of the descriptor matrix, ascending
  bool operator==(const NodeKeypoints&) const = default;
};

// Every keypoint under exactly one node, sorted by node.
using FeatureVector = std::vector<NodeKeypoints>;

struct ImageWords {
  BowVector bow;
  FeatureVector features;
  bool operator==(const ImageWords&) const = default;
};

// DBoW2's L1 score of two L1-normalised bag-of-words vectors, 1 - |a - b|_1 / 2, computed as the sum over the
// shared words of the smaller weight: in [0, 1]; 1 for equal vectors, 0 when no word is shared.
double Score(const BowVector& a, const BowVector& b);

}  // namespace hoidslam::bow
