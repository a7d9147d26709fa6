#pragma once
// The checks option structs' Check() is built from, so that every out-of-range value gets the same message naming
// its settings key. NaN fails every check: the comparisons are written negated.

#include <string>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::core {

inline void CheckPositive(double value, const std::string& parameter) {
  if (!(value > 0.0)) throw InputError::ForParameter(parameter, fmt::format("must be > 0, got {}", value));
}

// For values where 0 switches something off.
inline void CheckNotNegative(double value, const std::string& parameter) {
  if (!(value >= 0.0)) throw InputError::ForParameter(parameter, fmt::format("must be >= 0 (0: off), got {}", value));
}

// A share: in (0, 1].
inline void CheckShare(double value, const std::string& parameter) {
  if (!(value > 0.0 && value <= 1.0)) {
    throw InputError::ForParameter(parameter, fmt::format("must be in (0, 1], got {}", value));
  }
}

inline void CheckInRange(double value, double lo, double hi, const std::string& parameter) {
  if (!(value >= lo && value <= hi)) {
    throw InputError::ForParameter(parameter, fmt::format("must be in [{}, {}], got {}", lo, hi, value));
  }
}

}  // namespace hoidslam::core
