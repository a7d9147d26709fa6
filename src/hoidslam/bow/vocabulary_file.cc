#include "hoidslam/bow/vocabulary_file.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::bow {
namespace {

constexpr std::array<std::uint8_t, 8> kMagic = {'H', 'O', 'I', 'D', 'B', 'O', 'W', 0x1a};
constexpr std::size_t kHeaderBytes = kMagic.size() + 4 * 4 + 2 * 8;
constexpr std::size_t kNodeBytes = kDescriptorBytes + 4 + 8;

template <typename Unsigned>
void Put(std::vector<std::uint8_t>& out, Unsigned value) {
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) out.push_back(static_cast<std::uint8_t>(value >> (8 * i)));
}

template <typename Unsigned>
Unsigned Get(std::span<const std::uint8_t> bytes, std::size_t& offset) {
  Unsigned value = 0;
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) value |= static_cast<Unsigned>(bytes[offset + i]) << (8 * i);
  offset += sizeof(Unsigned);
  return value;
}

// The most nodes a tree of branching factor k and L levels has: 1 + k + ... + k^L (below 2^49 within the limits).
std::uint64_t MaxNodes(std::uint64_t k, int levels) {
  std::uint64_t nodes = 1;
  std::uint64_t level_nodes = 1;
  for (int level = 1; level <= levels; ++level) {
    level_nodes *= k;
    nodes += level_nodes;
  }
  return nodes;
}

// Reads the header into `tree` and checks that the file's size and checksum match it; returns the node count.
std::uint32_t ReadHeader(std::span<const std::uint8_t> bytes, const std::string& source, VocabularyTree& tree) {
  const auto fail = [&source](const std::string& what) { return core::InputError::InFile(source, what); };
  const std::size_t magic_bytes = std::min(bytes.size(), kMagic.size());
  if (!std::equal(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(magic_bytes), kMagic.begin())) {
    throw fail("not a hoidslam vocabulary file (it does not begin with the magic bytes HOIDBOW\\x1a)");
  }
  if (bytes.size() < kHeaderBytes + kChecksumBytes) {
    throw fail(fmt::format("truncated: {} bytes, shorter than the {}-byte header and checksum", bytes.size(),
                           kHeaderBytes + kChecksumBytes));
  }
  std::size_t offset = kMagic.size();
  const auto version = Get<std::uint32_t>(bytes, offset);
  const auto branching = Get<std::uint32_t>(bytes, offset);
  const auto levels = Get<std::uint32_t>(bytes, offset);
  const auto node_count = Get<std::uint32_t>(bytes, offset);
  tree.training_images = Get<std::uint64_t>(bytes, offset);
  tree.training_descriptors = Get<std::uint64_t>(bytes, offset);
  if (version != kVocabularyFormatVersion) {
    throw fail(fmt::format("unsupported format version {} (this hoidslam reads version {})", version,
                           kVocabularyFormatVersion));
  }
  if (branching < kMinBranching || branching > kMaxBranching) {
    throw fail(fmt::format("branching factor {} is outside [{}, {}]", branching, kMinBranching, kMaxBranching));
  }
  if (levels < kMinLevels || levels > kMaxLevels) {
    throw fail(fmt::format("{} levels is outside [{}, {}]", levels, kMinLevels, kMaxLevels));
  }
  tree.branching = static_cast<int>(branching);
  tree.levels = static_cast<int>(levels);
  const std::uint64_t max_nodes = MaxNodes(branching, tree.levels);
  if (node_count < 2 || node_count > max_nodes) {
    throw fail(fmt::format("{} nodes cannot make a tree of branching factor {} and {} levels (2 to {} nodes)",
                           node_count, branching, levels, max_nodes));
  }
  const std::uint64_t expected_size = kHeaderBytes + std::uint64_t{node_count} * kNodeBytes + kChecksumBytes;
  if (bytes.size() < expected_size) {
    throw fail(fmt::format("truncated: {} bytes where the header's {} nodes take {}", bytes.size(), node_count,
                           expected_size));
  }
  if (bytes.size() > expected_size) {
    throw fail(fmt::format("{} bytes past the end of the vocabulary's {}", bytes.size() - expected_size,
                           expected_size));
  }
  const std::uint64_t stored = StoredChecksum(bytes);
  if (const std::uint64_t computed = Fnv1a64(bytes.first(bytes.size() - kChecksumBytes)); stored != computed) {
    throw fail(fmt::format("corrupt: the checksum {:016x} does not match the content's {:016x}", stored, computed));
  }
  return node_count;
}

