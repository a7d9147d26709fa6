#pragma once
// A 256-bit ORB descriptor as four 64-bit words, so that the Hamming distance is four popcounts. OpenCV rows need
// not be 8-byte aligned, hence the copy in.

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>

namespace hoidslam::bow {

inline constexpr int kDescriptorBytes = 32;

using Descriptor = std::array<std::uint64_t, 4>;

// The descriptor in the 32 bytes at `row` (one row of a CV_8U descriptor matrix).
inline Descriptor DescriptorFromRow(const std::uint8_t* row) {
  Descriptor descriptor;
  std::memcpy(descriptor.data(), row, kDescriptorBytes);
  return descriptor;
}

inline int HammingDistance(const Descriptor& a, const Descriptor& b) {
  return std::popcount(a[0] ^ b[0]) + std::popcount(a[1] ^ b[1]) + std::popcount(a[2] ^ b[2]) +
         std::popcount(a[3] ^ b[3]);
}

}  // namespace hoidslam::bow
