#include "hoidslam/bench/process_pool.h"

#include <signal.h>

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "hoidslam/core/stopwatch.h"
#include "support/temp_dir.h"

namespace hoidslam::bench {
namespace {

Job Shell(const std::string& script, const std::filesystem::path& log) { return {{"/bin/sh", "-c", script}, log}; }

std::string Read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(RunJobs, ReportsEveryOutcomeAndWritesEachLog) {
  testing::TempDir dir;
  const std::vector<Job> jobs = {Shell("echo one; exit 0", dir / "a.log"), Shell("echo two >&2; exit 3", dir / "b.log"),
                                 Shell("kill -SEGV $$", dir / "c.log")};
  std::vector<JobOutcome> outcomes(jobs.size());
  const std::size_t started =
      RunJobs(jobs, {.parallel = 2}, [&](std::size_t i, const JobOutcome& outcome) { outcomes[i] = outcome; });
  EXPECT_EQ(started, 3U);
  EXPECT_TRUE(outcomes[0].Succeeded());
  EXPECT_EQ(outcomes[1].exit_code, 3);
  EXPECT_EQ(outcomes[1].Describe(), "exit status 3");
  EXPECT_EQ(outcomes[2].signal, SIGSEGV);
  EXPECT_FALSE(outcomes[2].Succeeded());
  EXPECT_EQ(Read(dir / "a.log"), "one\n");
  EXPECT_EQ(Read(dir / "b.log"), "two\n");
}

TEST(RunJobs, NeverRunsMoreThanAskedAtOnce) {
  testing::TempDir dir;
  // Each job appends "start"/"end" around a short sleep; with one at a time they never interleave.
  std::vector<Job> jobs;
  for (int i = 0; i < 3; ++i) {
    jobs.push_back(Shell("echo start >> " + (dir / "trace").string() + "; sleep 0.2; echo end >> " +
                             (dir / "trace").string(),
                         dir / "log"));
  }
  RunJobs(jobs, {.parallel = 1}, [](std::size_t, const JobOutcome&) {});
  EXPECT_EQ(Read(dir / "trace"), "start\nend\nstart\nend\nstart\nend\n");
}

TEST(RunJobs, StopsAJobPastItsTimeLimit) {
  testing::TempDir dir;
  JobOutcome outcome;
  const core::Stopwatch clock;
  RunJobs({Shell("sleep 30", dir / "log")}, {.parallel = 1, .timeout_seconds = 0.3, .kill_grace_seconds = 1.0},
          [&](std::size_t, const JobOutcome& o) { outcome = o; });
  EXPECT_LT(clock.ElapsedSeconds(), 10.0);
  EXPECT_TRUE(outcome.timed_out);
  EXPECT_FALSE(outcome.Succeeded());
  EXPECT_NE(outcome.Describe().find("timed out"), std::string::npos);
}

TEST(RunJobs, AStopRequestInterruptsTheRunningJobsAndStartsNoMore) {
  testing::TempDir dir;
  std::vector<Job> jobs(4, Shell("trap 'echo interrupted; exit 130' INT; sleep 30 & wait", dir / "log"));
  std::size_t finished = 0;
  const core::Stopwatch clock;
  const std::size_t started = RunJobs(
      jobs, {.parallel = 2, .kill_grace_seconds = 5.0}, [&](std::size_t, const JobOutcome&) { ++finished; },
      [&clock] { return clock.ElapsedSeconds() > 0.5; });
  EXPECT_EQ(started, 2U);
  EXPECT_EQ(finished, 2U);
  EXPECT_LT(clock.ElapsedSeconds(), 10.0);
  EXPECT_NE(Read(dir / "log").find("interrupted"), std::string::npos);  // they got SIGINT, not SIGKILL
}

TEST(RunJobs, AProgramThatCannotStartIsAnError) {
  testing::TempDir dir;
  EXPECT_THROW(RunJobs({{{"/no/such/program"}, dir / "log"}}, {}, [](std::size_t, const JobOutcome&) {}), core::Error);
}

}  // namespace
}  // namespace hoidslam::bench
