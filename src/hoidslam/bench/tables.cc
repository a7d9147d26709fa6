#include "hoidslam/bench/tables.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <fmt/format.h>

#include "hoidslam/eval/dense_score.h"
#include "hoidslam/eval/pose_check.h"
#include "hoidslam/eval/statistics.h"

namespace hoidslam::bench {
namespace {

using Value = std::function<std::optional<double>(const RunResult&)>;
using Format = std::function<std::string(double)>;

// A figure of a run and how a cell shows its median.
struct Figure {
  Value value;
  Format format;
};

double Median(std::vector<double> values) { return eval::ComputeStatistics(values).median; }

// The q-quantile of `values` (not empty) by linear interpolation between the closest ranks, as numpy.percentile.
double Quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
}

const Value kAteRmse = [](const RunResult& r) { return r.ate_rmse; };

// A run whose ATE is more than this many times its cell's median lost its map once: a failure, not noise.
constexpr double kJumpFactor = 3.0;
// A run tracking fewer than this share of the frames it could see (the lens uncovered) lost tracking for real.
constexpr double kMinTrackedShare = 0.99;

using Member = std::optional<double> RunResult::*;

// False ones of all, summed over `runs`: "1 of 3"; "–" when no run could judge them (no ground truth).
std::string FalseOfAll(const std::vector<const RunResult*>& runs, Member all, Member wrong) {
  double total = 0.0, false_ones = 0.0;
  bool judged = false;
  for (const RunResult* r : runs) {
    if (!(r->*all)) continue;
    judged = true;
    total += *(r->*all);
    false_ones += (r->*wrong).value_or(0.0);
  }
  return judged ? fmt::format("{:g} of {:g}", false_ones, total) : "–";
}

// A share pooled over `runs` (the parts summed over the wholes summed, so a run with many events weighs more than
// one with few): "83 % (5 of 6)"; `nothing` when the wholes sum to 0 (a share of nothing is no 100 %), "–" when no
// run measured it.
std::string Pooled(const std::vector<const RunResult*>& runs, Member part, Member whole, const std::string& nothing) {
  double parts = 0.0, wholes = 0.0;
  bool measured = false;
  for (const RunResult* r : runs) {
    if (!(r->*part) || !(r->*whole)) continue;
    measured = true;
    parts += *(r->*part);
    wholes += *(r->*whole);
  }
  if (!measured) return "–";
  if (wholes == 0.0) return nothing;
  return fmt::format("{:.0f} % ({:g} of {:g})", 100.0 * parts / wholes, parts, wholes);
}

// Frames tracked of all, per run, as a share; runs without frames left out.
std::vector<double> TrackedShares(const std::vector<const RunResult*>& runs) {
  std::vector<double> shares;
  for (const RunResult* r : runs) {
    if (r->frames > 0) shares.push_back(static_cast<double>(r->tracked) / static_cast<double>(r->frames));
  }
  return shares;
}

// The runs of one sequence and one variant.
struct Group {
  std::size_t planned = 0;
  std::size_t failed = 0;
  std::vector<const RunResult*> ok;
};

class Grid {
 public:
  Grid(const Plan& plan, const std::vector<RunResult>& results)
      : plan_(plan), groups_(plan.sequences.size(), std::vector<Group>(plan.variants.size())) {
    for (std::size_t i = 0; i < plan.runs.size(); ++i) {
      Group& group = groups_[plan.runs[i].sequence][plan.runs[i].variant];
      ++group.planned;
      if (results[i].status == RunStatus::kOk) group.ok.push_back(&results[i]);
      if (results[i].status == RunStatus::kFailed) ++group.failed;
    }
  }

  // The median of `value` over the finished runs, when they all have it.
  std::optional<double> MedianOf(std::size_t sequence, std::size_t variant, const Value& value) const {
    const Group& group = groups_[sequence][variant];
    std::vector<double> values;
    for (const RunResult* r : group.ok) {
      if (const std::optional<double> v = value(*r)) values.push_back(*v);
    }
    if (values.empty() || values.size() != group.ok.size()) return std::nullopt;
    return Median(values);
  }

