// `hoidslam masks`: HOID's dynamic regions as one mask PNG per frame, for SLAM systems that take feature masks
// (stella_vslam, DynaSLAM-style mask folders) instead of hoidslam's tracker (docs/masks.md).
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "detector_options.h"
#include "sequence_options.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/interrupt.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/pipeline/dynamic_mask.h"

namespace hoidslam::apps {
namespace {

struct MasksArgs {
  SequenceArgs sequence;
  std::string settings;
  DetectorArgs detector;
  std::string filter;             // overrides HOID.mode
  std::string format = "hoidslam";
  int dilate = 0;
  std::string out;
  std::size_t frames = 0;
  bool force = false;
};

void RunMasks(const MasksArgs& args) {
  std::optional<io::Settings> settings;
  if (!args.settings.empty()) settings = io::LoadSettings(args.settings);
  pipeline::MaskExportOptions options;
  options.exclusion.hoid = settings.value_or(io::Settings{}).hoid;
  options.camera = settings.value_or(io::Settings{}).camera;
  if (!args.filter.empty()) pipeline::SetFilterMode(args.filter, options.exclusion, "--filter");
  options.format = pipeline::ParseMaskFormat(args.format, "--format");
  options.dilate = args.dilate;
  options.max_frames = args.frames;
  options.out = args.out;
  options.force = args.force;
  options.Check();

  const io::RgbdSequence sequence =
      OpenSequence(args.sequence, settings ? std::optional(settings->depth_map_factor) : std::nullopt);
  const std::unique_ptr<detect::Detector> detector =
      OpenDetector(args.detector, args.sequence, options.exclusion, sequence);

  core::InterruptGuard interrupts;
  options.stop_requested = [&interrupts] { return interrupts.requested(); };
  pipeline::MaskExportSummary summary;
  try {
    summary = pipeline::ExportMasks(sequence, *detector, options);
  } catch (const core::Interrupted&) {
    spdlog::warn("interrupted; {} was not written", args.out);
    interrupts.Reraise();
  }
  fmt::print("{}: {} masks ({}, format {}{}) in {}/; {:.1f} % of the pixels masked on average\n", sequence.name(),
             summary.frames, options.exclusion.ModeName(), pipeline::ToString(options.format),
             options.dilate > 0 ? fmt::format(", dilated {} px", options.dilate) : "", io::NormalFolder(args.out).string(),
             100.0 * summary.mean_masked_share);
}

}  // namespace

void AddMasksCommand(CLI::App& app) {
  auto args = std::make_shared<MasksArgs>();
  CLI::App* command = app.add_subcommand(
      "masks",
      "Write HOID's dynamic regions (the boxes of people and of the objects they handle) as one mask PNG per frame, "
      "plus masks.txt, for SLAM systems that take feature masks: stella_vslam, DynaSLAM (docs/masks.md)");
  AddSequenceOptions(*command, args->sequence);
  command->add_option("--settings", args->settings,
                      "Settings file: its HOID section and DepthMapFactor are used (e.g. config/TUM3.yaml)");
  AddDetectorOptions(*command, args->detector);
  command->add_option("--filter", args->filter,
                      "What is masked: person, classes, hoid2d, hoid3d, hoidplus, or oracle (the ground-truth moving "
                      "masks of a synthetic sequence); none masks nothing; default: HOID.mode of the settings, else "
                      "hoidplus");
  command->add_option("--format", args->format,
                      "Pixel values for the tool that reads the masks: hoidslam (255 dynamic, 0 static), stella "
                      "(0 dynamic, 255 static) or dynaslam (1 dynamic, 0 static)")
      ->capture_default_str();
  command->add_option("--dilate", args->dilate, "Grow every masked region by this many pixels on each side")
      ->capture_default_str();
  command->add_option("--out", args->out, "Output folder (created complete or not at all)")->required();
  command->add_option("--frames", args->frames, "Only the first N frames (0 = all)")->capture_default_str();
  command->add_flag("--force", args->force, "Replace the --out folder when it exists and is not empty");
  command->callback([args] { RunMasks(*args); });
}

}  // namespace hoidslam::apps
