#pragma once
// What a bench runs: filter modes (and sweeps of the HOID parameters) × sequences × repeated runs, each run one
// self-contained `hoidslam run` command writing its own folder. The same plan is executed by `hoidslam bench`
// itself, or written as job lists for GNU parallel or a Slurm array and collected afterwards (docs/bench.md).
//
// Bench folder layout:
//   plan.json            this plan (what --collect reads)
//   prepare.txt          commands that render the synthetic sequences (one per line)
//   jobs.txt             the runs, one command per line, each writing runs/<id>/ and runs/<id>.log
//   sequences/<name>/    rendered synthetic sequences (unless --sequences-dir points elsewhere)
//   runs/<id>/           one `hoidslam run` output folder per run
//   results.json, tables.md, tables/*.csv, report.html

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace hoidslam::bench {

// A sequence of the bench: a shipped synthetic scenario or a random one rendered on demand, or a TUM / Bonn folder.
struct BenchSequence {
  std::string name;                 // its row in the tables
  std::filesystem::path path;       // the sequence folder (for a scenario: where it is rendered)
  std::string scenario;             // non-empty: rendered with `hoidslam synth --scenario <scenario>`
  std::optional<std::uint64_t> random_seed;  // set: rendered with `hoidslam synth --random <seed>`
  std::filesystem::path settings;   // `run --settings`; empty: run's default (TUM fr3)
  std::string problem;              // why it cannot be run (missing, broken); it then has no runs
  bool has_masks = false;           // ground-truth moving masks (mask/): oracle and exclusion quality
  double min_interaction_area = 0;  // the HOID values its settings give, so sweeps reuse the plain runs
  double depth_threshold = 0;

  // Rendered by the bench (a scenario or a random sequence), not a folder the user gave.
  bool Rendered() const { return !scenario.empty() || random_seed.has_value(); }
};

struct BenchOptions {
  std::vector<std::string> modes = {"none", "person", "classes", "hoid2d", "hoid3d", "oracle"};
  std::size_t runs = 5;                                // per mode and sequence; tables show the median
  std::size_t sweep_runs = 0;                          // per swept value and sequence; 0: as many as `runs`
  std::vector<double> area_sweep = {0.2, 0.3, 0.4, 0.5};  // hoid2d at these HOID.minInteractionArea (Table 2)
  std::vector<double> depth_sweep = {0.1, 0.2, 0.3, 0.5};  // hoid3d at these HOID.depthThreshold (m)
  std::size_t frames = 0;         // `run --frames`: only the first N frames (0 = all)
  std::size_t synth_frames = 0;   // `synth --frames` for rendered scenarios (0 = all)
  int synth_frame_step = 1;       // `synth --frame-step`
  double random_duration = 0;     // `synth --random-duration` (seconds) for random sequences (0 = synth's own)
  std::filesystem::path textures;  // `synth --textures` for random sequences (empty = synth's procedural ones)
  bool deterministic = false;     // `run --deterministic`: identical output on every run
  bool realtime = false;          // `run --realtime`: the detector in its own thread
  bool pace = false;              // `run --pace`: frames at their recorded rate, as from a live camera
  double detector_latency_ms = 0;  // `run --detector-latency`: a simulated detector latency
  bool dense = false;             // `run --dense`: every run also maps the static world densely (the dense tables)
  std::filesystem::path model;    // ONNX model for sequences without a detections.jsonl
  std::size_t snapshots = 6;      // annotated frames in the first run of each mode and sequence
  double timeout_seconds = 3600;  // a run taking longer is stopped and recorded as failed (0 = no limit)

  std::size_t SweepRuns() const { return sweep_runs == 0 ? runs : sweep_runs; }
  // Throws InputError naming the command-line parameter of a bad value.
  void Check() const;
};

// One column of the tables: a filter mode, possibly with a swept HOID parameter.
struct Variant {
  std::string mode;
  std::optional<double> min_interaction_area;
  std::optional<double> depth_threshold;

  static Variant Plain(std::string mode) { return {std::move(mode), std::nullopt, std::nullopt}; }

  // "hoid2d", "hoid2d area=0.3", "hoid3d depth=0.1"
  std::string Name() const;
  // For folder names: "hoid2d", "hoid2d-area0.3"
  std::string Slug() const;
  bool operator==(const Variant&) const = default;
};

struct RunSpec {
  std::string id;              // "<sequence>.<variant slug>.r<run>": its folder under runs/
  std::size_t sequence = 0;    // index into Plan::sequences
  std::size_t variant = 0;     // index into Plan::variants
  std::size_t run = 1;         // 1 .. runs
};

struct Plan {
  BenchOptions options;
  std::filesystem::path binary;  // the hoidslam executable every command calls (absolute)
  std::filesystem::path folder;  // the bench folder (absolute)
  std::vector<BenchSequence> sequences;
  std::vector<Variant> variants;
  std::vector<RunSpec> runs;

  std::filesystem::path RunFolder(const RunSpec& spec) const { return folder / "runs" / spec.id; }
  std::filesystem::path RunLog(const RunSpec& spec) const { return folder / "runs" / (spec.id + ".log"); }
  // The `hoidslam run` command of one run, as arguments.
  std::vector<std::string> RunCommand(const RunSpec& spec) const;
  // The `hoidslam synth` command that renders a scenario or random sequence (empty for a folder the user gave).
  std::vector<std::string> PrepareCommand(const BenchSequence& sequence) const;
  // The variant a sweep value is measured by: the plain mode's runs when the value is what the sequence's
  // settings give anyway, else the swept variant. nullopt when the plan has neither.
  std::optional<std::size_t> SweepVariant(const std::string& mode, double value, bool is_area,
                                          const BenchSequence& sequence) const;
};

// The variants and runs for `options` over `sequences`: every mode (oracle only where masks exist), the sweeps
// (values equal to a sequence's own setting reuse the plain runs), `options.runs` runs each. Sequences with a
// problem get no runs.
Plan MakePlan(const BenchOptions& options, std::vector<BenchSequence> sequences, const std::filesystem::path& binary,
              const std::filesystem::path& folder);

// A sequence folder checked for the bench: the settings file, and a problem text instead of an exception when
// the folder is missing or broken (the bench goes on with the others).
BenchSequence InspectSequence(std::string name, const std::filesystem::path& path, const std::filesystem::path& settings);

nlohmann::json PlanToJson(const Plan& plan);
// Throws InputError naming `file` when the JSON is not a plan.
Plan PlanFromJson(const nlohmann::json& json, const std::filesystem::path& file);

// One shell command line: every argument quoted where the shell would split or expand it.
std::string ShellCommand(const std::vector<std::string>& arguments);

}  // namespace hoidslam::bench
