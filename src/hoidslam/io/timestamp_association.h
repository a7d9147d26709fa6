#pragma once
// Matching two lists of timestamps as TUM's associate.py does. Used to pair RGB with depth images when a
// sequence is read, and ground truth with an estimate when a trajectory is evaluated.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace hoidslam::io {

// A matched pair: indices into the first and second timestamp lists.
struct TimestampMatch {
  std::size_t first = 0;
  std::size_t second = 0;

  friend bool operator==(const TimestampMatch&, const TimestampMatch&) = default;
};

// associate.py: every pair (a, b) with |a - (b + offset)| < max_difference is a candidate; candidates are taken
// greedily from the smallest difference up (ties by a, then b), each stamp at most once. The result is sorted
// by the first stamp. `max_difference` must be > 0 and `offset` finite (callers check their own options).
// Throws InputError naming `tolerance_parameter` if the tolerance is so wide that the candidate pairs would not
// fit in memory (tens of millions; a tolerance near the frame spacing gives a few per stamp).
std::vector<TimestampMatch> AssociateTimestamps(std::span<const double> first, std::span<const double> second,
                                                double max_difference, double offset,
                                                const std::string& tolerance_parameter);

}  // namespace hoidslam::io
