#include "hoidslam/bow/vocabulary_file.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/bow/vocabulary.h"
#include "hoidslam/core/error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::bow {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// k = 2, L = 2: the root, two children, and below the first of them two words.
VocabularyTree SmallTree() {
  VocabularyTree tree;
  tree.branching = 2;
  tree.levels = 2;
  tree.training_images = 3;
  tree.training_descriptors = 40;
  tree.nodes = {{{}, 2, 0.0}, {{1, 2, 3, 4}, 2, 0.0}, {{~0ULL, 0, 0, 5}, 0, 0.4}, {{1, 2, 3, 0}, 0, 1.0},
                {{1, 2, 3, 8}, 0, 0.0}};
  return tree;
}

// The message DecodeVocabulary gives for `bytes`, or "accepted".
std::string Rejection(const std::vector<std::uint8_t>& bytes) {
  try {
    DecodeVocabulary(bytes, "tree.hbow");
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Rewrites the u32 at `offset` and the checksum after it, as a program that writes bad trees would.
std::vector<std::uint8_t> WithU32(std::vector<std::uint8_t> bytes, std::size_t offset, std::uint32_t value) {
  for (std::size_t i = 0; i < 4; ++i) bytes[offset + i] = static_cast<std::uint8_t>(value >> (8 * i));
  const std::uint64_t checksum = Fnv1a64(std::span(bytes).first(bytes.size() - kChecksumBytes));
  for (std::size_t i = 0; i < kChecksumBytes; ++i) {
    bytes[bytes.size() - kChecksumBytes + i] = static_cast<std::uint8_t>(checksum >> (8 * i));
  }
  return bytes;
}

constexpr std::size_t kVersionOffset = 8;
constexpr std::size_t kNodeCountOffset = 20;
constexpr std::size_t kFirstNodeOffset = 40;
constexpr std::size_t kNodeBytes = 44;

TEST(VocabularyFile, RoundTripsATreeExactly) {
  const std::vector<std::uint8_t> bytes = EncodeVocabulary(SmallTree());
  EXPECT_EQ(bytes.size(), kFirstNodeOffset + 5 * kNodeBytes + kChecksumBytes);
  EXPECT_EQ(DecodeVocabulary(bytes, "tree.hbow"), SmallTree());
  const Vocabulary vocabulary = Vocabulary::Load(bytes, "tree.hbow");
  EXPECT_EQ(vocabulary.word_count(), 3U);
  EXPECT_EQ(vocabulary.identity(), fmt::format("{:016x}", StoredChecksum(bytes)));
}

TEST(VocabularyFile, TruncatedAnywhereSaysSo) {
  const std::vector<std::uint8_t> bytes = EncodeVocabulary(SmallTree());
  for (const std::size_t length : {std::size_t{0}, std::size_t{5}, std::size_t{8}, std::size_t{30},
                                   kFirstNodeOffset + kChecksumBytes - 1, kFirstNodeOffset + kChecksumBytes,
                                   kFirstNodeOffset + kNodeBytes + 3, bytes.size() - 1}) {
    const std::string error = Rejection(std::vector(bytes.begin(), bytes.begin() + static_cast<long>(length)));
    EXPECT_THAT(error, StartsWith("tree.hbow: truncated")) << length << " bytes";
  }
}

TEST(VocabularyFile, TrailingBytesAreRejected) {
  std::vector<std::uint8_t> bytes = EncodeVocabulary(SmallTree());
  bytes.push_back(0);
  EXPECT_EQ(Rejection(bytes), "tree.hbow: 1 bytes past the end of the vocabulary's 268");
}

TEST(VocabularyFile, AFlippedByteAnywhereAfterTheHeaderFailsTheChecksum) {
  const std::vector<std::uint8_t> bytes = EncodeVocabulary(SmallTree());
  for (std::size_t at = kFirstNodeOffset; at < bytes.size(); at += 7) {
    std::vector<std::uint8_t> flipped = bytes;
    flipped[at] ^= 0x10;
    EXPECT_THAT(Rejection(flipped), StartsWith("tree.hbow: corrupt: the checksum")) << "byte " << at;
  }
}

TEST(VocabularyFile, WrongMagicAndVersionAreNamed) {
  std::vector<std::uint8_t> bytes = EncodeVocabulary(SmallTree());
  std::vector<std::uint8_t> wrong_magic = bytes;
  wrong_magic[3] = 'X';
  EXPECT_THAT(Rejection(wrong_magic), StartsWith("tree.hbow: not a hoidslam vocabulary file"));
  EXPECT_THAT(Rejection({'%', 'Y', 'A', 'M', 'L'}), StartsWith("tree.hbow: not a hoidslam vocabulary file"));
  EXPECT_EQ(Rejection(WithU32(bytes, kVersionOffset, 2)),
            "tree.hbow: unsupported format version 2 (this hoidslam reads version 1)");
}

TEST(VocabularyFile, AHugeNodeCountIsRejectedWithoutAllocatingIt) {
  const std::vector<std::uint8_t> bytes = EncodeVocabulary(SmallTree());
  EXPECT_THAT(Rejection(WithU32(bytes, kNodeCountOffset, 8)), HasSubstr("8 nodes cannot make a tree"));
  EXPECT_THAT(Rejection(WithU32(bytes, kNodeCountOffset, 1)), HasSubstr("1 nodes cannot make a tree"));
  VocabularyTree wide = SmallTree();
  wide.branching = 64;
  wide.levels = 8;
  EXPECT_THAT(Rejection(WithU32(EncodeVocabulary(wide), kNodeCountOffset, std::numeric_limits<std::uint32_t>::max())),
              HasSubstr("truncated: 268 bytes where the header's 4294967295 nodes take"));
}

TEST(VocabularyFile, TreesThatAreNotTreesAreRejectedNamingTheNode) {
  const auto rejection_of = [](const auto& edit) {
    VocabularyTree tree = SmallTree();
    edit(tree);
    return Rejection(EncodeVocabulary(tree));
  };
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.branching = 1; }),
            "tree.hbow: branching factor 1 is outside [2, 64]");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.levels = 9; }), "tree.hbow: 9 levels is outside [1, 8]");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[1].child_count = 3; }),
            "tree.hbow: node 1: 3 children, more than the branching factor 2");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[0].child_count = 1; }),
            "tree.hbow: the child counts place 4 nodes, the header says 5");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) {
              t.levels = 3;
              t.nodes[4].child_count = 1;
            }),
            "tree.hbow: node 4: its children would run past the 5 nodes");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) {
              t.nodes[0].child_count = 1;  // node 2 has no parent, and its child would be node 2 itself
              t.nodes[1].child_count = 0;
              t.nodes[2].child_count = 1;
              t.nodes[2].idf = 0.0;
            }),
            "tree.hbow: node 2: its children come before it");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.levels = 1; }),
            "tree.hbow: 5 nodes cannot make a tree of branching factor 2 and 1 levels (2 to 3 nodes)");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) {
              t.nodes[3].child_count = 1;  // node 3 is on the last of the 2 levels
              t.nodes[3].idf = 0.0;
              t.nodes.push_back({{9, 9, 9, 9}, 0, 0.5});
            }),
            "tree.hbow: node 3: has children below the last of the 2 levels");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[3].idf = std::nan(""); }),
            "tree.hbow: node 3: word weight nan is outside [0, log(3 training images)]");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[3].idf = -1.0; }),
            "tree.hbow: node 3: word weight -1 is outside [0, log(3 training images)]");
  // So large that a bag of words would sum its weights to infinity (found by the fuzzer).
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[3].idf = 1e300; }),
            "tree.hbow: node 3: word weight 1e+300 is outside [0, log(3 training images)]");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[3].idf = std::log(3.0); }), "accepted");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[1].idf = 2.0; }),
            "tree.hbow: node 1: a weight 2 on a node that is not a word");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.nodes[0].centre[2] = 1; }),
            "tree.hbow: node 0: the root has a descriptor or a weight");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.training_images = 0; }), "tree.hbow: trained on 0 images");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.training_descriptors = 2; }),
            "tree.hbow: 3 words cannot come from training on 2 descriptors of 3 images");
  // One image, one descriptor: said in the singular.
  EXPECT_EQ(rejection_of([](VocabularyTree& t) { t.training_images = 1; }),
            "tree.hbow: node 2: word weight 0.4 is outside [0, log(1 training image)]");
  EXPECT_EQ(rejection_of([](VocabularyTree& t) {
              t.training_images = 1;
              t.training_descriptors = 1;
              t.nodes[2].idf = t.nodes[3].idf = 0.0;
            }),
            "tree.hbow: 3 words cannot come from training on 1 descriptor of 1 image");
}

