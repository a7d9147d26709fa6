#include "hoidslam/bow/k_majority.h"

#include <algorithm>
#include <array>
#include <limits>

namespace hoidslam::bow {
namespace {

constexpr int kDescriptorBits = 8 * kDescriptorBytes;

// A whole number in [0, bound) from two 32-bit draws, one a statement, so that no compiler reorders them; the
// modulo's bias is below bound / 2^64.
std::uint64_t DrawBelow(std::mt19937& rng, std::uint64_t bound) {
  const std::uint64_t high = rng();
  const std::uint64_t low = rng();
  return ((high << 32) | low) % bound;
}

// k-means++: the first centre at random, each next one drawn with probability proportional to the squared
// distance to the nearest centre chosen so far. Stops early when every member equals a chosen centre.
std::vector<Descriptor> SeedCentres(std::span<const Descriptor> descriptors, std::span<const std::uint32_t> members,
                                    int k, std::mt19937& rng) {
  std::vector<Descriptor> centres{descriptors[members[DrawBelow(rng, members.size())]]};
  std::vector<std::uint64_t> nearest_squared(members.size(), std::numeric_limits<std::uint64_t>::max());
  while (true) {
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const auto distance = static_cast<std::uint64_t>(HammingDistance(descriptors[members[i]], centres.back()));
      nearest_squared[i] = std::min(nearest_squared[i], distance * distance);
      total += nearest_squared[i];
    }
    if (static_cast<int>(centres.size()) == k || total == 0) return centres;
    std::uint64_t pick = DrawBelow(rng, total);
    std::size_t chosen = 0;
    while (pick >= nearest_squared[chosen]) pick -= nearest_squared[chosen++];
    centres.push_back(descriptors[members[chosen]]);
  }
}

// Sets each member's nearest centre (the first of equals); returns whether any assignment changed.
bool AssignToNearest(std::span<const Descriptor> descriptors, std::span<const std::uint32_t> members,
                     const std::vector<Descriptor>& centres, std::vector<std::uint32_t>& assignment) {
  bool changed = false;
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Descriptor& descriptor = descriptors[members[i]];
    std::uint32_t best = 0;
    int best_distance = HammingDistance(descriptor, centres[0]);
    for (std::uint32_t c = 1; c < centres.size(); ++c) {
      const int distance = HammingDistance(descriptor, centres[c]);
      if (distance < best_distance) {
        best_distance = distance;
        best = c;
      }
    }
    changed |= assignment[i] != best;
    assignment[i] = best;
  }
  return changed;
}

// Each centre with members becomes their per-bit majority; a centre without members keeps its place.
void MoveCentresToMajorities(std::span<const Descriptor> descriptors, std::span<const std::uint32_t> members,
                             const std::vector<std::uint32_t>& assignment, std::vector<Descriptor>& centres) {
  std::vector<std::array<std::uint32_t, kDescriptorBits>> bit_counts(centres.size());
  std::vector<std::uint32_t> sizes(centres.size(), 0);
  for (std::size_t i = 0; i < members.size(); ++i) {
    const Descriptor& descriptor = descriptors[members[i]];
    std::array<std::uint32_t, kDescriptorBits>& counts = bit_counts[assignment[i]];
    ++sizes[assignment[i]];
    for (int word = 0; word < 4; ++word) {
      for (int bit = 0; bit < 64; ++bit) counts[64 * word + bit] += (descriptor[word] >> bit) & 1U;
    }
  }
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (sizes[c] == 0) continue;
    for (int word = 0; word < 4; ++word) {
      std::uint64_t majority = 0;
      for (int bit = 0; bit < 64; ++bit) {
        if (2 * bit_counts[c][64 * word + bit] > sizes[c]) majority |= std::uint64_t{1} << bit;
      }
      centres[c][word] = majority;
    }
  }
}

}  // namespace

std::vector<Cluster> KMajority(std::span<const Descriptor> descriptors, std::span<const std::uint32_t> members, int k,
                               int max_iterations, std::mt19937& rng) {
  std::vector<Descriptor> centres = SeedCentres(descriptors, members, k, rng);
  std::vector<std::uint32_t> assignment(members.size(), 0);
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    if (!AssignToNearest(descriptors, members, centres, assignment) && iteration > 0) break;
    MoveCentresToMajorities(descriptors, members, assignment, centres);
  }

  std::vector<Cluster> clusters(centres.size());
  for (std::size_t c = 0; c < centres.size(); ++c) clusters[c].centre = centres[c];
  for (std::size_t i = 0; i < members.size(); ++i) clusters[assignment[i]].members.push_back(members[i]);
  std::erase_if(clusters, [](const Cluster& cluster) { return cluster.members.empty(); });
  return clusters;
}

}  // namespace hoidslam::bow
