#include "hoidslam/core/descriptor_distance.h"

#include <cstring>

#include "hoidslam/core/sanitizers.h"

namespace hoidslam::core {

// The build targets baseline x86-64, where __builtin_popcountll is a library call; a second copy compiled for
// the POPCNT instruction is picked at load time on CPUs that have it (about 5× faster here). Not under
// ThreadSanitizer: GCC's instruments the load-time picker (an ifunc resolver), which then runs before the
// sanitizer's runtime has started and crashes every program at load.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && !defined(HOIDSLAM_THREAD_SANITIZER)
__attribute__((target_clones("popcnt", "default")))
#endif
int DescriptorDistance(const std::uint8_t* a, const std::uint8_t* b) {
  int distance = 0;
  for (int i = 0; i < kOrbDescriptorBytes; i += 8) {
    std::uint64_t wa = 0;
    std::uint64_t wb = 0;
    std::memcpy(&wa, a + i, 8);  // rows need not be 8-byte aligned
    std::memcpy(&wb, b + i, 8);
    distance += __builtin_popcountll(wa ^ wb);
  }
  return distance;
}

}  // namespace hoidslam::core
