#include "hoidslam/eval/statistics.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace hoidslam::eval {

ErrorStatistics ComputeStatistics(std::span<const double> errors) {
  if (errors.empty()) throw std::invalid_argument("ComputeStatistics: no errors to summarise");
  const auto n = static_cast<double>(errors.size());
  ErrorStatistics s;
  s.count = errors.size();
  s.mean = std::accumulate(errors.begin(), errors.end(), 0.0) / n;
  double sum_squares = 0.0;
  double sum_squared_deviations = 0.0;  // two passes, as numpy.std, to stay accurate for a small spread
  for (const double e : errors) {
    sum_squares += e * e;
    sum_squared_deviations += (e - s.mean) * (e - s.mean);
  }
  s.rmse = std::sqrt(sum_squares / n);
  s.std = std::sqrt(sum_squared_deviations / n);

  std::vector<double> sorted(errors.begin(), errors.end());
  std::sort(sorted.begin(), sorted.end());
  const std::size_t middle = sorted.size() / 2;
  s.median = sorted.size() % 2 == 1 ? sorted[middle] : 0.5 * (sorted[middle - 1] + sorted[middle]);
  s.min = sorted.front();
  s.max = sorted.back();
  return s;
}

}  // namespace hoidslam::eval
