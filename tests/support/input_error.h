#pragma once
// For tests of what a bad input is told: the message of the core::InputError a call throws.

#include <string>

#include "hoidslam/core/error.h"

namespace hoidslam::testing {

// The message of the InputError `call` throws; "no error" when it throws none.
template <typename F>
std::string InputErrorOf(F call) {
  try {
    call();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace hoidslam::testing
