#pragma once
// A bag-of-words vocabulary for ORB descriptors, as DBoW2 builds them for ORB-SLAM: a tree of k branches and L
// levels trained by hierarchical k-majority clustering, whose leaves are the words. An image's descriptors become
// a TF-IDF weighted bag of words (to find places seen before) and a direct index (to match only keypoints under
// the same node). The vocabulary is data with a file format of its own (vocabulary_file.h, docs/vocabulary.md).

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "hoidslam/bow/bow_vector.h"
#include "hoidslam/bow/vocabulary_file.h"

namespace hoidslam::bow {

struct VocabularyOptions {
  int branching = 10;       // --branching, k in [2, 64]: children of a node
  int levels = 5;           // --levels, L in [1, 8]: depth of the tree, so at most k^L words
  int max_iterations = 10;  // --iterations, >= 1: k-majority rounds at a node, fewer when no assignment changes
  std::uint64_t seed = 1;   // --seed: of the k-means++ seeding (each node draws from its own std::mt19937)
  int threads = 0;          // --threads, >= 0: nodes clustered at once, 0 for one per core; the vocabulary is the
                            // same for every count

  // Throws core::InputError naming the parameter.
  void Check() const;
};

class Vocabulary {
 public:
  // Clusters the descriptors of a set of training images (each a CV_8U matrix of 32-byte rows, possibly empty);
  // the IDF weight of a word is log(images / images with a descriptor that Transform puts on the word).
  // Deterministic: the same descriptors and options give the same bytes whatever the thread count. Throws
  // core::InputError when options.Check() fails or there is no descriptor at all, std::invalid_argument for a
  // matrix that is not CV_8U with 32 columns.
  static Vocabulary Train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyOptions& options);

  // Reads a vocabulary file. Throws core::InputError naming the file and what is wrong with it (see
  // DecodeVocabulary): missing, unreadable, truncated, corrupt, of another format or version, or not a tree.
  static Vocabulary Load(const std::filesystem::path& path);
  // The same from the file's bytes; `source` names them in errors.
  static Vocabulary Load(std::span<const std::uint8_t> bytes, const std::string& source);

  // Writes the file atomically (a temporary name, then a rename); throws core::InputError when it cannot.
  void Save(const std::filesystem::path& path) const;
  // The file's bytes.
  std::vector<std::uint8_t> Serialize() const { return EncodeVocabulary(tree_); }

  // The bag of words of one image's descriptors (CV_8U, 32-byte rows; empty gives an empty result) and its direct
  // index: every keypoint (descriptor row) under its ancestor on level L - `direct_index_levels_up` (the root from
  // L up; the word itself for 0, or when the word is on that level or above it). Each descriptor descends the tree
  // to the nearest child by Hamming distance, the first of equals. Throws std::invalid_argument for a matrix of
  // another type or width, or a negative `direct_index_levels_up`.
  ImageWords Transform(const cv::Mat& descriptors, int direct_index_levels_up = 4) const;

  // Identifies the vocabulary (its file's checksum as 16 hex digits), so a saved map can say which one it used.
  const std::string& identity() const { return identity_; }

  int branching() const { return tree_.branching; }
  int levels() const { return tree_.levels; }
  std::size_t node_count() const { return tree_.nodes.size(); }
  std::size_t word_count() const { return word_nodes_.size(); }
  std::uint64_t training_images() const { return tree_.training_images; }
  std::uint64_t training_descriptors() const { return tree_.training_descriptors; }
  const VocabularyTree& tree() const { return tree_; }
  double idf(WordId word) const { return tree_.nodes[word_nodes_[word]].idf; }
  // The level of a node: 0 for the root, up to L.
  int Level(NodeId node) const { return node_levels_[node]; }

 private:
  // `checksum`: that of the tree's file.
  Vocabulary(VocabularyTree tree, std::uint64_t checksum);
  // A vocabulary of the tree, its checksum from its encoding.
  static Vocabulary FromTree(VocabularyTree tree);

  // The word a descriptor descends to, and its ancestor at `index_level` (or the word when it is not deeper).
  struct Descent {
    WordId word = 0;
    NodeId index_node = 0;
  };
  Descent Descend(const Descriptor& descriptor, int index_level) const;

  VocabularyTree tree_;
  std::vector<std::uint32_t> first_child_;  // per node: the id of its first child, placed by the child counts
  std::vector<std::uint8_t> node_levels_;   // per node
  std::vector<std::int32_t> node_words_;    // per node: its word, -1 for the other nodes
  std::vector<NodeId> word_nodes_;          // per word: its node
  std::string identity_;
};

}  // namespace hoidslam::bow
