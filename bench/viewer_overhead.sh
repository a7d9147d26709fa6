#!/usr/bin/env bash
# What the live viewer costs tracking: `hoidslam run` on one sequence without the viewer, with it and no page open,
# and with its page open in headless Chromium (the browser test, web/tests/viewer_test.mjs, watching the whole
# run), in turn, RUNS times each. Prints each run's median tracking time per frame (extract + filter + track, from
# summary.json) and the median of each way. Build first (scripts/setup.sh --no-run).
#
#   bench/viewer_overhead.sh SEQUENCE [RUNS=3] [hoidslam run options...]
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_BUILD_DIR:-$repo/build}"
sequence="${1:?usage: bench/viewer_overhead.sh SEQUENCE [RUNS] [run options...]}"
runs="${2:-3}"
shift $(($# < 2 ? $# : 2))
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

tracking_ms() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['median_ms']['tracking_total'])" "$1/summary.json"; }

declare -A times=([off]="" [on]="" [page]="")
for ((i = 1; i <= runs; i++)); do
  "$build/hoidslam" run "$sequence" "$@" --snapshots 0 --out "$scratch/off" --force > /dev/null 2>&1
  times[off]+=" $(tracking_ms "$scratch/off")"
  "$build/hoidslam" run "$sequence" "$@" --snapshots 0 --out "$scratch/on" --force --view --view-port 0 > /dev/null 2>&1
  times[on]+=" $(tracking_ms "$scratch/on")"
  node "$repo/web/tests/viewer_test.mjs" --hoidslam "$build/hoidslam" --out "$scratch/page" \
    --playwright "$build/web-node/node_modules/playwright-core" --timeout 600 \
    -- "$sequence" "$@" --snapshots 0 --force > "$scratch/page.log" 2>&1 || { cat "$scratch/page.log"; exit 1; }
  times[page]+=" $(tracking_ms "$scratch/page")"
  echo "run $i: off ${times[off]##* } ms, viewer without a page ${times[on]##* } ms, with a page ${times[page]##* } ms;" \
       "$(grep -o 'the page drew .*' "$scratch/page.log")"
done
for way in off on page; do
  python3 -c "import statistics,sys; v=[float(x) for x in sys.argv[2:]]; print(f'{sys.argv[1]}: median {statistics.median(v):.2f} ms of {v}')" "$way" ${times[$way]}
done