  // One cell: the formatted median (with the frames tracked when `tracked`) and "(k/n)" when runs are missing, or
  // why there is no number.
  std::string Cell(std::size_t sequence, std::optional<std::size_t> variant, const Value& value,
                   const std::function<std::string(double)>& format, bool tracked = false) const {
    if (!plan_.sequences[sequence].problem.empty()) return "missing";
    if (!variant) return "–";
    const Group& group = groups_[sequence][*variant];
    if (group.planned == 0) return "–";  // not applicable (oracle without masks)
    if (group.ok.empty()) return group.failed > 0 ? "failed" : "not run";
    const std::optional<double> median = MedianOf(sequence, *variant, value);
    if (!median) {
      const bool none_tracked = std::all_of(group.ok.begin(), group.ok.end(), [](const RunResult* r) {
        return r->tracked == 0;
      });
      if (none_tracked) return "no pose";
      // No run could be scored: the sequence has no ground truth, or no ground-truth masks (a real recording).
      const bool none_scored = std::none_of(group.ok.begin(), group.ok.end(), [&](const RunResult* r) {
        return value(*r).has_value();
      });
      return none_scored ? "–" : "n/a";
    }
    return format(*median) + (tracked ? Tracked(sequence, *variant) : "") + Shortfall(sequence, *variant);
  }

  // Several figures of the same runs in one cell: their medians joined by `separator`, as Cell shows one; or why
  // there is no number, as Cell says it for the first figure without one.
  std::string Joined(std::size_t sequence, std::size_t variant, const std::vector<Figure>& figures,
                     std::string_view separator, bool tracked = false) const {
    std::vector<std::string> medians;
    for (const Figure& figure : figures) {
      const std::optional<double> median = MedianOf(sequence, variant, figure.value);
      if (!median) return Cell(sequence, variant, figure.value, figure.format);
      medians.push_back(figure.format(*median));
    }
    return fmt::format("{}", fmt::join(medians, separator)) + (tracked ? Tracked(sequence, variant) : "") +
           Shortfall(sequence, variant);
  }

  // " (826/826 tracked)": the medians of the frames tracked and of the frames over the cell's finished runs, the
  // runs its ATE is the median of. Not the tracked count of the median run: of an even count of runs the median
  // ATE is no one run's.
  std::string Tracked(std::size_t sequence, std::size_t variant) const {
    std::vector<double> tracked, frames;
    for (const RunResult* r : groups_[sequence][variant].ok) {
      tracked.push_back(static_cast<double>(r->tracked));
      frames.push_back(static_cast<double>(r->frames));
    }
    return tracked.empty() ? "" : fmt::format(" ({:g}/{:g} tracked)", Median(tracked), Median(frames));
  }

  // " (k/n)" when only k of the n planned runs finished, else empty.
  std::string Shortfall(std::size_t sequence, std::size_t variant) const {
    const Group& group = groups_[sequence][variant];
    return group.ok.size() < group.planned ? fmt::format(" ({}/{})", group.ok.size(), group.planned) : "";
  }

  const Group& group(std::size_t sequence, std::size_t variant) const { return groups_[sequence][variant]; }

 private:
  const Plan& plan_;
  std::vector<std::vector<Group>> groups_;
};

std::string Metres(double v) { return fmt::format("{:.4f}", v); }
std::string Percent(double v) { return fmt::format("{:.1f} %", 100.0 * v); }
std::string Millis(double v) { return fmt::format("{:.2f}", v); }
std::string Count(double v) { return fmt::format("{:g}", v); }

std::optional<std::size_t> PlainVariant(const Plan& plan, const std::string& mode) {
  for (std::size_t v = 0; v < plan.variants.size(); ++v) {
    if (plan.variants[v] == Variant::Plain(mode)) return v;
  }
  return std::nullopt;
}

std::vector<std::size_t> PlainVariants(const Plan& plan) {
  std::vector<std::size_t> variants;
  for (const std::string& mode : plan.options.modes) variants.push_back(*PlainVariant(plan, mode));
  return variants;
}

// `lead` says what a cell is; the note adds how the runs were made and what the marks mean.
std::string RunsNote(const Plan& plan, std::string lead) {
  std::string note = std::move(lead);
  if (plan.options.deterministic) note += " (deterministic mode)";
  if (plan.options.realtime) note += " (real-time mode)";
  if (plan.options.pace) note += " (paced at the recorded rate)";
  if (plan.options.detector_latency_ms > 0) {
    note += fmt::format(" (detector latency {} ms)", plan.options.detector_latency_ms);
  }
  note += "; (k/n): only k of n runs finished; failed: no run finished; no pose: the runs finished without "
          "tracking a frame (the map never started); –: not applicable (such as no ground truth, or no "
          "ground-truth masks to score exclusion quality against).";
  for (const BenchSequence& s : plan.sequences) {
    if (!s.problem.empty()) note += fmt::format(" {} is missing: {}.", s.name, s.problem);
  }
  return note;
}

std::string RunsNote(const Plan& plan, std::size_t runs) {
  return RunsNote(plan, fmt::format("Median of {} run{} per cell", runs, runs == 1 ? "" : "s"));
}

using CellText = std::function<std::string(std::size_t sequence, std::size_t variant)>;

// Rows: sequences; columns: the plain modes.
report::Table PerMode(const Plan& plan, std::string title, const CellText& cell) {
  report::Table table{
      .title = std::move(title), .note = RunsNote(plan, plan.options.runs), .header = {"sequence"}, .rows = {}};
  for (const std::size_t v : PlainVariants(plan)) table.header.push_back(plan.variants[v].Name());
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    std::vector<std::string> row = {plan.sequences[s].name};
    for (const std::size_t v : PlainVariants(plan)) row.push_back(cell(s, v));
    table.rows.push_back(std::move(row));
  }
  return table;
}

