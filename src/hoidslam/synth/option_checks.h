#pragma once
// Checks shared by the synth modules' option structs, so that every out-of-range value gets the same message.

#include <fmt/format.h>

#include <string>

#include "hoidslam/core/error.h"

namespace hoidslam::synth {

// Throws InputError naming `parameter` unless lo <= value <= hi (NaN fails too: the comparisons are negated).
inline void CheckInRange(double value, double lo, double hi, const std::string& parameter) {
  if (!(value >= lo && value <= hi)) {
    throw core::InputError::ForParameter(parameter, fmt::format("must be in [{}, {}], got {}", lo, hi, value));
  }
}

}  // namespace hoidslam::synth
