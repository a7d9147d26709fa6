#pragma once
// One step of the vocabulary tree's hierarchical clustering: k-majority, the binary counterpart of k-means that
// DBoW2 uses for ORB. Centres start by k-means++ seeding on the Hamming distance, every descriptor goes to its
// nearest centre, and each centre becomes the per-bit majority of its members, until no assignment changes.

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "hoidslam/bow/descriptor.h"

namespace hoidslam::bow {

struct Cluster {
  Descriptor centre;                   // the per-bit majority of the members (ties give 0)
  std::vector<std::uint32_t> members;  // indices into the descriptors, in the order given; never empty
};

// Splits `members` (indices into `descriptors`, not empty) into at most `k` clusters, in at most `max_iterations`
// rounds of assignment and update. Fewer clusters come out when the members hold fewer than k distinct
// descriptors (each distinct one then is a cluster) or when a centre loses all its members. Ties go to the centre
// chosen first. Every random draw comes from `rng` as whole numbers, so the result is the same with every standard
// library.
std::vector<Cluster> KMajority(std::span<const Descriptor> descriptors, std::span<const std::uint32_t> members, int k,
                               int max_iterations, std::mt19937& rng);

}  // namespace hoidslam::bow
