#include "hoidslam/bench/process_pool.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "hoidslam/core/error.h"
#include "hoidslam/core/stopwatch.h"

extern char** environ;

namespace hoidslam::bench {
namespace {

// One running child. Destroyed while it still runs (an exception unwinding the pool), it is killed and reaped.
class Child {
 public:
  Child(const Job& job, std::size_t index) : index_(index) {
    const int log = open(job.log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log < 0) throw core::Error(fmt::format("{}: cannot write the log: {}", job.log.string(), std::strerror(errno)));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, log, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, log, STDERR_FILENO);
    std::vector<char*> argv;
    for (const std::string& argument : job.command) argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    const int error = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(log);
    if (error != 0) throw core::Error(fmt::format("cannot start {}: {}", job.command[0], std::strerror(error)));
  }
  ~Child() {
    if (pid_ <= 0) return;
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  std::size_t index() const { return index_; }
  double seconds() const { return clock_.ElapsedSeconds(); }

  // The outcome once the child has ended; nullopt while it runs.
  std::optional<JobOutcome> Poll() {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) != pid_) return std::nullopt;
    pid_ = 0;
    JobOutcome outcome;
    outcome.seconds = clock_.ElapsedSeconds();
    outcome.timed_out = timed_out_;
    if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
    return outcome;
  }

  // Sends `signal` once; SIGKILL follows when the child outlives `grace` seconds after the first signal.
  void Stop(int signal, double grace, bool timed_out) {
    timed_out_ = timed_out_ || timed_out;
    if (!stop_clock_) {
      stop_clock_.emplace();
      kill(pid_, signal);
    } else if (stop_clock_->ElapsedSeconds() > grace) {
      kill(pid_, SIGKILL);
    }
  }

 private:
  std::size_t index_;
  pid_t pid_ = 0;
  core::Stopwatch clock_;
  std::optional<core::Stopwatch> stop_clock_;  // since the first stop signal
  bool timed_out_ = false;
};

}  // namespace

std::string JobOutcome::Describe() const {
  if (timed_out) return fmt::format("timed out after {:.0f} s", seconds);
  if (signal != 0) return fmt::format("killed by signal {} ({})", signal, strsignal(signal));
  return fmt::format("exit status {}", exit_code);
}

std::size_t RunJobs(const std::vector<Job>& jobs, const PoolOptions& options,
                    const std::function<void(std::size_t, const JobOutcome&)>& on_finished,
                    const std::function<bool()>& stop_requested) {
  const std::size_t parallel = std::max<std::size_t>(1, options.parallel);
  std::vector<std::unique_ptr<Child>> running;
  std::size_t next = 0;
  while (next < jobs.size() || !running.empty()) {
    const bool stopping = stop_requested && stop_requested();
    while (!stopping && next < jobs.size() && running.size() < parallel) {
      running.push_back(std::make_unique<Child>(jobs[next], next));
      ++next;
    }
    for (auto it = running.begin(); it != running.end();) {
      Child& child = **it;
      if (const std::optional<JobOutcome> outcome = child.Poll()) {
        const std::size_t index = child.index();
        it = running.erase(it);
        on_finished(index, *outcome);
        continue;
      }
      if (stopping) {
        child.Stop(SIGINT, options.kill_grace_seconds, false);
      } else if (options.timeout_seconds > 0 && child.seconds() > options.timeout_seconds) {
        child.Stop(SIGTERM, options.kill_grace_seconds, true);
      }
      ++it;
    }
    if (stopping && running.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return next;
}

}  // namespace hoidslam::bench
