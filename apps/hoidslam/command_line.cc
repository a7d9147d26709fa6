#include "command_line.h"

#include <filesystem>
#include <string>
#include <vector>

namespace hoidslam::apps {
namespace {

struct CommandLine {
  std::vector<std::string> argv;
  std::string working_directory;
};

CommandLine& Remembered() {
  static CommandLine command_line;
  return command_line;
}

}  // namespace

void RememberCommandLine(int argc, char** argv) {
  CommandLine& remembered = Remembered();
  remembered.argv.assign(argv, argv + argc);
  std::error_code error;
  remembered.working_directory = std::filesystem::current_path(error).string();
}

nlohmann::json CommandLineJson() {
  const CommandLine& remembered = Remembered();
  return {{"argv", remembered.argv}, {"working_directory", remembered.working_directory}};
}

}  // namespace hoidslam::apps
