#include "hoidslam/bow/k_majority.h"

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace hoidslam::bow {
namespace {

Descriptor RandomDescriptor(std::mt19937_64& rng) { return {rng(), rng(), rng(), rng()}; }

// `copies` copies of each prototype, each with `flips` bits flipped at random, the prototypes interleaved.
std::vector<Descriptor> NoisyCopies(const std::vector<Descriptor>& prototypes, int copies, int flips,
                                    std::mt19937_64& rng) {
  std::vector<Descriptor> descriptors;
  for (int c = 0; c < copies; ++c) {
    for (const Descriptor& prototype : prototypes) {
      Descriptor copy = prototype;
      for (int f = 0; f < flips; ++f) {
        const auto bit = rng() % 256;
        copy[bit / 64] ^= std::uint64_t{1} << (bit % 64);
      }
      descriptors.push_back(copy);
    }
  }
  return descriptors;
}

std::vector<std::uint32_t> AllOf(const std::vector<Descriptor>& descriptors) {
  std::vector<std::uint32_t> members(descriptors.size());
  std::iota(members.begin(), members.end(), 0U);
  return members;
}

TEST(KMajority, FindsFarApartGroupsAndTheirPrototypesAsCentres) {
  std::mt19937_64 data_rng(3);
  std::vector<Descriptor> prototypes;
  for (int p = 0; p < 5; ++p) prototypes.push_back(RandomDescriptor(data_rng));
  const std::vector<Descriptor> descriptors = NoisyCopies(prototypes, 40, 12, data_rng);
  std::mt19937 rng(1);
  const std::vector<Cluster> clusters = KMajority(descriptors, AllOf(descriptors), 5, 10, rng);
  ASSERT_EQ(clusters.size(), 5U);
  std::vector<Descriptor> centres;
  for (const Cluster& cluster : clusters) {
    ASSERT_EQ(cluster.members.size(), 40U);
    // Copies of one prototype, as they were interleaved.
    for (const std::uint32_t member : cluster.members) EXPECT_EQ(member % 5, cluster.members.front() % 5);
    EXPECT_TRUE(std::is_sorted(cluster.members.begin(), cluster.members.end()));
    centres.push_back(cluster.centre);
  }
  // 40 copies with 12 of 256 bits flipped each outvote the noise on every bit.
  std::sort(centres.begin(), centres.end());
  std::sort(prototypes.begin(), prototypes.end());
  EXPECT_EQ(centres, prototypes);
}

TEST(KMajority, FewerDistinctDescriptorsThanKGiveOneClusterEach) {
  std::mt19937_64 data_rng(4);
  const Descriptor a = RandomDescriptor(data_rng);
  const Descriptor b = RandomDescriptor(data_rng);
  const std::vector<Descriptor> descriptors = {a, b, a, a, b};
  std::mt19937 rng(1);
  const std::vector<Cluster> clusters = KMajority(descriptors, AllOf(descriptors), 10, 10, rng);
  ASSERT_EQ(clusters.size(), 2U);
  for (const Cluster& cluster : clusters) {
    for (const std::uint32_t member : cluster.members) EXPECT_EQ(descriptors[member], cluster.centre);
  }
  EXPECT_EQ(clusters[0].members.size() + clusters[1].members.size(), 5U);
}

TEST(KMajority, SplitsOnlyTheMembersAskedAndTheSameGeneratorGivesTheSameClusters) {
  std::mt19937_64 data_rng(5);
  std::vector<Descriptor> descriptors;
  for (int i = 0; i < 300; ++i) descriptors.push_back(RandomDescriptor(data_rng));
  std::vector<std::uint32_t> odd;
  for (std::uint32_t i = 1; i < 300; i += 2) odd.push_back(i);
  std::mt19937 first(9);
  std::mt19937 second(9);
  const std::vector<Cluster> a = KMajority(descriptors, odd, 4, 5, first);
  const std::vector<Cluster> b = KMajority(descriptors, odd, 4, 5, second);
  ASSERT_EQ(a.size(), 4U);
  std::vector<std::uint32_t> members;
  for (std::size_t c = 0; c < a.size(); ++c) {
    EXPECT_EQ(a[c].centre, b[c].centre);
    EXPECT_EQ(a[c].members, b[c].members);
    members.insert(members.end(), a[c].members.begin(), a[c].members.end());
  }
  std::sort(members.begin(), members.end());
  EXPECT_EQ(members, odd);
}

}  // namespace
}  // namespace hoidslam::bow
