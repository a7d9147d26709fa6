#!/usr/bin/env bash
# Builds hoidslam's fuzz targets with clang (libFuzzer, AddressSanitizer, UndefinedBehaviorSanitizer) and runs each
# for a fixed time on its corpus and regressions. Fails when any target finds a crash, a sanitizer report, a broken
# error contract or a time-out. docs/fuzzing.md explains the targets.
#
#   scripts/fuzz.sh [--seconds-per-target N] [--jobs J] [--build-dir DIR] [--update-corpus] [target...]
#
#   --seconds-per-target N  run each target N seconds (default 60)
#   --jobs J                run J targets at a time (default 1; CI runs $(nproc))
#   --build-dir DIR         the clang build (default: build-asan in the checkout, the ASan build of
#                           scripts/sanitize.sh asan, configured the same way (scripts/sanitizers/builds.sh): after
#                           that script, nothing is left to build; never the gcc build/)
#   --update-corpus         afterwards, add to fuzz/corpus/<target> the inputs of DIR/new-corpus/<target> that
#                           reach code it does not (-merge=1 on edges only, which keeps the corpus small); by
#                           default new inputs stay in DIR/new-corpus/<target>
#   target...               some of the folders of fuzz/corpus: settings tum_lists associations trajectory
#                           detections scenario vocabulary (default: all)
#
# Findings go to DIR/findings/<target>/ (crash-*, timeout-*, oom-*), each run's log to DIR/logs/<target>.log.
# To replay one input: DIR/fuzz/<target>_fuzzer <file>. On a shared machine, run it niced: nice -n 10 scripts/fuzz.sh
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HOIDSLAM_ASAN_BUILD_DIR:-$repo/build-asan}"
seconds=60
jobs=1
update_corpus=0
targets=()
while (($# > 0)); do
  case "$1" in
    --seconds-per-target) seconds="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --build-dir) build="$(realpath -m "$2")"; shift 2 ;;
    --update-corpus) update_corpus=1; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
    *) targets+=("$1"); shift ;;
  esac
done
if ((${#targets[@]} == 0)); then
  for folder in "$repo"/fuzz/corpus/*/; do targets+=("$(basename "$folder")"); done
fi
[[ "$build" == "$repo/build" ]] && { echo "fuzz.sh: $build is the gcc build; choose another folder" >&2; exit 2; }

# shellcheck source=sanitizers/builds.sh
source "$repo/scripts/sanitizers/builds.sh"
# Only what the fuzz targets need is built here (core, io, synth, bow, the test-support library and the targets); in a
# folder where scripts/sanitize.sh asan ran, that is all built already. -O1 with line tables for the stack traces.
hoidslam_configure_asan "$repo" "$build"
cmake --build "$build" --target "${targets[@]/%/_fuzzer}" -j "$(nproc)"

# The targets write every input to a scratch file; in memory (/dev/shm) they run about five times faster than
# on disk. The folder also collects what a crashed run could not remove.
scratch_parent=/dev/shm
[[ -d "$scratch_parent" && -w "$scratch_parent" ]] || scratch_parent="$build"
TMPDIR="$(mktemp -d "$scratch_parent/hoidslam-fuzz.XXXXXX")"
export TMPDIR
# Stack traces with file and line (llvm-14 ships the symbolizer under its own name only).
[[ -x /usr/lib/llvm-14/bin/llvm-symbolizer ]] && export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
trap 'rm -rf "$TMPDIR"' EXIT
mkdir -p "$build/logs"
# fuzz <target>: runs one target; its exit status says whether it found something.
fuzz() {
  local target="$1" status=0
  local new_corpus="$build/new-corpus/$target" findings="$build/findings/$target" log="$build/logs/$target.log"
  mkdir -p "$new_corpus" "$findings"
  # The first folder receives the new inputs; the repository's corpus and regressions are only read.
  local inputs=("$new_corpus" "$repo/fuzz/corpus/$target")
  [[ -d "$repo/fuzz/regressions/$target" ]] && inputs+=("$repo/fuzz/regressions/$target")
  "$build/fuzz/${target}_fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings/" "${inputs[@]}" >"$log" 2>&1 || status=$?
  local runs
  runs="$(grep -ao 'Done [0-9]* runs in [0-9]* second' "$log" | tail -n 1 || true)"
  if ((status == 0)); then
    echo "fuzz.sh: $target: no finding (${runs:-see $log})"
  else
    echo "fuzz.sh: $target: FINDING (exit $status), log $log, input(s) in $findings:" >&2
    grep -a -m 3 -E 'ERROR: |runtime error|uncaught exception|what\(\)' "$log" >&2 || true
  fi
  if ((update_corpus)); then
    "$build/fuzz/${target}_fuzzer" -merge=1 -use_counters=0 "$repo/fuzz/corpus/$target" "$new_corpus" >>"$log" 2>&1
  fi
  return "$status"
}

# Up to $jobs targets at a time; each one's result is collected in target order.
failed=()
pids=()
for i in "${!targets[@]}"; do
  if ((i >= jobs)); then
    wait "${pids[i - jobs]}" || failed+=("${targets[i - jobs]}")
  fi
  fuzz "${targets[i]}" &
  pids+=("$!")
done
for ((i = ${#targets[@]} - jobs < 0 ? 0 : ${#targets[@]} - jobs; i < ${#targets[@]}; i++)); do
  wait "${pids[i]}" || failed+=("${targets[i]}")
done

if ((${#failed[@]} > 0)); then
  echo "fuzz.sh: findings in ${failed[*]}" >&2
  exit 1
fi
