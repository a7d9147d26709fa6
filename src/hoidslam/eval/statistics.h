#pragma once
// Summary statistics of a list of errors, as TUM's evaluation scripts print them (numpy semantics).

#include <cstddef>
#include <span>

namespace hoidslam::eval {

struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0.0;    // sqrt(mean(e^2))
  double mean = 0.0;
  double median = 0.0;  // mean of the two middle values for an even count, as numpy.median
  double std = 0.0;     // population standard deviation (divides by count), as numpy.std
  double min = 0.0;
  double max = 0.0;
};

// Statistics of `errors`; throws std::invalid_argument when it is empty (callers check their match counts).
ErrorStatistics ComputeStatistics(std::span<const double> errors);

}  // namespace hoidslam::eval
