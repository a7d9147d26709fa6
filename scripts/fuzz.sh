#!/usr/bin/env bash
# Builds hoidslam's fuzz targets with clang (libFuzzer, AddressSanitizer, UndefinedBehaviorSanitizer) in a
# folder of their own and runs each for a fixed time on its corpus and regressions. Fails when any target
# finds a crash, a sanitizer report, a broken error contract or a time-out. docs/fuzzing.md explains the targets.
#
#   scripts/fuzz.sh [--seconds-per-target N] [--build-dir DIR] [--update-corpus] [target...]
#
#   --seconds-per-target N  run each target N seconds (default 60)
#   --build-dir DIR         the clang build (default: build-fuzz in the checkout; never the gcc build/)
#   --update-corpus         afterwards, add to fuzz/corpus/<target> the inputs of DIR/new-corpus/<target> that
#                           reach code it does not (-merge=1 on edges only, which keeps the corpus small); by
#                           default new inputs stay in DIR/new-corpus/<target>
#   target...               some of the folders of fuzz/corpus: settings tum_lists associations trajectory
#                           detections scenario (default: all)
#
# Findings go to DIR/findings/<target>/ (crash-*, timeout-*, oom-*), each run's log to DIR/logs/<target>.log.
# To replay one input: DIR/fuzz/<target>_fuzzer <file>. On a shared machine, run it niced: nice -n 10 scripts/fuzz.sh
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$repo/build-fuzz"
seconds=60
update_corpus=0
targets=()
while (($# > 0)); do
  case "$1" in
    --seconds-per-target) seconds="$2"; shift 2 ;;
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

compiler="$(command -v clang++-14 || command -v clang++ || true)"
[[ -n "$compiler" ]] || { echo "fuzz.sh: clang++ not found; scripts/setup.sh installs clang-14" >&2; exit 2; }

# Only core, io, synth, the test-support library and the fuzz targets are built. The build type "Fuzz" keeps
# assertions on and optimises little, as is usual for fuzzing (-O1, line tables for the stack traces).
cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Fuzz -DCMAKE_CXX_FLAGS_FUZZ="-O1 -gline-tables-only" \
  -DCMAKE_CXX_COMPILER="$compiler" -DHOIDSLAM_BUILD_FUZZERS=ON -DHOIDSLAM_BUILD_TESTS=OFF \
  -DHOIDSLAM_BUILD_BENCHMARKS=OFF >/dev/null
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
failed=()
for target in "${targets[@]}"; do
  new_corpus="$build/new-corpus/$target"
  findings="$build/findings/$target"
  log="$build/logs/$target.log"
  mkdir -p "$new_corpus" "$findings"
  # The first folder receives the new inputs; the repository's corpus and regressions are only read.
  inputs=("$new_corpus" "$repo/fuzz/corpus/$target")
  [[ -d "$repo/fuzz/regressions/$target" ]] && inputs+=("$repo/fuzz/regressions/$target")
  status=0
  "$build/fuzz/${target}_fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$findings/" "${inputs[@]}" >"$log" 2>&1 || status=$?
  runs="$(grep -ao 'Done [0-9]* runs in [0-9]* second' "$log" | tail -n 1 || true)"
  if ((status == 0)); then
    echo "fuzz.sh: $target: no finding (${runs:-see $log})"
  else
    failed+=("$target")
    echo "fuzz.sh: $target: FINDING (exit $status), log $log, input(s) in $findings:" >&2
    grep -a -m 3 -E 'ERROR: |runtime error|uncaught exception|what\(\)' "$log" >&2 || true
  fi
  if ((update_corpus)); then
    "$build/fuzz/${target}_fuzzer" -merge=1 -use_counters=0 "$repo/fuzz/corpus/$target" "$new_corpus" >>"$log" 2>&1
  fi
done

if ((${#failed[@]} > 0)); then
  echo "fuzz.sh: findings in ${failed[*]}" >&2
  exit 1
fi
