// `hoidslam bench`: filter modes × sequences × runs in one command, with the tables in the shape of the paper's
// (docs/bench.md). Also writes the runs as job lists (--plan) for GNU parallel or Slurm, and builds the tables
// from finished run folders (--collect).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "hoidslam/bench/bench.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/shipped_dir.h"
#include "hoidslam/core/interrupt.h"
#include "hoidslam/report/table.h"

namespace hoidslam::apps {
namespace {

namespace fs = std::filesystem;

// The seven synthetic scenarios of the benchmark (the `_static` controls are left to ask for by name).
const std::vector<std::string> kDefaultScenarios = {
    "walking_xyz", "walking_static", "walking_halfsphere", "walking_rpy", "sitting_static", "carry", "crowd"};

struct BenchArgs {
  std::vector<std::string> folders;
  std::vector<std::string> scenarios;
  std::size_t random = 0;
  std::uint64_t seed = 1;
  std::vector<std::string> modes;
  std::string area_sweep = "0.2,0.3,0.4,0.5";
  std::string depth_sweep = "0.1,0.2,0.3,0.5";
  bench::BenchOptions options;
  std::string settings;
  std::string sequences_dir;
  std::string out;
  std::size_t jobs = std::max(1U, std::thread::hardware_concurrency());
  bool resume = false;
  bool force = false;
  bool plan = false;
  bool collect = false;
};

// "0.2,0.3" → {0.2, 0.3}; "none" or "" → {}.
std::vector<double> ParseSweep(const std::string& text, const std::string& parameter) {
  std::vector<double> values;
  if (text.empty() || text == "none") return values;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, end - start);
    try {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::logic_error&) {
      throw core::InputError::ForParameter(parameter, fmt::format("'{}' is not a number (a list like 0.2,0.3 or none)", item));
    }
    start = end + 1;
  }
  return values;
}

fs::path SelfPath() { return fs::canonical("/proc/self/exe"); }

// The ATE table, the distribution over the random sequences when there were any, and the closing line naming what
// was written (report.html only when it was).
void PrintOutcome(const bench::BenchOutcome& outcome, bool report_written) {
  fmt::print("{}\n", bench::FindTable(outcome.tables, "ate")->ToMarkdown());
  if (const report::Table* random = bench::FindTable(outcome.tables, "random")) {
    fmt::print("{}\n", random->ToMarkdown());
  }
  fmt::print("wrote {}/ (tables.md, tables/*.csv, results.json, {}runs/)\n", outcome.plan.folder.string(),
             report_written ? "report.html, " : "");
}

void RunBenchCommand(const BenchArgs& args) {
  if (args.collect) {
    const bench::BenchOutcome outcome = bench::CollectBench(args.out);
    PrintOutcome(outcome, bench::WriteBenchOutputs(outcome));
    return;
  }
  bench::BenchRequest request;
  request.options = args.options;
  if (!args.modes.empty()) request.options.modes = args.modes;
  request.options.area_sweep = ParseSweep(args.area_sweep, "--area-sweep");
  request.options.depth_sweep = ParseSweep(args.depth_sweep, "--depth-sweep");
  request.scenarios = args.scenarios;
  if (request.scenarios.empty() && args.folders.empty() && args.random == 0) request.scenarios = kDefaultScenarios;
  if (request.scenarios == std::vector<std::string>{"none"}) request.scenarios.clear();
  request.random = args.random;
  request.random_seed = args.seed;
  const fs::path shared = bench::SharedDataDir();
  // Random scenes are dressed in the shared photographs when there are any, as users' rooms would be.
  if (args.random > 0 && fs::is_directory(shared / "data" / "textures")) {
    request.options.textures = shared / "data" / "textures";
  }
  for (const std::string& folder : args.folders) {
    request.folders.push_back(bench::ResolveSequenceFolder(folder, shared));
  }
  request.settings = args.settings;
  request.config_dir = core::ShippedDir() / "config";
  request.sequences_dir = args.sequences_dir;
  request.folder = fs::absolute(args.out);
  request.binary = SelfPath();
  request.jobs = std::max<std::size_t>(1, args.jobs);
  request.resume = args.resume;
  request.force = args.force;

  if (args.plan) {
    const bench::Plan plan = bench::WriteBenchPlan(request);
    fmt::print("planned {} runs over {} sequences in {}/:\n", plan.runs.size(), plan.sequences.size(),
               plan.folder.string());
    fmt::print("  parallel < {0}/prepare.txt && parallel < {0}/jobs.txt && {1} bench --collect --out {0}\n",
               plan.folder.string(), request.binary.string());
    return;
  }
  core::InterruptGuard interrupts;
  const bench::BenchOutcome outcome = bench::RunBench(request, [&interrupts] { return interrupts.requested(); });
  PrintOutcome(outcome, bench::WriteBenchOutputs(outcome));
  if (outcome.interrupted) {
    spdlog::warn("interrupted: the tables hold the runs finished so far; --resume runs the rest");
    std::fflush(stdout);
    interrupts.Reraise();
  }
}

}  // namespace

