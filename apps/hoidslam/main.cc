// hoidslam: RGB-D SLAM that drops the features of people and of the objects they handle.
#include <exception>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <opencv2/core/utility.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "command_line.h"
#include "commands.h"
#include "hoidslam/core/error.h"
#include "hoidslam/version.h"

namespace {

// Counts (frames, runs, seeds, jobs, ...) are unsigned: "-5" is refused with the option named, where the parser
// alone would take it round to a huge count.
void RefuseNegativeCounts(CLI::App& app) {
  for (CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    for (CLI::Option* option : command->get_options()) {
      if (option->get_type_name().rfind("UINT", 0) != 0) continue;
      option->check(CLI::Validator(
          [](const std::string& value) {
            return value.find('-') == std::string::npos ? std::string() : "must be 0 or more, got " + value;
          },
          "", "non-negative"));
    }
  }
}

// The command named on the command line when it is none of hoidslam's (global flags come first, and none of them
// takes a value), else empty.
std::string UnknownCommand(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with('-')) continue;
    for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (command->check_name(std::string(arg))) return {};
    }
    return std::string(arg);
  }
  return {};
}

std::vector<std::string> CommandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    names.push_back(command->get_name());
  }
  return names;
}

}  // namespace

// Exit status: 0 done (and --help, --version), 1 bad input (the command line included), 2 internal error, 128 + the
// signal's number when interrupted (130 for Ctrl-C); README, "Bad input".
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
  hoidslam::apps::AddPlotCommand(app);
  hoidslam::apps::AddReportCommand(app);
  hoidslam::apps::AddRunCommand(app);
  hoidslam::apps::AddSynthCommand(app);
  hoidslam::apps::AddVocabularyCommand(app);

  RefuseNegativeCounts(app);
  hoidslam::apps::RememberCommandLine(argc, argv);

  try {
    if (const std::string unknown = UnknownCommand(app, argc, argv); !unknown.empty()) {
      spdlog::error("unknown command '{}' (commands: {}; see hoidslam --help)", unknown,
                    fmt::join(CommandNames(app), ", "));
      return 1;
    }
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    const std::vector<CLI::App*> parsed = app.get_subcommands();
    spdlog::error("{} (see hoidslam{} --help)", e.what(), parsed.empty() ? "" : " " + parsed.front()->get_name());
    return 1;
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
