#include "hoidslam/bench/bench.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <fstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "hoidslam/bench/process_pool.h"
#include "hoidslam/core/error.h"
#include "hoidslam/core/options.h"
#include "hoidslam/core/progress.h"
#include "hoidslam/core/stopwatch.h"
#include "hoidslam/io/atomic_file.h"
#include "hoidslam/io/files.h"
#include "hoidslam/io/settings.h"
#include "hoidslam/report/html_report.h"

namespace hoidslam::bench {
namespace {

namespace fs = std::filesystem;

void WriteText(const fs::path& path, const std::string& text) {
  io::AtomicFile file(path);
  file.stream() << text;
  file.Commit();
}

// A bench folder is new, continued (--resume) or started over (--force, keeping rendered sequences).
void PrepareFolder(const BenchRequest& request) {
  const fs::path& folder = request.folder;
  if (fs::exists(folder) && !fs::is_directory(folder)) {
    throw core::InputError::ForParameter("--out", fmt::format("{} is a file, not a folder", folder.string()));
  }
  const bool used = fs::exists(folder) && !fs::is_empty(folder);
  if (used && !request.resume && !request.force) {
    throw core::InputError::ForParameter(
        "--out", fmt::format("{} holds an earlier bench: --resume continues it, --force starts over", folder.string()));
  }
  if (used && request.force && !request.resume) {
    for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
      if (entry.path().filename() != "sequences") fs::remove_all(entry.path());
    }
  }
  fs::create_directories(folder / "runs");
}

// Where a rendered sequence goes: its name, and what makes it differ from the full rendering.
std::string RenderedFolderName(const BenchSequence& sequence, const BenchOptions& options) {
  std::string name = sequence.name;
  if (sequence.random_seed && options.random_duration > 0) name += fmt::format("-d{}", options.random_duration);
  if (options.synth_frames > 0) name += fmt::format("-f{}", options.synth_frames);
  if (options.synth_frame_step > 1) name += fmt::format("-s{}", options.synth_frame_step);
  return name;
}

// The sequences as the request names them; scenarios are not rendered yet, so they are taken as they will be.
std::vector<BenchSequence> RequestedSequences(const BenchRequest& request) {
  const fs::path sequences_dir =
      fs::absolute(request.sequences_dir.empty() ? request.folder / "sequences" : request.sequences_dir);
  std::vector<BenchSequence> sequences;
  const core::HoidOptions defaults;  // scenarios, shipped and random, run with run's default settings (TUM fr3)
  const auto add_rendered = [&](std::string name, std::string scenario, std::optional<std::uint64_t> seed) {
    BenchSequence& sequence = sequences.emplace_back();
    sequence.name = std::move(name);
    sequence.scenario = std::move(scenario);
    sequence.random_seed = seed;
    sequence.path = sequences_dir / RenderedFolderName(sequence, request.options);
    sequence.has_masks = true;
    sequence.min_interaction_area = defaults.min_interaction_area;
    sequence.depth_threshold = defaults.depth_threshold;
  };
  for (const std::string& scenario : request.scenarios) add_rendered(scenario, scenario, std::nullopt);
  for (std::size_t k = 0; k < request.random; ++k) {
    const std::uint64_t seed = request.random_seed + k;
    add_rendered(fmt::format("random-{}", seed), "", seed);
  }
  for (const fs::path& folder : request.folders) {
    std::string name = io::NormalFolder(folder).filename().string();
    const auto taken = [&](const std::string& n) {
      return std::any_of(sequences.begin(), sequences.end(), [&](const BenchSequence& s) { return s.name == n; });
    };
    for (int k = 2; taken(name); ++k) name = fmt::format("{}-{}", io::NormalFolder(folder).filename().string(), k);
    const fs::path settings = request.settings.empty() ? io::ShippedSettingsForFolder(folder, request.config_dir) : request.settings;
    sequences.push_back(InspectSequence(name, folder, settings));
    if (!sequences.back().problem.empty()) spdlog::warn("{}: left out: {}", name, sequences.back().problem);
  }
  return sequences;
}

// Renders the scenarios not rendered yet, in parallel, and checks every one; a failed rendering becomes the
// sequence's problem.
void RenderScenarios(const Plan& plan, std::vector<BenchSequence>& sequences, std::size_t jobs,
                     const std::function<bool()>& stop_requested) {
  std::vector<Job> renders;
  std::vector<std::size_t> rendered;
  for (std::size_t s = 0; s < sequences.size(); ++s) {
    if (!sequences[s].Rendered() || fs::exists(sequences[s].path / "rgb.txt")) continue;
    fs::create_directories(sequences[s].path.parent_path());
    const fs::path log = sequences[s].path.string() + ".log";
    fs::remove(log);
    renders.push_back({plan.PrepareCommand(sequences[s]), log});
    rendered.push_back(s);
  }
  if (!renders.empty()) spdlog::info("rendering {} synthetic sequence(s)", renders.size());
  RunJobs(renders, {.parallel = jobs}, [&](std::size_t i, const JobOutcome& outcome) {
    BenchSequence& sequence = sequences[rendered[i]];
    if (outcome.Succeeded()) {
      spdlog::info("rendered {} ({:.0f} s)", sequence.name, outcome.seconds);
    } else {
      sequence.problem = fmt::format("rendering failed, {} (log: {}.log)", outcome.Describe(), sequence.path.string());
      spdlog::warn("{}: {}", sequence.name, sequence.problem);
    }
  }, stop_requested);
  for (BenchSequence& sequence : sequences) {
    if (!sequence.Rendered() || !sequence.problem.empty()) continue;
    BenchSequence inspected = InspectSequence(sequence.name, sequence.path, sequence.settings);
    inspected.scenario = sequence.scenario;
    inspected.random_seed = sequence.random_seed;
    sequence = inspected;
  }
}

void WritePlanFiles(const Plan& plan) {
  WriteText(plan.folder / "plan.json", PlanToJson(plan).dump(2) + "\n");
  std::string prepare;
  for (const BenchSequence& sequence : plan.sequences) {
    if (!sequence.Rendered()) continue;
    fs::create_directories(sequence.path.parent_path());
    const std::string log = sequence.path.string() + ".log";
    // Rendering a sequence that is already there is skipped, so the list can run again after a failure.
    prepare += fmt::format("test -e {} || {} > {} 2>&1\n", ShellCommand({(sequence.path / "rgb.txt").string()}),
                           ShellCommand(plan.PrepareCommand(sequence)), ShellCommand({log}));
  }
  WriteText(plan.folder / "prepare.txt", prepare);
  std::string jobs;
  for (const RunSpec& spec : plan.runs) {
    jobs += fmt::format("{} > {} 2>&1\n", ShellCommand(plan.RunCommand(spec)), ShellCommand({plan.RunLog(spec).string()}));
  }
  WriteText(plan.folder / "jobs.txt", jobs);
}

std::string DescribeResult(const RunResult& result) {
  if (result.status != RunStatus::kOk) return fmt::format("{}: {}", ToString(result.status), result.message);
  std::string text = result.ate_rmse ? fmt::format("ATE {:.4f} m", *result.ate_rmse) : "no ATE";
  text += fmt::format(", {} of {} frames tracked", result.tracked, result.frames);
  if (result.leaked) text += fmt::format(", leaked {:.1f} %, wasted {:.1f} %", 100 * *result.leaked, 100 * *result.wasted);
  if (result.dense_ghost_area) text += fmt::format(", dense ghost surface {:.3f} m²", *result.dense_ghost_area);
  return text;
}

// The run of `mode` (its plain variant) on sequence `s` whose ATE is the median of the finished runs (the lower
// one of an even count), so that the picture shows the run the table's figure stands for.
std::optional<std::size_t> MedianRun(const BenchOutcome& outcome, std::size_t s, const std::string& mode) {
  const Plan& plan = outcome.plan;
  std::vector<std::size_t> runs;
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    const RunSpec& spec = plan.runs[i];
    if (spec.sequence == s && plan.variants[spec.variant] == Variant::Plain(mode) &&
        outcome.results[i].status == RunStatus::kOk && outcome.results[i].ate_rmse) {
      runs.push_back(i);
    }
  }
  if (runs.empty()) return std::nullopt;
  std::sort(runs.begin(), runs.end(), [&](std::size_t a, std::size_t b) {
    return *outcome.results[a].ate_rmse < *outcome.results[b].ate_rmse;
  });
  return runs[(runs.size() - 1) / 2];
}

