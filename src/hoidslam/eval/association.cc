#include "hoidslam/eval/association.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include <limits>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::eval {

namespace {

// About 0.5 GB of candidates: far beyond any sensible tolerance, well below what a 2-core machine holds.
constexpr std::size_t kMaxCandidates = 20'000'000;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Candidate {
  double difference;
  double a;
  double b;
  std::size_t first;
  std::size_t second;
};

}  // namespace

void AssociationOptions::Check() const {
  if (!std::isfinite(max_difference) || max_difference <= 0.0)
    throw core::InputError::ForParameter("--max-difference", fmt::format("must be > 0 seconds, got {}", max_difference));
  if (!std::isfinite(offset)) throw core::InputError::ForParameter("--offset", "must be a finite number of seconds");
}

std::vector<Match> AssociateByTimestamp(std::span<const double> first, std::span<const double> second,
                                        const AssociationOptions& options) {
  options.Check();
  // Shifted second stamps in ascending order, so each first stamp finds its candidates by binary search.
  std::vector<std::size_t> order(second.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<double> shifted(second.size());
  for (std::size_t j = 0; j < second.size(); ++j) shifted[j] = second[j] + options.offset;
  std::sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return shifted[l] < shifted[r]; });
  std::vector<double> sorted_shifted(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted_shifted[k] = shifted[order[k]];

  // Windows widened by one unit in the last place against the rounding of first ± max_difference; the exact
  // test below decides, as associate.py does.
  std::vector<std::pair<std::size_t, std::size_t>> windows(first.size());
  std::size_t total = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const auto lo = std::lower_bound(sorted_shifted.begin(), sorted_shifted.end(),
                                     std::nextafter(first[i] - options.max_difference, -kInfinity));
    const auto hi = std::upper_bound(lo, sorted_shifted.end(),
                                     std::nextafter(first[i] + options.max_difference, kInfinity));
    windows[i] = {static_cast<std::size_t>(lo - sorted_shifted.begin()),
                  static_cast<std::size_t>(hi - sorted_shifted.begin())};
    total += windows[i].second - windows[i].first;
  }
  if (total > kMaxCandidates)
    throw core::InputError::ForParameter(
        "--max-difference", fmt::format("{} s lets {} stamp pairs compete for matches; use a tolerance near the "
                                        "frame spacing (default 0.02 s)", options.max_difference, total));

  std::vector<Candidate> candidates;
  candidates.reserve(total);
  for (std::size_t i = 0; i < first.size(); ++i) {
    for (std::size_t k = windows[i].first; k < windows[i].second; ++k) {
      const std::size_t j = order[k];
      const double difference = std::abs(first[i] - (second[j] + options.offset));
      if (difference < options.max_difference) candidates.push_back({difference, first[i], second[j], i, j});
    }
  }
  // associate.py sorts (difference, a, b) tuples; indices only make equal stamps deterministic.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
    return std::tie(l.difference, l.a, l.b, l.first, l.second) < std::tie(r.difference, r.a, r.b, r.first, r.second);
  });

  std::vector<bool> first_used(first.size(), false);
  std::vector<bool> second_used(second.size(), false);
  std::vector<Match> matches;
  for (const Candidate& c : candidates) {
    if (first_used[c.first] || second_used[c.second]) continue;
    first_used[c.first] = true;
    second_used[c.second] = true;
    matches.push_back({c.first, c.second});
  }
  std::sort(matches.begin(), matches.end(), [&](const Match& l, const Match& r) {
    return std::tie(first[l.first], second[l.second], l.first) < std::tie(first[r.first], second[r.second], r.first);
  });
  return matches;
}

std::vector<Match> AssociateByTimestamp(const core::Trajectory& first, const core::Trajectory& second,
                                        const AssociationOptions& options) {
  return AssociateByTimestamp(Timestamps(first), Timestamps(second), options);
}

std::size_t ClosestIndex(std::span<const double> sorted, double t) {
  if (sorted.empty()) throw std::invalid_argument("ClosestIndex: empty list");
  const auto after = std::lower_bound(sorted.begin(), sorted.end(), t);
  if (after == sorted.begin()) return 0;
  const auto index = static_cast<std::size_t>(after - sorted.begin());
  if (after == sorted.end()) return index - 1;
  return t - sorted[index - 1] <= *after - t ? index - 1 : index;
}

core::Trajectory SortedUniqueByTime(core::Trajectory trajectory) {
  for (const core::StampedPose& pose : trajectory)
    if (!std::isfinite(pose.timestamp)) throw core::InputError("a trajectory has a timestamp that is not a number");
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const core::StampedPose& l, const core::StampedPose& r) { return l.timestamp < r.timestamp; });
  // Keep the last of each run of equal stamps: walk backwards keeping first occurrences, then restore order.
  std::reverse(trajectory.begin(), trajectory.end());
  const auto end = std::unique(trajectory.begin(), trajectory.end(), [](const auto& l, const auto& r) {
    return l.timestamp == r.timestamp;
  });
  trajectory.erase(end, trajectory.end());
  std::reverse(trajectory.begin(), trajectory.end());
  return trajectory;
}

std::vector<double> Timestamps(const core::Trajectory& trajectory) {
  std::vector<double> stamps(trajectory.size());
  std::transform(trajectory.begin(), trajectory.end(), stamps.begin(),
                 [](const core::StampedPose& p) { return p.timestamp; });
  return stamps;
}

}  // namespace hoidslam::eval
