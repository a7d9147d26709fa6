// hoidslam: RGB-D SLAM that drops the features of people and of the objects they handle.
#include <exception>

#include <CLI/CLI.hpp>
#include <opencv2/core/utility.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "hoidslam/core/error.h"
#include "hoidslam/version.h"

int main(int argc, char** argv) {
  // Logs and errors go to stderr, results to stdout. "error: <file>:<line>: <what>": one plain line a user can
  // act on; no timestamps in an interactive tool.
  spdlog::set_default_logger(spdlog::stderr_color_mt("hoidslam"));
  spdlog::set_pattern("%^%l%$: %v");
  CLI::App app{"hoidslam: RGB-D SLAM in scenes where people walk and move things (HOID method)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "hoidslam " HOIDSLAM_VERSION);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "Log debugging details");
  app.parse_complete_callback([&verbose] {
    spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
  });

  hoidslam::apps::AddBenchCommand(app);
  hoidslam::apps::AddDemoCommand(app);
  hoidslam::apps::AddDetectCommand(app);
  hoidslam::apps::AddEvalCommand(app);
  hoidslam::apps::AddMasksCommand(app);
  hoidslam::apps::AddReportCommand(app);
  hoidslam::apps::AddRunCommand(app);
  hoidslam::apps::AddSynthCommand(app);
  hoidslam::apps::AddVocabularyCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const hoidslam::core::InputError& e) {
    spdlog::error("{}", e.what());
    return 1;
  } catch (const cv::Exception& e) {
    spdlog::error("OpenCV: {}", e.what());
    return 1;
  } catch (const std::exception& e) {
    spdlog::error("internal error: {}", e.what());
    return 2;
  }
  return 0;
}