// PerMode with the medians of `figures` in each cell (Grid::Joined, with the frames tracked when `tracked`), and a
// last row with their medians over the sequences (when there are several and every one has a number).
report::Table PerMode(const Plan& plan, const Grid& grid, std::string title, const std::vector<Figure>& figures,
                      std::string_view separator, bool tracked = false) {
  report::Table table = PerMode(plan, std::move(title), [&](std::size_t s, std::size_t v) {
    return grid.Joined(s, v, figures, separator, tracked);
  });
  if (plan.sequences.size() < 2) return table;
  std::vector<std::string> row = {"median of the sequences"};
  for (const std::size_t v : PlainVariants(plan)) {
    std::vector<std::string> medians;
    for (const Figure& figure : figures) {
      std::vector<double> values;
      for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
        if (const std::optional<double> m = grid.MedianOf(s, v, figure.value)) values.push_back(*m);
      }
      if (values.size() < plan.sequences.size()) break;
      medians.push_back(figure.format(Median(values)));
    }
    row.push_back(medians.size() == figures.size() ? fmt::format("{}", fmt::join(medians, separator)) : "–");
  }
  table.rows.push_back(std::move(row));
  return table;
}

// PerMode with one figure per cell.
report::Table PerMode(const Plan& plan, const Grid& grid, std::string title, const Value& value, const Format& format,
                      bool tracked = false) {
  return PerMode(plan, grid, std::move(title), {{value, format}}, "", tracked);
}

