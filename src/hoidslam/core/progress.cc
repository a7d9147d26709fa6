#include "hoidslam/core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace hoidslam::core {

std::string FormatDuration(double seconds) {
  const auto total = static_cast<long long>(std::max(0.0, seconds) + 0.5);
  if (total >= 3600) return fmt::format("{}:{:02}:{:02}", total / 3600, total / 60 % 60, total % 60);
  return fmt::format("{}:{:02}", total / 60, total % 60);
}

ProgressReporter::ProgressReporter(std::string label, std::size_t total)
    : label_(std::move(label)), total_(total), terminal_(isatty(fileno(stderr)) != 0) {}

ProgressReporter::~ProgressReporter() {
  if (line_open_) std::fputc('\n', stderr);  // cannot throw, unlike fmt::print to a closed stderr
}

void ProgressReporter::Update(std::size_t done) {
  const double elapsed = clock_.ElapsedSeconds();
  const double interval = terminal_ ? 0.2 : 5.0;
  if (done < total_ && elapsed - last_shown_ < interval) return;
  last_shown_ = elapsed;
  const double rate = elapsed > 0.0 ? static_cast<double>(done) / elapsed : 0.0;
  const std::string eta = rate > 0.0 ? FormatDuration(static_cast<double>(total_ - done) / rate) : "?";
  const std::string line = fmt::format("{}: {}/{} frames, {:.1f} fps, ETA {}", label_, done, total_, rate, eta);
  if (!terminal_) {
    spdlog::info("{}", line);
    return;
  }
  line_open_ = done < total_;
  fmt::print(stderr, "\r{}\033[K{}", line, line_open_ ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace hoidslam::core