void AddBenchCommand(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Filter modes × sequences × runs as parallel processes, with tables like the paper's: ATE per mode, 2D vs 3D, "
      "the interaction-area and depth-threshold sweeps, RPE, frames lost, robustness (frames tracked, false "
      "relocalisations, loops and merges, loop recall), time per stage, exclusion quality and, with --dense, the dense "
      "map's quality (docs/bench.md)");
  command->add_option("sequences", args->folders,
                      "TUM / Bonn sequence folders to run besides (or instead of) the synthetic scenarios, or names "
                      "of the shared real recordings (fr1_rpy: $HOIDSLAM_SHARED_DIR/data/tum/fr1_rpy)");
  command->add_option("--scenarios", args->scenarios,
                      fmt::format("Shipped synthetic scenarios to render and run (default without folders: {}; none: "
                                  "no scenario)",
                                  fmt::join(kDefaultScenarios, ", ")))
      ->delimiter(',');
  CLI::Option* random =
      command->add_option("--random", args->random,
                          "Also render N random sequences (hoidslam synth --random) random-<seed> and run them like "
                          "the scenarios; the tables end with their distribution")
          ->capture_default_str();
  command->add_option("--seed", args->seed, "The first random sequence's seed; the others follow it")
      ->capture_default_str()
      ->needs(random);
  command->add_option("--random-duration", args->options.random_duration,
                      "Seconds of camera time of each random sequence (0 = synth's own)")
      ->capture_default_str()
      ->needs(random);
  command->add_option("--modes", args->modes,
                      "Filter modes (default: none,person,classes,hoid2d,hoid3d,oracle; also hoidplus and its parts alone, e.g. "
                      "hoidplus:depth; oracle only where masks exist)")
      ->delimiter(',');
  command->add_option("--runs", args->options.runs, "Runs per mode and sequence; the tables show the median")
      ->capture_default_str();
  command->add_option("--sweep-runs", args->options.sweep_runs,
                      "Runs per swept value and sequence (default: as many as --runs)");
  command->add_option("--area-sweep", args->area_sweep,
                      "hoid2d runs at these minimum interaction areas (the paper's Table 2); none to skip")
      ->capture_default_str();
  command->add_option("--depth-sweep", args->depth_sweep, "hoid3d runs at these depth thresholds (m); none to skip")
      ->capture_default_str();
  command->add_option("--jobs,-j", args->jobs, "Runs at once (default: the number of cores)")->capture_default_str();
  command->add_option("--frames", args->options.frames, "Run only the first N frames of each sequence (0 = all)")
      ->capture_default_str();
  command->add_option("--synth-frames", args->options.synth_frames,
                      "Render only the first N frames of each scenario (0 = all)")
      ->capture_default_str();
  command->add_option("--synth-frame-step", args->options.synth_frame_step,
                      "Render every n-th frame of each scenario's camera path")
      ->capture_default_str();
  command->add_flag("--deterministic", args->options.deterministic,
                    "Runs with local mapping in step with tracking: the same numbers on every run and machine");
  command->add_flag("--realtime", args->options.realtime,
                    "Runs in the real-time mode: the detector in its own thread (docs/realtime.md)");
  command->add_flag("--pace", args->options.pace, "Runs paced at the recorded rate, as from a live camera");
  command->add_option("--detector-latency", args->options.detector_latency_ms,
                      "Runs with every detection taking at least this many ms (a simulated latency)")
      ->check(CLI::Range(0.0, 60000.0));
  command->add_flag("--dense", args->options.dense,
                    "Runs with a dense map of the static world (run --dense, docs/dense.md); the tables add its ghost "
                    "surface, accuracy and completeness against a synthetic sequence's geometry, and its cost");
  command->add_option("--model", args->options.model,
                      "ONNX detector for sequence folders without a detections.jsonl");
  command->add_option("--settings", args->settings,
                      "Settings for the sequence folders (default: config/TUM1/2/3.yaml or Bonn.yaml by folder name)");
  command->add_option("--snapshots", args->options.snapshots,
                      "Annotated frames kept from the first run of each mode and sequence")
      ->capture_default_str();
  command->add_option("--timeout", args->options.timeout_seconds,
                      "Seconds after which a run is stopped and recorded as failed (0 = no limit)")
      ->capture_default_str();
  command->add_option("--sequences-dir", args->sequences_dir,
                      "Where scenarios are rendered, so several benches can share them (default: <out>/sequences)");
  command->add_option("--out", args->out, "Bench folder")->required();
  command->add_flag("--resume", args->resume, "Continue a bench in --out: finished runs are kept, the rest run");
  command->add_flag("--force", args->force, "Start over in a non-empty --out (rendered sequences are kept)");
  command->add_flag("--plan", args->plan,
                    "Only write plan.json, prepare.txt and jobs.txt (one shell command per line) for GNU parallel or "
                    "a Slurm array; then --collect");
  command->add_flag("--collect", args->collect, "Only build the tables from the run folders of a planned bench in --out");
  command->callback([args] { RunBenchCommand(*args); });
}

}  // namespace hoidslam::apps
