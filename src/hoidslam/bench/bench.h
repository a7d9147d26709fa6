#pragma once
// `hoidslam bench` from start to end: render the synthetic scenarios asked for, check the sequence folders
// given, plan the runs, run them as parallel child processes (or write them as job lists), and build the tables
// and results from the run folders. docs/bench.md describes the folder and the tables.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "hoidslam/bench/plan.h"
#include "hoidslam/bench/results.h"
#include "hoidslam/bench/tables.h"

namespace hoidslam::bench {

struct BenchRequest {
  BenchOptions options;
  std::vector<std::string> scenarios;          // shipped synthetic scenarios, rendered on demand
  std::size_t random = 0;                      // random sequences random-<seed>, rendered on demand ...
  std::uint64_t random_seed = 1;               // ... with the seeds random_seed, random_seed + 1, ...
  std::vector<std::filesystem::path> folders;  // TUM / Bonn sequence folders
  std::filesystem::path settings;     // settings for the folders; empty: picked by folder name from config_dir
  std::filesystem::path config_dir;   // the shipped settings files (TUM1/2/3.yaml, Bonn.yaml)
  std::filesystem::path sequences_dir;  // where scenarios are rendered; empty: <folder>/sequences
  std::filesystem::path folder;       // the bench folder
  std::filesystem::path binary;       // the hoidslam executable
  std::size_t jobs = 1;               // processes at once
  bool resume = false;                // keep finished runs and rendered sequences, run the rest
  bool force = false;                 // start over in a non-empty folder (rendered sequences are kept)
};

// The shared data folder (real recordings, textures, models): $HOIDSLAM_SHARED_DIR when set, else the folder
// configured at build time (`shared` beside the checkout). Not checked for existence.
std::filesystem::path SharedDataDir();

// A sequence as the command line names it: a folder that exists, else the recording of that name among the shared
// real ones (`fr1_rpy`: <shared_dir>/data/tum/fr1_rpy), else as given (the bench then reports it missing).
std::filesystem::path ResolveSequenceFolder(const std::string& argument, const std::filesystem::path& shared_dir);

struct BenchOutcome {
  Plan plan;
  std::vector<RunResult> results;
  std::vector<NamedTable> tables;
  bool interrupted = false;
};

// Runs the whole bench. `stop_requested` is polled: the runs under way finish their outputs as on Ctrl-C, no new
// one starts, and the tables of the finished runs are written. Throws InputError for bad options or a folder
// that is in use without --resume / --force.
BenchOutcome RunBench(const BenchRequest& request, const std::function<bool()>& stop_requested);

// Writes plan.json, prepare.txt and jobs.txt (one self-contained shell command per line) without running
// anything, for GNU parallel or a Slurm array. Returns the plan.
Plan WriteBenchPlan(const BenchRequest& request);

// Reads <folder>/plan.json and the run folders, and writes the tables and results (CollectBench after jobs.txt
// ran elsewhere). Throws InputError naming plan.json when it is missing or broken.
BenchOutcome CollectBench(const std::filesystem::path& folder);

// results.json, tables.md, tables/<name>.csv and report.html in the plan's folder, each complete or absent.
// Returns whether report.html was written: a page that cannot be made (a run folder it reads is broken) is a
// warning saying why, and the page of an earlier collect is removed, since it would show other results.
[[nodiscard]] bool WriteBenchOutputs(const BenchOutcome& outcome);

// The bench as one self-contained HTML page: ATE per mode and sequence as a chart and every table, and for each
// sequence the trajectories of `none`, `hoid2d` and `oracle` (each mode's median run) over the ground truth.
std::string RenderBenchReport(const BenchOutcome& outcome);

}  // namespace hoidslam::bench