std::string CpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.starts_with("model name")) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

}  // namespace

fs::path SharedDataDir() {
  if (const char* shared = std::getenv("HOIDSLAM_SHARED_DIR"); shared != nullptr && *shared != '\0') return shared;
  return HOIDSLAM_SHARED_DIR_DEFAULT;
}

fs::path ResolveSequenceFolder(const std::string& argument, const fs::path& shared_dir) {
  if (fs::exists(argument)) return argument;
  const fs::path recording = shared_dir / "data" / "tum" / argument;
  // Only a plain name is looked up, never a path that happens to be missing.
  if (fs::path(argument).has_parent_path() || !fs::is_directory(recording)) return argument;
  return recording;
}

BenchOutcome RunBench(const BenchRequest& request, const std::function<bool()>& stop_requested) {
  request.options.Check();
  if (request.scenarios.empty() && request.folders.empty() && request.random == 0) {
    throw core::InputError::ForParameter("--scenarios", "nothing to run: give scenarios, --random or sequence folders");
  }
  PrepareFolder(request);
  std::vector<BenchSequence> sequences = RequestedSequences(request);
  RenderScenarios(MakePlan(request.options, sequences, request.binary, request.folder), sequences, request.jobs,
                  stop_requested);

  BenchOutcome outcome;
  outcome.plan = MakePlan(request.options, sequences, request.binary, request.folder);
  const Plan& plan = outcome.plan;
  WritePlanFiles(plan);

  std::vector<Job> jobs;
  std::vector<std::size_t> job_runs;  // plan.runs index of each job
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    if (request.resume && ReadRunResult(plan, plan.runs[i]).status == RunStatus::kOk) continue;
    fs::remove(plan.RunLog(plan.runs[i]));  // a log tells of the latest attempt only
    jobs.push_back({plan.RunCommand(plan.runs[i]), plan.RunLog(plan.runs[i])});
    job_runs.push_back(i);
  }
  spdlog::info("{} runs planned, {} to run, {} at a time", plan.runs.size(), jobs.size(), request.jobs);
  const core::Stopwatch clock;
  std::size_t finished = 0;
  RunJobs(jobs, {.parallel = request.jobs, .timeout_seconds = plan.options.timeout_seconds},
          [&](std::size_t j, const JobOutcome& job) {
            const RunSpec& spec = plan.runs[job_runs[j]];
            if (job.timed_out) {
              std::ofstream(plan.RunLog(spec), std::ios::app) << "\nhoidslam bench: " << job.Describe() << '\n';
            }
            const RunResult result = ReadRunResult(plan, spec);
            ++finished;
            const double eta = clock.ElapsedSeconds() / static_cast<double>(finished) *
                               static_cast<double>(jobs.size() - finished);
            spdlog::info("[{}/{}] {} {} #{}: {} ({:.0f} s; ETA {})", finished, jobs.size(),
                         plan.sequences[spec.sequence].name, plan.variants[spec.variant].Name(), spec.run,
                         DescribeResult(result), job.seconds, core::FormatDuration(eta));
          },
          stop_requested);

  outcome.interrupted = stop_requested && stop_requested();
  outcome.results = CollectResults(plan);
  outcome.tables = BuildTables(plan, outcome.results);
  return outcome;
}

