#include "hoidslam/io/timestamp_association.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io {
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

std::vector<TimestampMatch> AssociateTimestamps(std::span<const double> first, std::span<const double> second,
                                                double max_difference, double offset,
                                                const std::string& tolerance_parameter) {
  // Shifted second stamps in ascending order, so each first stamp finds its candidates by binary search.
  std::vector<std::size_t> order(second.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<double> shifted(second.size());
  for (std::size_t j = 0; j < second.size(); ++j) shifted[j] = second[j] + offset;
  std::sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) { return shifted[l] < shifted[r]; });
  std::vector<double> sorted_shifted(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted_shifted[k] = shifted[order[k]];

  // Windows widened by one unit in the last place against the rounding of first ± max_difference; the exact
  // test below decides, as associate.py does.
  std::vector<std::pair<std::size_t, std::size_t>> windows(first.size());
  std::size_t total = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const auto lo = std::lower_bound(sorted_shifted.begin(), sorted_shifted.end(),
                                     std::nextafter(first[i] - max_difference, -kInfinity));
    const auto hi =
        std::upper_bound(lo, sorted_shifted.end(), std::nextafter(first[i] + max_difference, kInfinity));
    windows[i] = {static_cast<std::size_t>(lo - sorted_shifted.begin()),
                  static_cast<std::size_t>(hi - sorted_shifted.begin())};
    total += windows[i].second - windows[i].first;
  }
  if (total > kMaxCandidates) {
    throw core::InputError::ForParameter(
        tolerance_parameter, fmt::format("{} s lets {} stamp pairs compete for matches; use a tolerance near the "
                                         "frame spacing (default 0.02 s)",
                                         max_difference, total));
  }

  std::vector<Candidate> candidates;
  candidates.reserve(total);
  for (std::size_t i = 0; i < first.size(); ++i) {
    for (std::size_t k = windows[i].first; k < windows[i].second; ++k) {
      const std::size_t j = order[k];
      const double difference = std::abs(first[i] - (second[j] + offset));
      if (difference < max_difference) candidates.push_back({difference, first[i], second[j], i, j});
    }
  }
  // associate.py sorts (difference, a, b) tuples; indices only make equal stamps deterministic.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
    return std::tie(l.difference, l.a, l.b, l.first, l.second) < std::tie(r.difference, r.a, r.b, r.first, r.second);
  });

  std::vector<bool> first_used(first.size(), false);
  std::vector<bool> second_used(second.size(), false);
  std::vector<TimestampMatch> matches;
  for (const Candidate& c : candidates) {
    if (first_used[c.first] || second_used[c.second]) continue;
    first_used[c.first] = true;
    second_used[c.second] = true;
    matches.push_back({c.first, c.second});
  }
  std::sort(matches.begin(), matches.end(), [&](const TimestampMatch& l, const TimestampMatch& r) {
    return std::tie(first[l.first], second[l.second], l.first) < std::tie(first[r.first], second[r.second], r.first);
  });
  return matches;
}

}  // namespace hoidslam::io
