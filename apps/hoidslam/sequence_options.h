#pragma once
// The input sequence of a command: a TUM / Bonn folder, or two plain image folders played at a fixed rate.
// Shared by every command that reads a sequence, so they all accept the same options.

#include <filesystem>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "hoidslam/io/rgbd_sequence.h"

namespace hoidslam::apps {

struct SequenceArgs {
  std::string dataset;       // TUM-layout folder (positional)
  std::string rgb_folder;    // or: --rgb-folder and --depth-folder, sorted by name and paired in order
  std::string depth_folder;
  double fps = 30.0;         // frame rate of image folders
  std::string associations;  // optional associations file, relative to the dataset folder
  std::optional<double> depth_factor;  // --depth-factor; default: the settings file's, else 5000
};

// Adds the positional dataset and --rgb-folder, --depth-folder, --fps, --associations, --depth-factor.
void AddSequenceOptions(CLI::App& command, SequenceArgs& args);

// Opens what the options name. The depth factor is --depth-factor or `settings_depth_factor` (the DepthMapFactor
// of a settings file the user gave), not both, else `default_depth_factor`. Throws InputError for options that
// contradict each other (a dataset folder and image folders, --associations with image folders, both depth
// factors), and, as the readers do, for a missing or empty sequence.
io::RgbdSequence OpenSequence(const SequenceArgs& args, std::optional<double> settings_depth_factor,
                              double default_depth_factor = 5000.0);

// Where a command writes a per-sequence file by default: inside the dataset folder, or beside the image folders.
std::filesystem::path SequenceFolder(const SequenceArgs& args);

}  // namespace hoidslam::apps
