#include "fuzz/fuzz_target.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <Eigen/Geometry>

#include "hoidslam/bow/vocabulary_file.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::fuzz {

namespace fs = std::filesystem;

void Require(bool condition, const std::string& what) {
  if (!condition) throw ContractViolation(what);
}

const fs::path& ScratchDir() {
  static const testing::TempDir dir;
  return dir.path();
}

void WriteBytes(const fs::path& path, Bytes bytes) {
  testing::WriteText(path, std::string(bytes.begin(), bytes.end()));
}

void WriteOrRemove(const fs::path& path, const std::optional<Bytes>& bytes) {
  if (bytes) {
    WriteBytes(path, *bytes);
  } else {
    fs::remove(path);
  }
}

std::vector<Bytes> SplitFiles(Bytes input, std::size_t count) {
  constexpr std::string_view kSeparator = "%%";
  std::vector<Bytes> files;
  std::size_t file_begin = 0;
  for (std::size_t line_begin = 0; line_begin < input.size() && files.size() + 1 < count;) {
    std::size_t line_end = line_begin;
    while (line_end < input.size() && input[line_end] != '\n') ++line_end;
    const std::string_view line(reinterpret_cast<const char*>(input.data()) + line_begin, line_end - line_begin);
    const std::size_t next = std::min(line_end + 1, input.size());
    if (line == kSeparator) {
      files.push_back(input.subspan(file_begin, line_begin - file_begin));
      file_begin = next;
    }
    line_begin = next;
  }
  files.push_back(input.subspan(file_begin));
  return files;
}

std::optional<std::vector<std::uint8_t>> WithChecksum(Bytes input) {
  if (input.size() < bow::kChecksumBytes) return std::nullopt;
  std::vector<std::uint8_t> checksummed(input.begin(), input.end());
  const std::size_t content = checksummed.size() - bow::kChecksumBytes;
  const std::uint64_t checksum = bow::Fnv1a64(std::span(checksummed).first(content));
  for (std::size_t i = 0; i < bow::kChecksumBytes; ++i) {
    checksummed[content + i] = static_cast<std::uint8_t>(checksum >> (8 * i));
  }
  return checksummed;
}

void CheckRejection(const core::InputError& error, const std::string& source) {
  const std::string_view what = error.what();
  Require(what.starts_with(source), "the message does not begin with the file " + source + ": " + error.what());
  const bool one_line = std::none_of(what.begin(), what.end(), [](char c) {
    const auto byte = static_cast<unsigned char>(c);
    return (byte < 0x20 && c != '\t') || byte == 0x7F;
  });
  Require(one_line, std::string("the message is not one line of text: ") + error.what());
}

void CheckTrajectory(const core::Trajectory& trajectory) {
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const core::StampedPose& stamped = trajectory[i];
    Require(std::isfinite(stamped.timestamp), "a timestamp is not finite");
    Require(i == 0 || trajectory[i - 1].timestamp < stamped.timestamp, "timestamps are not strictly increasing");
    Require(stamped.T_wc.translation().allFinite(), "a translation is not finite");
    const Eigen::Matrix3d R = stamped.T_wc.linear();
    Require(R.allFinite() && (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0.0,
            "a rotation is not a rotation");
  }
}

}  // namespace hoidslam::fuzz
