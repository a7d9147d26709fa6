#!/usr/bin/env bash
# Measures the SLAM core on the shipped synthetic scenarios: every filter mode on each scenario and `none` on
# its people-free `_static` control, N runs each (runs in parallel, two at a time), and prints the median ATE
# RMSE and frames lost as Markdown tables (docs/slam.md shows them). `hoidslam bench` will do this with more
# tables; until then this is the command behind the figures.
#
#   scripts/slam-table.sh [WORK_DIR] [RUNS] [MODES...]     default: out/slam-table 5, all six modes
#
# Sequences are rendered into WORK_DIR/seq once (about a minute each); runs go to WORK_DIR/runs, and a run whose
# summary.json exists is not repeated, so an interrupted measurement picks up where it stopped.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_BUILD_DIR:-$repo/build}"
work="${1:-$repo/out/slam-table}"
runs="${2:-5}"
shift $(( $# > 2 ? 2 : $# ))
modes=("$@")
((${#modes[@]} > 0)) || modes=(hoid2d oracle none hoid3d person classes)
scenarios=(walking_xyz walking_static walking_halfsphere walking_rpy sitting_static carry)
mkdir -p "$work/seq" "$work/runs"

for s in "${scenarios[@]}"; do
  for name in "$s" "${s}_static"; do
    [[ -f "$work/seq/$name/rgb.txt" ]] || "$build/hoidslam" synth --scenario "$name" --out "$work/seq/$name" --force
  done
done

jobs="$work/jobs.txt"
: > "$jobs"
for r in $(seq 1 "$runs"); do
  for s in "${scenarios[@]}"; do
    for m in "${modes[@]}"; do echo "$s $m $r" >> "$jobs"; done
    echo "${s}_static none $r" >> "$jobs"
  done
done
export build work
run_one() {
  local out="$work/runs/$1__$2__$3"
  [[ -f "$out/summary.json" ]] && return 0
  "$build/hoidslam" run "$work/seq/$1" --filter "$2" --out "$out" --force > "$out.log" 2>&1 || echo "failed: $out ($out.log)"
}
export -f run_one
xargs -P 2 -L 1 bash -c 'run_one "$@"' _ < "$jobs"

python3 "$repo/scripts/slam_table.py" "$work/runs" "${scenarios[@]}" -- "${modes[@]}"
