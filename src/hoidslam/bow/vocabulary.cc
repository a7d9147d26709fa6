#include "hoidslam/bow/vocabulary.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <numeric>
#include <random>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "hoidslam/bow/k_majority.h"
#include "hoidslam/core/error.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/files.h"

namespace hoidslam::bow {
namespace {

void CheckDescriptorMatrix(const cv::Mat& descriptors) {
  if (!descriptors.empty() && (descriptors.type() != CV_8UC1 || descriptors.cols != kDescriptorBytes)) {
    throw std::invalid_argument(fmt::format("ORB descriptors must be CV_8UC1 rows of {} bytes, got type {} and {} "
                                            "columns",
                                            kDescriptorBytes, descriptors.type(), descriptors.cols));
  }
}

// Every image's descriptors in one array, and where each image's begin (one more entry: the end).
struct TrainingSet {
  std::vector<Descriptor> descriptors;
  std::vector<std::size_t> image_begin;
};

TrainingSet GatherDescriptors(const std::vector<cv::Mat>& descriptors_per_image) {
  TrainingSet set;
  for (const cv::Mat& image : descriptors_per_image) {
    CheckDescriptorMatrix(image);
    set.image_begin.push_back(set.descriptors.size());
    for (int row = 0; row < image.rows; ++row) set.descriptors.push_back(DescriptorFromRow(image.ptr(row)));
  }
  set.image_begin.push_back(set.descriptors.size());
  if (set.descriptors.empty()) {
    throw core::InputError(fmt::format("vocabulary training: the {} image{} gave no descriptor",
                                       descriptors_per_image.size(), descriptors_per_image.size() == 1 ? "" : "s"));
  }
  if (set.descriptors.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw core::InputError(fmt::format("vocabulary training: {} descriptors, more than 2^32 - 1",
                                       set.descriptors.size()));
  }
  return set;
}

// Runs work(i) for i in [0, count), the larger tasks first, on `threads` threads; rethrows the first exception.
template <typename Work>
void ForEachLargestFirst(const std::vector<std::size_t>& sizes, int threads, const Work& work) {
  std::vector<std::size_t> order(sizes.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&sizes](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto run = [&] {
    for (std::size_t i = next++; i < order.size(); i = next++) {
      try {
        work(order[i]);
      } catch (...) {
        const std::lock_guard lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  {
    std::vector<std::jthread> workers;
    for (int t = 1; t < std::min<int>(threads, static_cast<int>(order.size())); ++t) workers.emplace_back(run);
    run();
  }
  if (failure) std::rethrow_exception(failure);
}

bool AllEqual(const std::vector<Descriptor>& descriptors, const std::vector<std::uint32_t>& members) {
  return std::all_of(members.begin(), members.end(),
                     [&](std::uint32_t m) { return descriptors[m] == descriptors[members.front()]; });
}

// A node whose training descriptors are not yet split.
struct PendingNode {
  NodeId id = 0;
  std::vector<std::uint32_t> members;
};

// The tree's shape and centres (no weights yet), grown level by level so that the nodes come in file order. Each
// node clusters with a generator seeded from (seed, node id): the same tree whatever thread clusters it.
std::vector<TreeNode> GrowTree(const std::vector<Descriptor>& descriptors, const VocabularyOptions& options) {
  std::vector<TreeNode> nodes(1);
  std::vector<PendingNode> level(1);
  level[0].members.resize(descriptors.size());
  std::iota(level[0].members.begin(), level[0].members.end(), 0U);
  const int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  for (int depth = 0; depth < options.levels && !level.empty(); ++depth) {
    std::vector<std::vector<Cluster>> splits(level.size());
    std::vector<std::size_t> sizes(level.size());
    std::transform(level.begin(), level.end(), sizes.begin(), [](const PendingNode& n) { return n.members.size(); });
    ForEachLargestFirst(sizes, threads, [&](std::size_t i) {
      const PendingNode& node = level[i];
      // A node of one distinct descriptor is a word; the root always splits, so that it has children.
      if (depth > 0 && AllEqual(descriptors, node.members)) return;
      std::seed_seq seeds{static_cast<std::uint32_t>(options.seed), static_cast<std::uint32_t>(options.seed >> 32),
                          static_cast<std::uint32_t>(node.id)};
      std::mt19937 rng(seeds);
      splits[i] = KMajority(descriptors, node.members, options.branching, options.max_iterations, rng);
    });
    std::vector<PendingNode> next;
    for (std::size_t i = 0; i < level.size(); ++i) {
      nodes[level[i].id].child_count = static_cast<std::uint32_t>(splits[i].size());
      for (Cluster& cluster : splits[i]) {
        next.push_back({static_cast<NodeId>(nodes.size()), std::move(cluster.members)});
        nodes.push_back({cluster.centre, 0, 0.0});
      }
    }
    level = std::move(next);
  }
  return nodes;
}

}  // namespace

void VocabularyOptions::Check() const {
  if (branching < kMinBranching || branching > kMaxBranching) {
    throw core::InputError::ForParameter(
        "--branching", fmt::format("must be in [{}, {}], got {}", kMinBranching, kMaxBranching, branching));
  }
  if (levels < kMinLevels || levels > kMaxLevels) {
    throw core::InputError::ForParameter("--levels",
                                         fmt::format("must be in [{}, {}], got {}", kMinLevels, kMaxLevels, levels));
  }
  if (max_iterations < 1) {
    throw core::InputError::ForParameter("--iterations", fmt::format("must be >= 1, got {}", max_iterations));
  }
  if (threads < 0) throw core::InputError::ForParameter("--threads", fmt::format("must be >= 0, got {}", threads));
}

Vocabulary::Vocabulary(VocabularyTree tree, std::uint64_t checksum)
    : tree_(std::move(tree)), identity_(fmt::format("{:016x}", checksum)) {
  const std::size_t count = tree_.nodes.size();
  first_child_.resize(count);
  node_levels_.assign(count, 0);
  node_words_.assign(count, -1);
  std::uint32_t next_child = 1;
  for (std::size_t node = 0; node < count; ++node) {
    first_child_[node] = next_child;
    for (std::uint32_t c = 0; c < tree_.nodes[node].child_count; ++c) {
      node_levels_[next_child + c] = static_cast<std::uint8_t>(node_levels_[node] + 1);
    }
    next_child += tree_.nodes[node].child_count;
    if (node > 0 && tree_.nodes[node].child_count == 0) {
      node_words_[node] = static_cast<std::int32_t>(word_nodes_.size());
      word_nodes_.push_back(static_cast<NodeId>(node));
    }
  }
}

Vocabulary Vocabulary::FromTree(VocabularyTree tree) {
  const std::uint64_t checksum = StoredChecksum(EncodeVocabulary(tree));
  return Vocabulary(std::move(tree), checksum);
}

Vocabulary Vocabulary::Train(const std::vector<cv::Mat>& descriptors_per_image, const VocabularyOptions& options) {
  options.Check();
  const TrainingSet set = GatherDescriptors(descriptors_per_image);
  VocabularyTree tree;
  tree.branching = options.branching;
  tree.levels = options.levels;
  tree.training_images = descriptors_per_image.size();
  tree.training_descriptors = set.descriptors.size();
  tree.nodes = GrowTree(set.descriptors, options);

  // The weights count the images whose descriptors Transform puts on each word, as images will be transformed.
  const Vocabulary shape = FromTree(tree);
  std::vector<std::uint32_t> images_with_word(shape.word_count(), 0);
  std::vector<WordId> image_words;
  for (std::size_t image = 0; image + 1 < set.image_begin.size(); ++image) {
    image_words.clear();
    for (std::size_t d = set.image_begin[image]; d < set.image_begin[image + 1]; ++d) {
      image_words.push_back(shape.Descend(set.descriptors[d], options.levels).word);
    }
    std::sort(image_words.begin(), image_words.end());
    image_words.erase(std::unique(image_words.begin(), image_words.end()), image_words.end());
    for (const WordId word : image_words) ++images_with_word[word];
  }
  const auto images = static_cast<double>(tree.training_images);
  for (WordId word = 0; word < shape.word_count(); ++word) {
    // A word that no training descriptor descends to (its centre moved away) counts as seen in one image.
    tree.nodes[shape.word_nodes_[word]].idf = std::log(images / std::max<std::uint32_t>(images_with_word[word], 1));
  }
  return FromTree(std::move(tree));
}

Vocabulary Vocabulary::Load(std::span<const std::uint8_t> bytes, const std::string& source) {
  VocabularyTree tree = DecodeVocabulary(bytes, source);
  return Vocabulary(std::move(tree), StoredChecksum(bytes));
}

Vocabulary Vocabulary::Load(const std::filesystem::path& path) {
  return Load(io::ReadBinaryFile(path, "vocabulary file"), path.string());
}

void Vocabulary::Save(const std::filesystem::path& path) const {
  const std::vector<std::uint8_t> bytes = Serialize();
  io::AtomicFile file(path);
  file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  file.Commit();
}

Vocabulary::Descent Vocabulary::Descend(const Descriptor& descriptor, int index_level) const {
  NodeId node = 0;
  NodeId index_node = 0;
  while (tree_.nodes[node].child_count > 0) {
    const NodeId first = first_child_[node];
    const NodeId end = first + tree_.nodes[node].child_count;
    NodeId best = first;
    int best_distance = HammingDistance(descriptor, tree_.nodes[first].centre);
    for (NodeId child = first + 1; child < end; ++child) {
      const int distance = HammingDistance(descriptor, tree_.nodes[child].centre);
      if (distance < best_distance) {
        best_distance = distance;
        best = child;
      }
    }
    node = best;
    if (node_levels_[node] <= index_level) index_node = node;
  }
  return {static_cast<WordId>(node_words_[node]), index_node};
}

ImageWords Vocabulary::Transform(const cv::Mat& descriptors, int direct_index_levels_up) const {
  CheckDescriptorMatrix(descriptors);
  if (direct_index_levels_up < 0) {
    throw std::invalid_argument(fmt::format("direct_index_levels_up must be >= 0, got {}", direct_index_levels_up));
  }
  const int index_level = std::max(tree_.levels - direct_index_levels_up, 0);
  std::vector<WordId> words(static_cast<std::size_t>(descriptors.rows));
  std::vector<std::pair<NodeId, int>> node_keypoints(words.size());
  for (int row = 0; row < descriptors.rows; ++row) {
    const Descent descent = Descend(DescriptorFromRow(descriptors.ptr(row)), index_level);
    words[static_cast<std::size_t>(row)] = descent.word;
    node_keypoints[static_cast<std::size_t>(row)] = {descent.index_node, row};
  }

  ImageWords result;
  // Term frequency times IDF, L1-normalised: the descriptor count cancels out.
  std::sort(words.begin(), words.end());
  double total = 0.0;
  for (auto run = words.begin(); run != words.end();) {
    const auto run_end = std::upper_bound(run, words.end(), *run);
    const double weight = static_cast<double>(run_end - run) * idf(*run);
    if (weight > 0.0) {
      result.bow.push_back({*run, weight});
      total += weight;
    }
    run = run_end;
  }
  for (WordWeight& entry : result.bow) entry.weight /= total;
  // A weight far below the others' (a word of a tiny IDF) can round to 0; it goes, as the words of weight 0 went.
  std::erase_if(result.bow, [](const WordWeight& entry) { return entry.weight == 0.0; });

  std::sort(node_keypoints.begin(), node_keypoints.end());
  for (const auto& [node, keypoint] : node_keypoints) {
    if (result.features.empty() || result.features.back().node != node) result.features.push_back({node, {}});
    result.features.back().keypoints.push_back(keypoint);
  }
  return result;
}

}  // namespace hoidslam::bow
