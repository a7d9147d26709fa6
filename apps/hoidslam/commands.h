#pragma once
// Each subcommand of the hoidslam tool lives in its own <name>_command.cc and adds itself to the app here.
// A command's callback throws core::InputError for bad input; main() turns that into one message and exit 1.

#include <CLI/CLI.hpp>

namespace hoidslam::apps {

void AddBenchCommand(CLI::App& app);
void AddDemoCommand(CLI::App& app);
void AddDetectCommand(CLI::App& app);
void AddEvalCommand(CLI::App& app);
void AddMasksCommand(CLI::App& app);
void AddPlotCommand(CLI::App& app);
void AddReportCommand(CLI::App& app);
void AddRunCommand(CLI::App& app);
void AddSynthCommand(CLI::App& app);
void AddVocabularyCommand(CLI::App& app);

}  // namespace hoidslam::apps