report::Table Sweep(const Plan& plan, const Grid& grid, const std::string& mode, const std::vector<double>& values,
                    bool is_area, std::string title) {
  std::string note = RunsNote(plan, plan.options.SweepRuns());
  if (plan.options.SweepRuns() != plan.options.runs) {
    note += fmt::format(" The value a sequence's settings give is measured by the plain {} runs ({} per cell).", mode,
                        plan.options.runs);
  }
  report::Table table{.title = std::move(title), .note = std::move(note), .header = {"sequence"}, .rows = {}};
  for (const double value : values) table.header.push_back(fmt::format("{}", value));
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    std::vector<std::string> row = {plan.sequences[s].name};
    for (const double value : values) {
      row.push_back(grid.Cell(s, plan.SweepVariant(mode, value, is_area, plan.sequences[s]), kAteRmse, Metres, true));
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

// Per sequence and plain mode, over its runs: how often tracking held, how far the ATE spread, whether anything was
// joined wrongly, and whether the returns were recalled.
report::Table Robustness(const Plan& plan, const Grid& grid) {
  report::Table table{
      .title = "Robustness over the runs: frames tracked, ATE spread, false relocalisations, loops and merges, loop "
               "recall and precision",
      .note = RunsNote(plan, fmt::format("Of the {} run{} of each sequence and mode: tracked % the median and the "
                                         "least; the ATE median and the largest ATE over it; false ones of all, "
                                         "summed; loop recall (returns recalled of all) and precision (loops and "
                                         "merges the ground truth confirms of all closed), pooled over the runs; no "
                                         "return / no loop: nothing to count",
                                         plan.options.runs, plan.options.runs == 1 ? "" : "s")),
      .header = {"sequence", "mode", "runs", "tracked % (median)", "tracked % (min)", "ATE median (m)",
                 "ATE max / median", "false relocalisations", "false loops", "false merges", "loop recall",
                 "loop precision"},
      .rows = {}};
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    for (const std::size_t v : PlainVariants(plan)) {
      const Group& group = grid.group(s, v);
      std::vector<std::string> row = {plan.sequences[s].name, plan.variants[v].Name()};
      if (plan.sequences[s].problem.empty() && group.planned == 0) continue;  // not applicable (oracle)
      if (!plan.sequences[s].problem.empty() || group.ok.empty()) {
        row.resize(table.header.size(), grid.Cell(s, v, kAteRmse, Metres));  // missing, failed, not run
        table.rows.push_back(std::move(row));
        continue;
      }
      row.push_back(group.ok.size() == group.planned ? std::to_string(group.planned)
                                                     : fmt::format("{} of {}", group.ok.size(), group.planned));
      const std::vector<double> shares = TrackedShares(group.ok);
      row.push_back(shares.empty() ? "–" : Percent(Median(shares)));
      row.push_back(shares.empty() ? "–" : Percent(*std::min_element(shares.begin(), shares.end())));
      if (const std::optional<double> median = grid.MedianOf(s, v, kAteRmse)) {
        double largest = 0.0;
        for (const RunResult* r : group.ok) largest = std::max(largest, *r->ate_rmse);
        row.push_back(Metres(*median));
        row.push_back(*median > 0.0 ? fmt::format("{:.2f}", largest / *median) : "–");
      } else {
        row.insert(row.end(), 2, grid.Cell(s, v, kAteRmse, Metres));  // says why not
      }
      row.push_back(FalseOfAll(group.ok, &RunResult::relocalizations, &RunResult::false_relocalizations));
      row.push_back(FalseOfAll(group.ok, &RunResult::loops, &RunResult::false_loops));
      row.push_back(FalseOfAll(group.ok, &RunResult::merges, &RunResult::false_merges));
      row.push_back(Pooled(group.ok, &RunResult::returns_recalled, &RunResult::return_events, "no return"));
      row.push_back(Pooled(group.ok, &RunResult::closures_confirmed, &RunResult::closures_judged, "no loop"));
      table.rows.push_back(std::move(row));
    }
  }
  return table;
}

// Over every random sequence and run of each plain mode: what a user meeting scenes like these would see.
report::Table RandomDistribution(const Plan& plan, const Grid& grid, const std::vector<std::size_t>& random) {
  report::Table table{
      .title = fmt::format("Over {} random sequence{}: the distribution of the runs", random.size(),
                           random.size() == 1 ? "" : "s"),
      .note = RunsNote(plan, fmt::format("Every finished run of the random sequences, {} planned per sequence and "
                                         "mode. Uncovered frames: those the lens was not covered in (events.jsonl); "
                                         "a jump: a run whose ATE is more than {:g}× the median of its sequence's "
                                         "runs; false ones of all and loop recall and precision pooled over the "
                                         "runs; the 90th percentile interpolates between ranks (numpy's)",
                                         plan.options.runs, kJumpFactor)),
      .header = {"measure"},
      .rows = {{"runs finished"},
               {"tracked % (median / min)"},
               {fmt::format("runs tracking under {:g} % of the uncovered frames", 100.0 * kMinTrackedShare)},
               {"ATE RMSE median / 90th percentile (m)"},
               {fmt::format("runs above {:g}× their sequence's median ATE", kJumpFactor)},
               {"false relocalisations"},
               {"false loops"},
               {"false merges"},
               {"loop recall"},
               {"loop precision"}}};
  for (const std::size_t v : PlainVariants(plan)) {
    table.header.push_back(plan.variants[v].Name());
    std::vector<const RunResult*> runs;
    std::size_t planned = 0, under = 0, jumps = 0, judged = 0;
    std::vector<double> ates;
    for (const std::size_t s : random) {
      const Group& group = grid.group(s, v);
      planned += group.planned;
      runs.insert(runs.end(), group.ok.begin(), group.ok.end());
      const std::optional<double> median = grid.MedianOf(s, v, kAteRmse);
      for (const RunResult* r : group.ok) {
        const double uncovered = static_cast<double>(r->frames - std::min(r->covered, r->frames));
        if (static_cast<double>(r->tracked) < kMinTrackedShare * uncovered) ++under;
        if (!r->ate_rmse) continue;
        ates.push_back(*r->ate_rmse);
        if (!median) continue;
        ++judged;
        if (*r->ate_rmse > kJumpFactor * *median) ++jumps;
      }
    }
    const std::vector<double> shares = TrackedShares(runs);
    const std::vector<std::string> cells = {
        fmt::format("{} of {}", runs.size(), planned),
        shares.empty() ? "–"
                       : fmt::format("{} / {}", Percent(Median(shares)),
                                     Percent(*std::min_element(shares.begin(), shares.end()))),
        fmt::format("{} of {}", under, runs.size()),
        ates.empty() ? "–" : fmt::format("{} / {}", Metres(Median(ates)), Metres(Quantile(ates, 0.9))),
        judged == 0 ? "–" : fmt::format("{} of {}", jumps, judged),
        FalseOfAll(runs, &RunResult::relocalizations, &RunResult::false_relocalizations),
        FalseOfAll(runs, &RunResult::loops, &RunResult::false_loops),
        FalseOfAll(runs, &RunResult::merges, &RunResult::false_merges),
        Pooled(runs, &RunResult::returns_recalled, &RunResult::return_events, "no return"),
        Pooled(runs, &RunResult::closures_confirmed, &RunResult::closures_judged, "no loop")};
    for (std::size_t i = 0; i < cells.size(); ++i) table.rows[i].push_back(cells[i]);
  }
  return table;
}

std::string Millimetres(double v) { return fmt::format("{:.1f}", 1000.0 * v); }
std::string OneDecimal(double v) { return fmt::format("{:.1f}", v); }
std::string GhostArea(double v) { return fmt::format("{:.3f}", v); }

const Value kDenseArea = [](const RunResult& r) { return r.dense_area; };
const Value kGhostArea = [](const RunResult& r) { return r.dense_ghost_area; };
const Value kDenseAccuracy = [](const RunResult& r) { return r.dense_accuracy_median; };
const Value kCompleteness = [](const RunResult& r) { return r.dense_completeness; };

// Whether any run has `value`: a bench without --dense, or without a sequence carrying its geometry, has no dense
// table of it.
bool AnyRunHas(const std::vector<RunResult>& results, const Value& value) {
  return std::any_of(results.begin(), results.end(), [&](const RunResult& r) { return value(r).has_value(); });
}

// Per sequence and plain mode: its dense map's ghost surface as a multiple of none's and oracle's on the sequence,
// and its accuracy and completeness as a multiple of oracle's (of the medians over the runs). The columns of a
// mode the plan does not run are left out; without none and oracle there is no table.
std::optional<report::Table> DenseAgainstReferences(const Plan& plan, const Grid& grid, const std::string& note) {
  struct Ratio {
    std::string header;
    Value value;
    std::size_t reference;
  };
  std::vector<Ratio> ratios;
  if (const std::optional<std::size_t> none = PlainVariant(plan, "none")) {
    ratios.push_back({"ghost surface / none's", kGhostArea, *none});
  }
  if (const std::optional<std::size_t> oracle = PlainVariant(plan, "oracle")) {
    ratios.push_back({"ghost surface / oracle's", kGhostArea, *oracle});
    ratios.push_back({"accuracy / oracle's", kDenseAccuracy, *oracle});
    ratios.push_back({"completeness / oracle's", kCompleteness, *oracle});
  }
  if (ratios.empty()) return std::nullopt;
  report::Table table{
      .title = "Dense map against no filter and the oracle: ghost surface, accuracy and completeness as multiples",
      .note = note + " Each mode's median over its runs divided by the reference mode's on the same sequence; –: the "
                     "reference has no number there, or 0. The targets of the default mode, hoidplus: a ghost surface "
                     "at most 0.2× none's and 2× oracle's, accuracy within 1.2× oracle's, completeness at least 0.9× "
                     "oracle's.",
      .header = {"sequence", "mode"},
      .rows = {}};
  for (const Ratio& ratio : ratios) table.header.push_back(ratio.header);
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    for (const std::size_t v : PlainVariants(plan)) {
      if (plan.sequences[s].problem.empty() && grid.group(s, v).planned == 0) continue;  // not applicable (oracle)
      std::vector<std::string> row = {plan.sequences[s].name, plan.variants[v].Name()};
      for (const Ratio& ratio : ratios) {
        const std::optional<double> own = grid.MedianOf(s, v, ratio.value);
        if (!own) {
          row.push_back(grid.Cell(s, v, ratio.value, OneDecimal));  // says why not
          continue;
        }
        const std::optional<double> reference = grid.MedianOf(s, ratio.reference, ratio.value);
        row.push_back(reference && *reference > 0.0 ? fmt::format("{:.2f}×", *own / *reference) : "–");
      }
      table.rows.push_back(std::move(row));
    }
  }
  return table;
}