TEST(VocabularyFile, LoadNamesAMissingFileAndTheFileItRejects) {
  const testing::TempDir scratch;
  try {
    Vocabulary::Load(scratch / "absent.hbow");
    FAIL() << "loaded a missing file";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("absent.hbow: vocabulary file does not exist"));
  }
  testing::WriteText(scratch / "text.hbow", "HOIDBOW but text\n");
  try {
    Vocabulary::Load(scratch / "text.hbow");
    FAIL() << "loaded a text file";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (scratch / "text.hbow").string() +
                  ": not a hoidslam vocabulary file (it does not begin with the magic bytes HOIDBOW\\x1a)");
  }
}

TEST(VocabularyFile, SaveLeavesNoHalfWrittenFileWhereItCannotWrite) {
  const testing::TempDir scratch;
  const Vocabulary vocabulary = Vocabulary::Load(EncodeVocabulary(SmallTree()), "tree.hbow");
  EXPECT_THROW(vocabulary.Save(scratch / "no-such-folder" / "tree.hbow"), core::InputError);
  vocabulary.Save(scratch / "tree.hbow");
  EXPECT_EQ(Vocabulary::Load(scratch / "tree.hbow").identity(), vocabulary.identity());
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(scratch.path()), {}), 1);
}

}  // namespace
}  // namespace hoidslam::bow
