#include "cli_test_support.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <csignal>
#include <thread>

#include <algorithm>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "support/text_file.h"

extern char** environ;

namespace hoidslam::apps {

namespace fs = std::filesystem;

RunResult RunProgram(const testing::TempDir& scratch, const std::vector<std::string>& argv_strings,
                     std::optional<std::chrono::milliseconds> interrupt_after) {
  const fs::path out = scratch / "stdout.txt";
  const fs::path err = scratch / "stderr.txt";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> strings = argv_strings;
  std::vector<char*> argv;
  for (std::string& arg : strings) argv.push_back(arg.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  RunResult result;
  if (spawned != 0) return result;
  if (interrupt_after) {
    std::this_thread::sleep_for(*interrupt_after);
    kill(pid, SIGINT);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = testing::ReadText(out);
  result.err = testing::ReadText(err);
  return result;
}

RunResult RunHoidslam(const testing::TempDir& scratch, const std::vector<std::string>& args,
                      std::optional<std::chrono::milliseconds> interrupt_after) {
  std::vector<std::string> argv = {HOIDSLAM_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return RunProgram(scratch, argv, interrupt_after);
}

void ExpectOneErrorLine(const RunResult& result, const std::string& names) {
  EXPECT_EQ(result.exit_status, 1) << result.err;
  EXPECT_THAT(result.err, ::testing::StartsWith("error: "));
  EXPECT_THAT(result.err, ::testing::HasSubstr(names));
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
}

fs::path Render(const testing::TempDir& scratch, const std::string& scenario, Stretch stretch) {
  const fs::path sequence = scratch / scenario;
  const RunResult synth =
      RunHoidslam(scratch, {"synth", "--scenario", scenario, "--frames", std::to_string(stretch.frames * stretch.step),
                            "--frame-step", std::to_string(stretch.step), "--out", sequence.string()});
  EXPECT_EQ(synth.exit_status, 0) << synth.err;
  return sequence;
}

nlohmann::json Summary(const fs::path& out) { return nlohmann::json::parse(testing::ReadText(out / "summary.json")); }

RunResult RunPageTest(const testing::TempDir& scratch, const std::vector<std::string>& arguments) {
  std::vector<std::string> argv = {HOIDSLAM_NODE, HOIDSLAM_WEB_TEST_DRIVER, "--playwright", HOIDSLAM_PLAYWRIGHT_DIR,
                                   "--timeout", "600"};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return RunProgram(scratch, argv);
}

cv::Mat ChromiumScreenshot(const testing::TempDir& scratch, const fs::path& html, cv::Size window) {
  const std::string chromium = HOIDSLAM_CHROMIUM;
  if (chromium.empty()) {
    ADD_FAILURE() << "no chromium was found when the build was configured: install the Debian package chromium "
                     "(scripts/setup.sh does) and configure again";
    return {};
  }
  const fs::path png = scratch / "screenshot.png";
  fs::remove(png);  // a screenshot of an earlier page must not pass for this one's
  const RunResult browser = RunProgram(
      scratch,
      {"timeout", "--kill-after=10", "120", chromium, "--headless", "--no-sandbox", "--disable-gpu",
       "--disable-dev-shm-usage", "--disable-background-networking", "--no-first-run",
       "--user-data-dir=" + (scratch / "chromium").string(), "--hide-scrollbars",
       "--window-size=" + std::to_string(window.width) + "," + std::to_string(window.height),
       "--screenshot=" + png.string(),
       "file://" + html.string()});
  if (browser.exit_status != 0) {
    ADD_FAILURE() << chromium << " exited with status " << browser.exit_status << ": " << browser.err;
    return {};
  }
  cv::Mat shot = cv::imread(png.string(), cv::IMREAD_COLOR);
  if (shot.empty()) ADD_FAILURE() << png << ": no screenshot: " << browser.err;
  return shot;
}

}  // namespace hoidslam::apps