Plan WriteBenchPlan(const BenchRequest& request) {
  request.options.Check();
  if (request.scenarios.empty() && request.folders.empty() && request.random == 0) {
    throw core::InputError::ForParameter("--scenarios",
                                         "nothing to plan: give scenarios, --random or sequence folders");
  }
  PrepareFolder(request);
  Plan plan = MakePlan(request.options, RequestedSequences(request), request.binary, request.folder);
  WritePlanFiles(plan);
  return plan;
}

BenchOutcome CollectBench(const fs::path& folder) {
  const fs::path plan_path = folder / "plan.json";
  std::ifstream in(plan_path);
  if (!in) throw core::InputError::InFile(plan_path, "not found: --collect needs a folder made by bench --plan");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError::InFile(plan_path, fmt::format("not JSON: {}", e.what()));
  }
  BenchOutcome outcome;
  outcome.plan = PlanFromJson(json, plan_path);
  outcome.results = CollectResults(outcome.plan);
  outcome.tables = BuildTables(outcome.plan, outcome.results);
  return outcome;
}

bool WriteBenchOutputs(const BenchOutcome& outcome) {
  const Plan& plan = outcome.plan;
  nlohmann::json runs = nlohmann::json::array();
  for (std::size_t i = 0; i < plan.runs.size(); ++i) {
    const RunSpec& spec = plan.runs[i];
    nlohmann::json entry = RunResultToJson(outcome.results[i]);
    entry.update({{"id", spec.id},
                  {"sequence", plan.sequences[spec.sequence].name},
                  {"variant", plan.variants[spec.variant].Name()},
                  {"mode", plan.variants[spec.variant].mode},
                  {"run", spec.run}});
    runs.push_back(std::move(entry));
  }
  nlohmann::json tables = nlohmann::json::array();
  std::string markdown = fmt::format("# hoidslam bench\n\nMachine: {}, {} threads. Plan: `{}`.\n\n", CpuModel(),
                                     std::thread::hardware_concurrency(), (plan.folder / "plan.json").string());
  fs::create_directories(plan.folder / "tables");
  for (const NamedTable& named : outcome.tables) {
    const report::Table& t = named.table;
    tables.push_back({{"name", named.name}, {"title", t.title}, {"note", t.note}, {"header", t.header}, {"rows", t.rows}});
    markdown += t.ToMarkdown() + "\n";
    WriteText(plan.folder / "tables" / (named.name + ".csv"), t.ToCsv());
  }
  WriteText(plan.folder / "tables.md", markdown);
  WriteText(plan.folder / "results.json",
            nlohmann::json{{"plan", PlanToJson(plan)}, {"runs", runs}, {"tables", tables}}.dump(2) + "\n");
  try {
    WriteText(plan.folder / "report.html", RenderBenchReport(outcome));
    return true;
  } catch (const core::InputError& e) {
    fs::remove(plan.folder / "report.html");
    spdlog::warn("no report.html: {}", e.what());  // the tables are complete; only the page is missing
    return false;
  }
}

