#pragma once
// Child processes for the bench: each job is one command whose output goes to its own log file, run with at most
// N at a time, each under a time limit. The pool owns its children: a job past its limit is stopped (SIGTERM,
// then SIGKILL), and a pool destroyed early (an exception) kills and reaps whatever still runs, so no child
// outlives the bench.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace hoidslam::bench {

struct Job {
  std::vector<std::string> command;  // command[0] is an absolute path to the program
  std::filesystem::path log;         // stdout and stderr of the child, appended to
};

struct JobOutcome {
  int exit_code = -1;      // the child's exit status when it exited
  int signal = 0;          // the signal that ended it, 0 if it exited
  bool timed_out = false;  // stopped by the pool at its time limit
  double seconds = 0.0;

  bool Succeeded() const { return signal == 0 && exit_code == 0 && !timed_out; }
  std::string Describe() const;  // "exit status 1", "killed by signal 11", "timed out after 3600 s"
};

struct PoolOptions {
  std::size_t parallel = 1;       // jobs running at once, >= 1
  double timeout_seconds = 0.0;   // per job; 0 = no limit
  double kill_grace_seconds = 10.0;  // after SIGTERM (time limit, or a stop request), SIGKILL follows
};

// Runs `jobs` in order. `on_finished(index, outcome)` is called on this thread as each one ends. When
// `stop_requested` turns true no new job starts and the running ones get SIGINT (they finish their outputs as
// on Ctrl-C); RunJobs returns once all have ended. Returns how many jobs were started. Throws core::Error when a
// log file cannot be opened or a process cannot be started.
std::size_t RunJobs(const std::vector<Job>& jobs, const PoolOptions& options,
                    const std::function<void(std::size_t, const JobOutcome&)>& on_finished,
                    const std::function<bool()>& stop_requested = {});

}  // namespace hoidslam::bench