// The dense map of a bench with --dense: against the exact geometry of the sequences that carry it (synthetic ones),
// and what it cost.
void AddDenseTables(const Plan& plan, const Grid& grid, const std::vector<RunResult>& results,
                    std::vector<NamedTable>& tables) {
  const std::string note =
      RunsNote(plan, plan.options.runs) +
      " The dense map is scored against the sequence's exact geometry (static_geometry.ply and moving_volume.ply, "
      "which synthetic sequences carry); – on a sequence without it.";
  const auto scored = [&](std::string title, const std::vector<Figure>& figures, std::string_view separator) {
    report::Table table = PerMode(plan, grid, std::move(title), figures, separator);
    table.note = note;
    return table;
  };
  const Value ghost_share = [](const RunResult& r) { return r.dense_ghost_share; };
  const Value accuracy_p90 = [](const RunResult& r) { return r.dense_accuracy_p90; };
  const Value ghost_cells = [](const RunResult& r) { return r.dense_ghost_cells; };
  const Value occupied_cells = [](const RunResult& r) { return r.dense_occupied_cells; };
  const Value fuse_ms = [](const RunResult& r) { return r.dense_fuse_ms; };
  const Value build_seconds = [](const RunResult& r) { return r.dense_build_seconds; };
  const Value volume_mb = [](const RunResult& r) { return r.dense_volume_mb; };
  const eval::DenseScoreOptions score;  // what `run --dense` scores with
  if (AnyRunHas(results, kGhostArea)) {
    tables.push_back({"dense_ghost_area",
                      scored(fmt::format("Dense map: ghost surface (m²), farther than {:g} cm from every static "
                                         "surface, and its share of the map's",
                                         100.0 * score.ghost_distance),
                             {{kGhostArea, GhostArea}, {ghost_share, Percent}}, " / ")});
    tables.push_back({"dense_accuracy",
                      scored("Dense map: accuracy (mm), the distance of its vertices to the true static surface, "
                             "median / 90th percentile",
                             {{kDenseAccuracy, Millimetres}, {accuracy_p90, Millimetres}}, " / ")});
    tables.push_back({"dense_completeness",
                      scored(fmt::format("Dense map: completeness (%), the static surface in view mapped within {:g} "
                                         "cm",
                                         100.0 * score.completeness_distance),
                             {{kCompleteness, Percent}}, "")});
    if (std::optional<report::Table> against = DenseAgainstReferences(plan, grid, note)) {
      tables.push_back({"dense_against", std::move(*against)});
    }
  }
  if (AnyRunHas(results, ghost_cells)) {
    tables.push_back({"dense_ghost_cells",
                      scored("Dense map: occupancy ghost cells, occupied where only people and moved objects ever "
                             "were, of the occupied cells",
                             {{ghost_cells, Count}, {occupied_cells, Count}}, " of ")});
  }
  const Value people_kept = [](const RunResult& r) { return r.dense_people_kept; };
  if (AnyRunHas(results, people_kept)) {
    report::Table table = PerMode(plan, grid,
                                  "Dense map: people kept (%), of the person pixels in the keyframes' person boxes "
                                  "those where the map has surface at the depth measured",
                                  {{people_kept, Percent}}, "");
    table.note = RunsNote(plan, plan.options.runs) +
                 " Judged without ground truth, on real recordings too: a map with the people left out has surface "
                 "there only where something static stands at the person's depth; – when no keyframe had a person "
                 "box (mode none without the sequence's own detections.jsonl runs no detector).";
    tables.push_back({"dense_people", std::move(table)});
  }
  if (AnyRunHas(results, kDenseArea)) {
    tables.push_back({"dense_time", PerMode(plan, grid, "Dense map: fusion (ms a keyframe) and final build (s)",
                                            {{fuse_ms, OneDecimal}, {build_seconds, OneDecimal}}, " / ")});
    tables.push_back({"dense_size", PerMode(plan, grid, "Dense map: mesh surface (m²) and the volume's memory (MB)",
                                            {{kDenseArea, OneDecimal}, {volume_mb, OneDecimal}}, " / ")});
  }
}

}  // namespace