std::string RenderBenchReport(const BenchOutcome& outcome) {
  const Plan& plan = outcome.plan;
  const std::size_t finished = static_cast<std::size_t>(std::count_if(
      outcome.results.begin(), outcome.results.end(), [](const RunResult& r) { return r.status == RunStatus::kOk; }));
  const std::size_t failed = static_cast<std::size_t>(std::count_if(
      outcome.results.begin(), outcome.results.end(), [](const RunResult& r) { return r.status == RunStatus::kFailed; }));
  const std::vector<std::string> intro = {
      fmt::format("{} run{} of {} sequence{}: {} finished, {} failed, {} not run or interrupted", plan.runs.size(),
                  plan.runs.size() == 1 ? "" : "s", plan.sequences.size(), plan.sequences.size() == 1 ? "" : "s",
                  finished, failed, plan.runs.size() - finished - failed),
      fmt::format("Median of {} run{} per cell{}", plan.options.runs, plan.options.runs == 1 ? "" : "s",
                  plan.options.deterministic ? ", deterministic mode" : ""),
      fmt::format("Machine: {}, {} threads", CpuModel(), std::thread::hardware_concurrency()),
      fmt::format("Folder: {} (tables.md, tables/*.csv, results.json; each run's own report in runs/<id>/report.html)",
                  plan.folder.string())};

  std::vector<std::string> sequences;
  for (const BenchSequence& sequence : plan.sequences) sequences.push_back(sequence.name);
  const report::Table* ate_table = FindTable(outcome.tables, "ate");
  std::vector<report::BenchReportSection> sections;
  sections.push_back({.heading = "Accuracy",
                      .text = "ATE RMSE per filter mode and sequence (the median of the runs). A × marks a mode "
                              "without a number: failed, missing or not applicable.",
                      .tables = {*ate_table},
                      .svg_figures = {report::AteBarChartSvg(sequences, plan.options.modes,
                                                             AteMedians(plan, outcome.results))},
                      .html = {}});

  report::BenchReportSection trajectories{
      .heading = "Trajectories",
      .text = "For each of none, hoid2d, hoidplus and oracle that ran, the run whose ATE is the median of its runs: "
              "seen from above over the ground truth, aligned as the ATE aligns them, and its error over time.",
      .tables = {},
      .svg_figures = {},
      .html = {}};
  // The frames are drawn from the default mode's runs, else from the paper's.
  const bool default_mode_ran = std::ranges::find(plan.variants, Variant::Plain("hoidplus")) != plan.variants.end();
  const Variant annotated = Variant::Plain(default_mode_ran ? "hoidplus" : "hoid2d");
  report::BenchReportSection frames{
      .heading = "Annotated frames",
      .text = "From the first " + annotated.Name() +
              " run of each sequence: boxes coloured by the filter's decision with the interaction ratio, keypoints "
              "kept green and dropped red.",
      .tables = {},
      .svg_figures = {},
      .html = {}};
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    // A recording without ground truth has no trajectory to draw over it, but its annotated frames all the same.
    const fs::path groundtruth = plan.sequences[s].path / "groundtruth.txt";
    std::vector<report::RunReport> runs;
    std::vector<std::string> labels;
    for (const std::string mode : {"none", "hoid2d", "hoidplus", "oracle"}) {
      const std::optional<std::size_t> i = MedianRun(outcome, s, mode);
      if (i && fs::exists(groundtruth)) {
        runs.push_back(report::LoadRunReport(plan.RunFolder(plan.runs[*i]), groundtruth));
        labels.push_back(fmt::format("{} {} (run {})", plan.sequences[s].name, mode, plan.runs[*i].run));
      }
    }
    if (!runs.empty()) {
      trajectories.svg_figures.push_back(report::TrajectoryOverlaySvg(runs, labels));
      trajectories.svg_figures.push_back(report::AteOverTimeSvg(runs, labels));
    }
    // Snapshots are kept from each mode's first run only (BenchOptions::snapshots).
    for (std::size_t i = 0; i < plan.runs.size(); ++i) {
      const RunSpec& spec = plan.runs[i];
      if (spec.sequence != s || spec.run != 1 || !(plan.variants[spec.variant] == annotated) ||
          outcome.results[i].status != RunStatus::kOk) {
        continue;
      }
      const std::string gallery = report::SnapshotGallery(report::LoadRunReport(plan.RunFolder(spec), {}), 3);
      if (!gallery.empty()) frames.html += fmt::format("<h3>{}</h3>\n{}", report::EscapeXml(plan.sequences[s].name), gallery);
    }
  }
  if (!trajectories.svg_figures.empty()) sections.push_back(std::move(trajectories));
  if (!frames.html.empty()) sections.push_back(std::move(frames));

  // A section of the tables `names`; without any of them, left out, or `without_tables` said instead.
  const auto section = [&](std::string heading, std::string text, const std::vector<std::string>& names,
                           std::string without_tables = "") {
    report::BenchReportSection result{.heading = std::move(heading), .text = std::move(text), .tables = {},
                                      .svg_figures = {}, .html = {}};
    for (const std::string& name : names) {
      if (const report::Table* table = FindTable(outcome.tables, name)) result.tables.push_back(*table);
    }
    if (result.tables.empty()) result.text = std::move(without_tables);
    if (!result.text.empty() || !result.tables.empty()) sections.push_back(std::move(result));
  };
  section("The paper's tables", "ATE statistics (Tables 3 and 5), 2D against 3D (Table 6) and the sweeps (Table 2).",
          {"ate_statistics", "hoid_2d_3d", "area_sweep", "depth_sweep"});
  section("Drift and lost frames", "", {"rpe_translation", "rpe_rotation", "lost"});
  section("Robustness",
          "Over the runs of each sequence and mode, and over the random sequences: how often tracking held, how far "
          "the ATE spread, whether a relocalisation, loop or merge was false, and how many returns to a mapped place "
          "ended with the map joined there (loop recall).",
          {"robustness", "random"});
  section("Exclusion quality",
          "Against the ground-truth moving masks: leaked is the share of keypoints on moving things kept for "
          "tracking, wasted the share of static keypoints dropped.",
          {"leaked", "wasted"},
          "Not scored: none of the sequences has ground-truth masks (mask/) to tell which keypoints lay on moving "
          "things, as real recordings have none.");
  section("Dense map",
          "With --dense, each run's dense map of the static world against the sequence's exact geometry: the ghost "
          "surface and occupied cells that people and moved objects left in it, accuracy and completeness, the same "
          "as multiples of no filter's and the oracle's; the people it kept, judged in the person boxes without "
          "ground truth; and what the map cost.",
          {"dense_ghost_area", "dense_accuracy", "dense_completeness", "dense_against", "dense_ghost_cells",
           "dense_people", "dense_time", "dense_size"});
  section("Time per stage", "", {"timing"});
  return report::RenderBenchHtml("hoidslam bench", intro, sections);
}

}  // namespace hoidslam::bench
