#pragma once
// What every hoidslam fuzz target shares. A target feeds one input to one of the parsers users give files to,
// and checks the contract every parser keeps (DESIGN.md, "Errors"):
//
//   - malformed input is rejected with core::InputError, whose message is one line that begins with the
//     file it is about (and names the line or the key where it can);
//   - input that is accepted gives a result that keeps the parser's documented invariants (finite numbers,
//     sorted timestamps, scores in [0, 1], ...), so garbage is never taken silently.
//
// A broken contract is thrown as ContractViolation; the targets let it and every exception other than
// InputError escape, so that libFuzzer reports it as a crash and the replay test (replay_test.cc) as a failure.
// Sanitizer reports and time-outs are findings too; libFuzzer reports those itself.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "hoidslam/core/error.h"
#include "hoidslam/core/pose.h"

namespace hoidslam::fuzz {

using Bytes = std::span<const std::uint8_t>;

class ContractViolation : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

// Throws ContractViolation("<what>") unless `condition` holds.
void Require(bool condition, const std::string& what);

// A scratch folder of this process, created on first use and removed when the process exits normally.
const std::filesystem::path& ScratchDir();

// Writes `bytes` to `path` exactly as they are.
void WriteBytes(const std::filesystem::path& path, Bytes bytes);

// Writes `bytes` to `path`, or removes `path` when there are no bytes to write (nullopt), so that a target can
// also exercise a missing file.
void WriteOrRemove(const std::filesystem::path& path, const std::optional<Bytes>& bytes);

// The input cut into at most `count` files at lines that are exactly "%%" (the last file gets the rest); a
// target that reads several files (rgb.txt and depth.txt) takes its files from one input this way.
std::vector<Bytes> SplitFiles(Bytes input, std::size_t count);

// The input with its last eight bytes made the FNV-1a 64 checksum of the others (as the vocabulary and map files
// end), so that mutations get past the checksum to the checks behind it; nullopt for an input shorter than that.
std::optional<std::vector<std::uint8_t>> WithChecksum(Bytes input);

// Checks that `error` keeps the rejection contract: one line (no control character but tabs) beginning with
// `source` (the file's path).
void CheckRejection(const core::InputError& error, const std::string& source);

// Runs `parse()`: its result when it accepts the input, nullopt when it rejects it with an InputError that
// keeps the contract. Any other exception escapes.
template <typename Parse>
std::optional<std::invoke_result_t<Parse>> ParseOrReject(Parse parse, const std::string& source) {
  try {
    return parse();
  } catch (const core::InputError& error) {
    CheckRejection(error, source);
    return std::nullopt;
  }
}

// Invariants of a trajectory read from a TUM file: finite timestamps in strictly increasing order, finite
// translations, rotations that are rotations.
void CheckTrajectory(const core::Trajectory& trajectory);

}  // namespace hoidslam::fuzz
