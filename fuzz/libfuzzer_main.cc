// The libFuzzer entry point of one fuzz target, chosen at build time by HOIDSLAM_FUZZ_TARGET (fuzz/CMakeLists.txt).

#include <cstddef>
#include <cstdint>

#include "fuzz/targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const auto run = hoidslam::fuzz::FindTarget(HOIDSLAM_FUZZ_TARGET).run;
  run({data, size});
  return 0;
}
