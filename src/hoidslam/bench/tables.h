#pragma once
// The bench's results as tables in the shape of the paper's: ATE per mode and sequence (its Tables 3 and 5),
// 2D against 3D (Table 6), the sweeps of the minimum interaction area (Table 2) and of the depth threshold, RPE,
// frames lost, time per stage, the exclusion quality against the ground-truth masks, and with --dense the dense map
// against a synthetic sequence's exact geometry and what it cost. Every cell is the median over the runs that
// finished; a cell with fewer finished runs than planned says how many, and a mode or sequence whose runs all failed
// says "failed", never a number.

#include <string>
#include <vector>

#include "hoidslam/bench/plan.h"
#include "hoidslam/bench/results.h"
#include "hoidslam/report/table.h"

namespace hoidslam::bench {

struct NamedTable {
  std::string name;  // file stem: tables/<name>.csv
  report::Table table;
};

// `results` has one entry per plan.runs entry. Tables that have nothing to show (no sweep asked, no sequence
// with masks) are left out.
std::vector<NamedTable> BuildTables(const Plan& plan, const std::vector<RunResult>& results);

// The table named `name` in `tables`, or nullptr.
const report::Table* FindTable(const std::vector<NamedTable>& tables, const std::string& name);

// The `ate` table's medians as numbers: ATE RMSE (m) per sequence and plain mode (in plan.options.modes order),
// NaN where the table has none (failed, missing, not applicable, no pose).
std::vector<std::vector<double>> AteMedians(const Plan& plan, const std::vector<RunResult>& results);

}  // namespace hoidslam::bench