const report::Table* FindTable(const std::vector<NamedTable>& tables, const std::string& name) {
  for (const NamedTable& named : tables) {
    if (named.name == name) return &named.table;
  }
  return nullptr;
}

std::vector<std::vector<double>> AteMedians(const Plan& plan, const std::vector<RunResult>& results) {
  const Grid grid(plan, results);
  std::vector<std::vector<double>> medians;
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    std::vector<double>& row = medians.emplace_back();
    for (const std::size_t v : PlainVariants(plan)) {
      row.push_back(grid.MedianOf(s, v, kAteRmse).value_or(std::numeric_limits<double>::quiet_NaN()));
    }
  }
  return medians;
}

std::vector<NamedTable> BuildTables(const Plan& plan, const std::vector<RunResult>& results) {
  const Grid grid(plan, results);
  const auto has_mode = [&plan](const std::string& mode) { return PlainVariant(plan, mode).has_value(); };
  std::vector<NamedTable> tables;

  const Value mean = [](const RunResult& r) { return r.ate_mean; };
  const Value median = [](const RunResult& r) { return r.ate_median; };
  tables.push_back({"ate", PerMode(plan, grid, "ATE RMSE (m) per filter mode, with the frames tracked", kAteRmse,
                                   Metres, true)});
  tables.push_back({"ate_statistics",
                    PerMode(plan, "ATE RMSE / mean / median (m), as in the paper's Tables 3 and 5",
                            [&](std::size_t s, std::size_t v) {
                              return grid.Joined(s, v, {{kAteRmse, Metres}, {mean, Metres}, {median, Metres}}, " / ",
                                                 true);
                            })});

  if (has_mode("hoid2d") && has_mode("hoid3d")) {
    report::Table table{.title = "2D against 3D interaction test: ATE RMSE (m), as in the paper's Table 6",
                        .note = RunsNote(plan, plan.options.runs),
                        .header = {"sequence", "hoid2d", "hoid3d", "3D − 2D"},
                        .rows = {}};
    const std::size_t v2 = *PlainVariant(plan, "hoid2d");
    const std::size_t v3 = *PlainVariant(plan, "hoid3d");
    for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
      const std::optional<double> a = grid.MedianOf(s, v2, kAteRmse);
      const std::optional<double> b = grid.MedianOf(s, v3, kAteRmse);
      table.rows.push_back({plan.sequences[s].name, grid.Cell(s, v2, kAteRmse, Metres, true),
                            grid.Cell(s, v3, kAteRmse, Metres, true),
                            a && b && plan.sequences[s].problem.empty() ? fmt::format("{:+.4f}", *b - *a) : "–"});
    }
    tables.push_back({"hoid_2d_3d", std::move(table)});
  }
  if (!plan.options.area_sweep.empty()) {
    tables.push_back({"area_sweep", Sweep(plan, grid, "hoid2d", plan.options.area_sweep, true,
                                          "hoid2d ATE RMSE (m) by minimum interaction area, as in the paper's Table 2")});
  }
  if (!plan.options.depth_sweep.empty()) {
    tables.push_back({"depth_sweep", Sweep(plan, grid, "hoid3d", plan.options.depth_sweep, false,
                                           "hoid3d ATE RMSE (m) by depth threshold (m)")});
  }

  // A run that jumps is a failure, not noise: each cell's runs whose ATE is more than 3× the cell's median.
  report::Table jumps = PerMode(
      plan, fmt::format("Runs whose ATE RMSE is more than {:g}× the median of their cell, of all", kJumpFactor),
      [&](std::size_t s, std::size_t v) {
        const std::optional<double> median_ate = grid.MedianOf(s, v, kAteRmse);
        if (!median_ate) return grid.Cell(s, v, kAteRmse, Metres);  // says why not
        std::size_t jumped = 0, runs = 0;
        for (const RunResult* r : grid.group(s, v).ok) {
          if (!r->ate_rmse) continue;
          ++runs;
          if (*r->ate_rmse > kJumpFactor * *median_ate) ++jumped;
        }
        return fmt::format("{} of {}{}", jumped, runs, grid.Shortfall(s, v));
      });
  jumps.note = RunsNote(plan, fmt::format("Of the {} runs of each cell: a run far off its cell's median lost its map "
                                          "once (a wrong relocalisation or loop, a bad keyframe)",
                                          plan.options.runs));
  tables.push_back({"jumps", std::move(jumps)});

  tables.push_back({"rpe_translation",
                    PerMode(plan, grid, "RPE translation RMSE (m per second)",
                            [](const RunResult& r) { return r.rpe_translation_rmse; }, Metres)});
  tables.push_back({"rpe_rotation", PerMode(plan, grid, "RPE rotation RMSE (degrees per second)",
                                            [](const RunResult& r) { return r.rpe_rotation_rmse; },
                                            [](double v) { return fmt::format("{:.3f}", v); })});
  tables.push_back({"lost", PerMode(plan, grid, "Frames lost after initialisation (and never initialised)",
                                    [](const RunResult& r) -> std::optional<double> {
                                      return static_cast<double>(r.lost + r.before_initialization);
                                    },
                                    Count)});
  // Events checked against the ground truth, summed over the runs of each cell: one false one in any run is a
  // failure.
  const auto false_of_all = [&](const std::string& title, Member all, Member wrong, const std::string& what) {
    const Value count = [all](const RunResult& r) { return r.*all; };
    report::Table table = PerMode(plan, title, [&](std::size_t s, std::size_t v) {
      if (!grid.MedianOf(s, v, count)) return grid.Cell(s, v, count, Count);  // says why not
      return FalseOfAll(grid.group(s, v).ok, all, wrong) + grid.Shortfall(s, v);
    });
    table.note = RunsNote(plan, fmt::format("Summed over the {} runs of each cell: a false {} in any of them is a "
                                            "failure", plan.options.runs, what));
    return table;
  };
  const eval::PoseCheckOptions limits;
  tables.push_back({"relocalizations",
                    false_of_all(fmt::format("False relocalisations (more than {:g} m or {:g}° from the ground truth) "
                                             "of all, over the runs",
                                             limits.max_position_error, limits.max_rotation_error_deg),
                                 &RunResult::relocalizations, &RunResult::false_relocalizations, "relocalisation")});
  tables.push_back({"loops", false_of_all(fmt::format("False loops (their two ends more than {:g} m or {:g}° from the "
                                                      "true relative pose) of all closed, over the runs",
                                                      limits.max_position_error, limits.max_rotation_error_deg),
                                          &RunResult::loops, &RunResult::false_loops, "loop")});
  tables.push_back({"robustness", Robustness(plan, grid)});
  std::vector<std::size_t> random;
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    if (plan.sequences[s].random_seed) random.push_back(s);
  }
  if (!random.empty()) tables.push_back({"random", RandomDistribution(plan, grid, random)});

  const bool any_masks = std::any_of(plan.sequences.begin(), plan.sequences.end(),
                                     [](const BenchSequence& s) { return s.has_masks && s.problem.empty(); });
  if (any_masks) {
    tables.push_back({"leaked", PerMode(plan, grid,
                                        "Exclusion quality: keypoints on moving things kept for tracking (leaked)",
                                        [](const RunResult& r) { return r.leaked; }, Percent)});
    tables.push_back({"wasted", PerMode(plan, grid, "Exclusion quality: static keypoints dropped (wasted)",
                                        [](const RunResult& r) { return r.wasted; }, Percent)});
  }

  AddDenseTables(plan, grid, results, tables);

  report::Table timing{.title = "Time per stage (ms per frame): median over the runs of each run's median",
                       .note = "Tracking = extraction + filter + tracking, the detector excluded. Runs that share "
                               "the cores (--jobs > 1) are slower than one run alone.",
                       .header = {"mode", "load", "extract", "detect", "filter", "track", "tracking", "runs"},
                       .rows = {}};
  for (const std::size_t v : PlainVariants(plan)) {
    std::vector<StageMedians> medians;
    for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
      for (const RunResult* r : grid.group(s, v).ok) medians.push_back(r->median_ms);
    }
    std::vector<std::string> row = {plan.variants[v].Name()};
    for (double StageMedians::*stage : {&StageMedians::load, &StageMedians::extract, &StageMedians::detect,
                                        &StageMedians::filter, &StageMedians::track, &StageMedians::tracking_total}) {
      std::vector<double> values;
      for (const StageMedians& m : medians) values.push_back(m.*stage);
      row.push_back(values.empty() ? "–" : Millis(Median(values)));
    }
    row.push_back(std::to_string(medians.size()));
    timing.rows.push_back(std::move(row));
  }
  tables.push_back({"timing", std::move(timing)});
  return tables;
}

}  // namespace hoidslam::bench