// The tree's shape and weights, which a checksum does not vouch for: a file may be written by another program.
void CheckTree(const VocabularyTree& tree, const std::string& source) {
  const auto fail = [&source](std::size_t node, const std::string& what) {
    return core::InputError::InFile(source, fmt::format("node {}: {}", node, what));
  };
  if (tree.nodes[0].centre != Descriptor{} || tree.nodes[0].idf != 0.0) {
    throw fail(0, "the root has a descriptor or a weight");
  }
  if (tree.training_images == 0) throw core::InputError::InFile(source, "trained on 0 images");
  // log(N / n) for a word in n >= 1 of N images; the bound keeps Transform's sums of weights finite.
  const double max_idf = std::log(static_cast<double>(tree.training_images));
  std::vector<std::uint8_t> depth(tree.nodes.size(), 0);
  std::uint64_t next_child = 1;
  std::uint64_t words = 0;
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    const TreeNode& node = tree.nodes[i];
    if (node.child_count > static_cast<std::uint32_t>(tree.branching)) {
      throw fail(i, fmt::format("{} children, more than the branching factor {}", node.child_count, tree.branching));
    }
    if (node.child_count > 0 && depth[i] == tree.levels) {
      throw fail(i, fmt::format("has children below the last of the {} levels", tree.levels));
    }
    if (i == 0 && node.child_count == 0) throw fail(i, "the root has no children");
    if (next_child + node.child_count > tree.nodes.size()) {
      throw fail(i, fmt::format("its children would run past the {} nodes", tree.nodes.size()));
    }
    if (node.child_count > 0 && next_child <= i) throw fail(i, "its children come before it");
    for (std::uint32_t c = 0; c < node.child_count; ++c) {
      depth[next_child + c] = static_cast<std::uint8_t>(depth[i] + 1);
    }
    next_child += node.child_count;
    if (i > 0 && node.child_count == 0) {
      ++words;
      if (!(node.idf >= 0.0 && node.idf <= max_idf)) {
        throw fail(i, fmt::format("word weight {} is outside [0, log({} training image{})]", node.idf,
                                  tree.training_images, tree.training_images == 1 ? "" : "s"));
      }
    } else if (i > 0 && node.idf != 0.0) {
      throw fail(i, fmt::format("a weight {} on a node that is not a word", node.idf));
    }
  }
  if (next_child != tree.nodes.size()) {
    throw core::InputError::InFile(source, fmt::format("the child counts place {} nodes, the header says {}",
                                                       next_child, tree.nodes.size()));
  }
  if (tree.training_descriptors < words) {
    throw core::InputError::InFile(
        source, fmt::format("{} word{} cannot come from training on {} descriptor{} of {} image{}", words,
                            words == 1 ? "" : "s", tree.training_descriptors, tree.training_descriptors == 1 ? "" : "s",
                            tree.training_images, tree.training_images == 1 ? "" : "s"));
  }
}

}  // namespace

std::uint64_t Fnv1a64(std::span<const std::uint8_t> bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (const std::uint8_t byte : bytes) {
    hash ^= byte;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::uint64_t StoredChecksum(std::span<const std::uint8_t> file_bytes) {
  std::size_t offset = file_bytes.size() - kChecksumBytes;
  return Get<std::uint64_t>(file_bytes, offset);
}

std::vector<std::uint8_t> EncodeVocabulary(const VocabularyTree& tree) {
  std::vector<std::uint8_t> out(kMagic.begin(), kMagic.end());
  out.reserve(kHeaderBytes + tree.nodes.size() * kNodeBytes + kChecksumBytes);
  Put<std::uint32_t>(out, kVocabularyFormatVersion);
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(tree.branching));
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(tree.levels));
  Put<std::uint32_t>(out, static_cast<std::uint32_t>(tree.nodes.size()));
  Put<std::uint64_t>(out, tree.training_images);
  Put<std::uint64_t>(out, tree.training_descriptors);
  for (const TreeNode& node : tree.nodes) {
    const std::size_t at = out.size();
    out.resize(at + kDescriptorBytes);
    std::memcpy(out.data() + at, node.centre.data(), kDescriptorBytes);
    Put<std::uint32_t>(out, node.child_count);
    Put<std::uint64_t>(out, std::bit_cast<std::uint64_t>(node.idf));
  }
  Put<std::uint64_t>(out, Fnv1a64(out));
  return out;
}

VocabularyTree DecodeVocabulary(std::span<const std::uint8_t> bytes, const std::string& source) {
  VocabularyTree tree;
  tree.nodes.resize(ReadHeader(bytes, source, tree));
  std::size_t offset = kHeaderBytes;
  for (TreeNode& node : tree.nodes) {
    std::memcpy(node.centre.data(), bytes.data() + offset, kDescriptorBytes);
    offset += kDescriptorBytes;
    node.child_count = Get<std::uint32_t>(bytes, offset);
    node.idf = std::bit_cast<double>(Get<std::uint64_t>(bytes, offset));
  }
  CheckTree(tree, source);
  return tree;
}

}  // namespace hoidslam::bow
