#pragma once
// Deterministic random numbers for the synthetic generator.
//
// Every component owns its generator and seeds it explicitly, usually per frame from (scenario seed, frame
// index, purpose), so frames can be produced in any order or in parallel and still give identical bytes.
// The distributions use only integer arithmetic and + - * / on doubles, never the standard library's
// distributions, whose output differs between standard libraries.

#include <cstdint>

namespace hoidslam::synth {

// SplitMix64 finaliser: a strong 64-bit mixing function.
constexpr std::uint64_t Mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30U)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27U)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31U);
}

// The seed of one purpose (sensor noise, detector noise, ...) at one frame of one scenario.
constexpr std::uint64_t FrameSeed(std::uint64_t scenario_seed, std::uint64_t frame_index, std::uint64_t purpose) {
  return Mix64(Mix64(Mix64(scenario_seed) ^ frame_index) ^ (purpose * 0xD1B54A32D192ED03ULL));
}

// A small, fast generator (SplitMix64) with the few distributions the generator needs.
// Two draws never stand as the arguments of one call or the operands of one operator: the order those are
// evaluated in is the compiler's (GCC and clang differ), and a seed must give the same bytes whatever built
// hoidslam. Where two once stood in one call, the later argument is drawn first, the order of the published
// sequences.
class Random {
 public:
  explicit constexpr Random(std::uint64_t seed) : state_(seed) {}

  constexpr std::uint64_t Next() {
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
  }

  // Uniform in [0, 1), with 53 random bits.
  constexpr double Uniform() { return static_cast<double>(Next() >> 11U) * 0x1.0p-53; }
  // Uniform in [lo, hi).
  constexpr double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [lo, hi] (inclusive); the tiny modulo bias is irrelevant here.
  constexpr int UniformInt(int lo, int hi) {
    return lo + static_cast<int>(Next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  constexpr bool Bernoulli(double p) { return Uniform() < p; }
  // Approximately standard normal: the sum of 12 uniforms minus 6 (mean 0, variance 1, tails cut at ±6).
  constexpr double Normal() {
    double sum = 0.0;
    for (int i = 0; i < 12; ++i) sum += Uniform();
    return sum - 6.0;
  }
  constexpr double Normal(double mean, double sigma) { return mean + sigma * Normal(); }

 private:
  std::uint64_t state_;
};

}  // namespace hoidslam::synth
