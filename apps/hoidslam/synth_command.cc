// `hoidslam synth`: renders a synthetic dynamic-scene RGB-D sequence with exact ground truth
// (docs/synthetic-benchmark.md).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/interrupt.h"
#include "hoidslam/synth/preview.h"
#include "hoidslam/synth/random_scenario.h"
#include "hoidslam/synth/scenario.h"
#include "hoidslam/synth/sequence_writer.h"

namespace hoidslam::apps {
namespace {

struct SynthArgs {
  std::string scenario;
  std::optional<std::uint64_t> random;  // --random SEED: a random scenario instead of --scenario
  synth::RandomScenarioOptions random_options;
  std::string print_scenario;
  CLI::Option* print_option = nullptr;  // given with a name, or bare with --random
  bool list_scenarios = false;
  std::string data_dir;
  std::optional<std::uint64_t> seed;
  std::optional<std::size_t> frames;
  std::optional<double> miss_rate, box_jitter, false_positive_rate, class_confusion;
  std::string preview;  // PNG to draw the preview into; empty = none
  synth::PreviewOptions preview_options;
  synth::SynthOptions options;
};

// Where the real TUM camera paths are: --data-dir, else $HOIDSLAM_SHARED_DIR/data/tum, else the shared folder
// configured at build time.
std::filesystem::path TumDataDir(const std::string& data_dir) {
  if (!data_dir.empty()) return data_dir;
  if (const char* shared = std::getenv("HOIDSLAM_SHARED_DIR"); shared != nullptr && *shared != '\0') {
    return std::filesystem::path(shared) / "data" / "tum";
  }
  return std::filesystem::path(HOIDSLAM_SHARED_DIR_DEFAULT) / "data" / "tum";
}

void RunSynth(SynthArgs& args) {
  if (args.list_scenarios) {
    for (const std::string& name : synth::BuiltinScenarioNames()) fmt::print("{}\n", name);
    return;
  }
  if (args.print_option->count() > 0) {
    if (args.random) {
      if (!args.print_scenario.empty()) {
        throw core::InputError::ForParameter("--print-scenario",
                                             "give a shipped scenario's name or --random, not both");
      }
      fmt::print("{}\n", synth::RandomScenarioDocument(*args.random, args.random_options).dump(2));
      return;
    }
    const auto text = synth::BuiltinScenarioText(args.print_scenario);
    if (!text) {
      throw core::InputError::ForParameter(
          "--print-scenario",
          args.print_scenario.empty()
              ? std::string("name a shipped scenario (see --list-scenarios), or give --random SEED")
              : fmt::format("no shipped scenario '{}' (see --list-scenarios)", args.print_scenario));
    }
    fmt::print("{}", *text);
    return;
  }
  if (args.options.out.empty()) throw core::InputError::ForParameter("--out", "required");
  if (args.scenario.empty() && !args.random) {
    if (args.preview.empty()) {
      throw core::InputError::ForParameter("--scenario", "required (see --list-scenarios), or --random SEED");
    }
    // Only a preview of the sequence already in --out.
    synth::WritePreviewPng(args.preview, synth::SequencePreview(args.options.out, args.preview_options));
    return;
  }

  synth::Scenario scenario = args.random ? synth::RandomScenario(*args.random, args.random_options)
                                         : synth::LoadScenario(args.scenario);
  if (args.seed) scenario.seed = *args.seed;
  if (args.frames) scenario.max_frames = *args.frames;
  synth::DetectorNoiseOptions& noise = scenario.detector_noise;
  if (args.miss_rate) noise.miss_rate = *args.miss_rate;
  if (args.box_jitter) noise.box_jitter = *args.box_jitter;
  if (args.false_positive_rate) noise.false_positive_rate = *args.false_positive_rate;
  if (args.class_confusion) noise.class_confusion_rate = *args.class_confusion;
  args.options.tum_dir = TumDataDir(args.data_dir);

  core::InterruptGuard interrupts;
  args.options.stop_requested = [&interrupts] { return interrupts.requested(); };
  synth::SynthResult result;
  try {
    result = synth::WriteSequence(scenario, args.options);
  } catch (const core::Interrupted&) {
    spdlog::warn("interrupted; {} was not written", args.options.out.string());
    interrupts.Reraise();
  }
  fmt::print("{}: {} frames of '{}' in {:.1f} s ({:.1f} ms a frame, {} threads)\n", args.options.out.string(),
             result.frames, scenario.name, result.seconds, 1e3 * result.seconds / static_cast<double>(result.frames),
             args.options.threads);
  if (!args.preview.empty()) {
    synth::WritePreviewPng(args.preview, synth::SequencePreview(args.options.out, args.preview_options));
  }
}

}  // namespace

void AddSynthCommand(CLI::App& app) {
  auto args = std::make_shared<SynthArgs>();
  synth::SynthOptions& options = args->options;
  CLI::App* command = app.add_subcommand(
      "synth",
      "Render a synthetic RGB-D sequence of people moving things in an office, in TUM layout, with ground-truth "
      "camera poses, detections, moving-pixel masks and an event log (docs/synthetic-benchmark.md)");
  command->add_option("--scenario", args->scenario,
                      fmt::format("A shipped scenario ({}) or a .json file",
                                  fmt::join(synth::BuiltinScenarioNames(), ", ")));
  CLI::Option* random =
      command->add_option("--random", args->random,
                          "Render the random scenario of this seed instead of --scenario: a random office, camera path "
                          "and people, the same for the same seed (named random-<seed>)")
          ->check(CLI::NonNegativeNumber);
  command->get_option("--scenario")->excludes(random);
  command
      ->add_option("--random-duration", args->random_options.duration,
                   "Seconds of camera path of a --random scenario")
      ->capture_default_str()
      ->needs(random);
  command->add_option("--out", options.out, "Output sequence folder (created complete or not at all)");
  command->add_option("--seed", args->seed, "Override the scenario's seed (sensor and detector noise)");
  command->add_option("--frames", args->frames, "Render only the first N frames (0 = all)");
  command->add_option("--textures", options.textures_dir,
                      "Folder of photos for walls, desks and posters (default: procedural textures)");
  command->add_option("--data-dir", args->data_dir,
                      "Folder with the TUM camera paths (groundtruth/, associations/); default "
                      "$HOIDSLAM_SHARED_DIR/data/tum or the shared folder beside the checkout");
  command->add_option("--miss-rate", args->miss_rate, "Detector noise: chance that a true box is dropped")
      ->check(CLI::Range(0.0, 1.0));
  command->add_option("--box-jitter", args->box_jitter, "Detector noise: std of box edge shifts, fraction of size")
      ->check(CLI::Range(0.0, 1.0));
  command
      ->add_option("--false-positive-rate", args->false_positive_rate,
                   "Detector noise: mean number of invented boxes per frame")
      ->check(CLI::Range(0.0, 100.0));
  command
      ->add_option("--class-confusion", args->class_confusion,
                   "Detector noise: chance that a true box gets another class's label")
      ->check(CLI::Range(0.0, 1.0));
  command->add_option("--threads", options.threads, "Frames rendered in parallel")->capture_default_str();
  command
      ->add_option("--frame-step", options.frame_step,
                   "Keep only every n-th frame of the camera path (a quick look at a long scenario)")
      ->capture_default_str();
  command->add_flag("--force", options.force, "Replace the output folder when it exists and is not empty");
  command->add_flag("--list-scenarios", args->list_scenarios, "List the shipped scenarios and exit");
  args->print_option = command
                           ->add_option("--print-scenario", args->print_scenario,
                                        "Print a shipped scenario's JSON (to copy and edit); with --random and no "
                                        "name, the random scenario's")
                           ->expected(0, 1);
  command->add_option("--preview", args->preview,
                      "Also draw a PNG of a few frames (colour, depth, boxes, moving mask); without --scenario or "
                      "--random, draw it for the sequence already in --out");
  command
      ->add_option("--preview-frames", args->preview_options.frames,
                   "Frame indices for --preview (default: 3 spread over the sequence)")
      ->delimiter(',');
  command->add_option("--preview-scale", args->preview_options.scale, "Image scale in --preview")
      ->capture_default_str();
  options.progress = true;
  command->callback([args] { RunSynth(*args); });
}

}  // namespace hoidslam::apps
