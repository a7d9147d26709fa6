#pragma once
// Progress of a long job on stderr: "<label>: 120/826 frames, 38.2 fps, ETA 0:18". On a terminal one line is
// rewritten in place; otherwise (a log file, a pipe, CI) a log line is written every few seconds, so logs stay
// readable.

#include <cstddef>
#include <string>

#include "hoidslam/core/stopwatch.h"

namespace hoidslam::core {

class ProgressReporter {
 public:
  ProgressReporter(std::string label, std::size_t total);
  // Ends an unfinished in-place line (after an error or an interruption), so later messages start on their own.
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  // `done` of the total are finished. Not thread-safe: callers on several threads serialise the calls.
  void Update(std::size_t done);

 private:
  std::string label_;
  std::size_t total_;
  bool terminal_;
  Stopwatch clock_;
  double last_shown_ = -1.0;
  bool line_open_ = false;
};

// "m:ss", or "h:mm:ss" from an hour on.
std::string FormatDuration(double seconds);

}  // namespace hoidslam::core
