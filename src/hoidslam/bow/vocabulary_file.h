#pragma once
// The vocabulary file (.hbow), version 1; docs/vocabulary.md describes it. All numbers are little-endian:
//
//   header     8 bytes  magic "HOIDBOW\x1a"
//              u32      format version (1)
//              u32      branching factor k, in [2, 64]
//              u32      levels L, in [1, 8]
//              u32      node count, the root included
//              u64      images the vocabulary was trained on
//              u64      descriptors it was trained on
//   nodes      44 bytes each, level by level from the root; the children of a node follow those of the nodes
//              before it, so a node's child count is all that places its children
//              32 bytes descriptor (zero for the root)
//              u32      child count, <= k; 0 for a word
//              f64      IDF weight for a word, 0 for the other nodes
//   checksum   u64      FNV-1a 64 of every byte before it
//
// The words are the nodes without children, numbered in node order.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hoidslam/bow/descriptor.h"

namespace hoidslam::bow {

inline constexpr std::uint32_t kVocabularyFormatVersion = 1;
inline constexpr int kMinBranching = 2;
inline constexpr int kMaxBranching = 64;
inline constexpr int kMinLevels = 1;
inline constexpr int kMaxLevels = 8;

struct TreeNode {
  Descriptor centre{};             // the per-bit majority of the training descriptors below it; zero for the root
  std::uint32_t child_count = 0;   // 0 for a word
  double idf = 0.0;                // a word's weight, log(training images / images with the word), so at most
                                   // log(training images); 0 for the other nodes
  bool operator==(const TreeNode&) const = default;
};

// What a vocabulary file holds.
struct VocabularyTree {
  int branching = 0;
  int levels = 0;
  std::uint64_t training_images = 0;
  std::uint64_t training_descriptors = 0;
  std::vector<TreeNode> nodes;  // in file order, the root first
  bool operator==(const VocabularyTree&) const = default;
};

// The file's bytes.
std::vector<std::uint8_t> EncodeVocabulary(const VocabularyTree& tree);

// Reads a file's bytes; `source` names it in errors. Every check runs before anything is sized from the data:
// throws core::InputError "<source>: <what is wrong>" for a file that is truncated, has trailing bytes, a wrong
// magic, an unsupported version, a checksum that does not match, or a tree that is not one (a node count that k
// and L cannot give, more than k children, a node deeper than L, a word weight outside [0, log(training images)]).
VocabularyTree DecodeVocabulary(std::span<const std::uint8_t> bytes, const std::string& source);

inline constexpr std::size_t kChecksumBytes = 8;

// FNV-1a 64 of `bytes`: the file's checksum, and as hex its identity.
std::uint64_t Fnv1a64(std::span<const std::uint8_t> bytes);

// The checksum in the last kChecksumBytes of a file's bytes (there must be that many).
std::uint64_t StoredChecksum(std::span<const std::uint8_t> file_bytes);

}  // namespace hoidslam::bow
