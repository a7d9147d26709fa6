#!/usr/bin/env bash
# Builds hoidslam with clang's sanitizers and runs its tests under them.
#
#   scripts/sanitize.sh asan     AddressSanitizer + UndefinedBehaviorSanitizer (leaks included): the whole test suite
#   scripts/sanitize.sh tsan     ThreadSanitizer: the tests labelled `threaded` (ctest -L threaded), those that run
#                                hoidslam's own threads (THREADED_TESTS in cmake/HoidslamModule.cmake)
#   scripts/sanitize.sh [all]    both: builds the two, then runs the two test runs at once, the TSan tests on one
#                                CPU and the ASan suite on all (with one CPU, one after the other). CI runs this
#                                after scripts/test.sh.
#
# Further arguments go to ctest, e.g. `scripts/sanitize.sh tsan -R CliRun`. Build folders: build-asan/ and
# build-tsan/ in the checkout ($HOIDSLAM_ASAN_BUILD_DIR, $HOIDSLAM_TSAN_BUILD_DIR); the builds are incremental.
# Needs the packages scripts/setup.sh installs (clang-14 with its sanitizer runtimes, lld-14, llvm-14).
#
# How the builds are configured is in scripts/sanitizers/builds.sh: clang, a unity build, lld, -O1 with line
# tables, no benchmark programs. The ASan build also makes the libFuzzer targets, so scripts/fuzz.sh (which uses
# the same folder) builds nothing more; the TSan build makes only the executables its tests run. The TSan tests run
# on one CPU, two at a time (see below); the ASan tests on all CPUs, as many at a time as there are CPUs.
#
# Any sanitizer report fails the run, whichever process wrote it: a test, or a hoidslam process a test started
# (whose exit status the test may not look at). Reports are written to <build>/sanitizer-reports/ and printed at
# the end. Undefined behaviour aborts at once (-fno-sanitize-recover). Findings in third-party libraries are
# suppressed in scripts/sanitizers/, each entry with the reason it is not hoidslam's.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
which="${1:-all}"
(($# > 0)) && shift
case "$which" in
  asan | tsan | all) ;;
  *)
    echo "usage: scripts/sanitize.sh [asan|tsan|all] [ctest arguments...]" >&2
    exit 2
    ;;
esac
suppressions="$repo/scripts/sanitizers"
# shellcheck source=sanitizers/builds.sh
source "$suppressions/builds.sh"
# Stack traces with file and line: llvm-14 ships llvm-symbolizer under its own folder only.
[[ -d /usr/lib/llvm-14/bin ]] && export PATH="/usr/lib/llvm-14/bin:$PATH"

# build <name> <build folder> <build target>
build() {
  local name="$1" build="$2" target="$3"
  echo "== hoidslam sanitize: $name build in $build"
  "hoidslam_configure_$name" "$repo" "$build"
  cmake --build "$build" -j "$(nproc)" --target "$target"
}

# run_tests <name> <build folder> <CPU list for taskset> <tests at a time> [ctest arguments...]: the tests, then
# the reports.
run_tests() {
  local name="$1" build="$2" cpus="$3" jobs="$4"
  shift 4
  local reports="$build/sanitizer-reports"
  rm -rf "$reports"
  mkdir -p "$reports"
  local status=0
  echo "== hoidslam sanitize: $name tests on CPU $cpus"
  ASAN_OPTIONS="log_path=$reports/asan:detect_leaks=1:check_initialization_order=1" \
    UBSAN_OPTIONS="log_path=$reports/ubsan:print_stacktrace=1" \
    TSAN_OPTIONS="log_path=$reports/tsan:suppressions=$suppressions/tsan.supp:second_deadlock_stack=1" \
    taskset -c "$cpus" ctest --test-dir "$build" --output-on-failure -j "$jobs" "$@" || status=$?
  if compgen -G "$reports/*" >/dev/null; then
    for report in "$reports"/*; do
      echo "== $name report $report"
      cat "$report"
    done
    status=1
  fi
  if ((status == 0)); then
    echo "== hoidslam sanitize: $name clean"
  else
    echo "== hoidslam sanitize: $name FAILED" >&2
  fi
  return "$status"
}

asan_build="${HOIDSLAM_ASAN_BUILD_DIR:-$repo/build-asan}"
tsan_build="${HOIDSLAM_TSAN_BUILD_DIR:-$repo/build-tsan}"
# The CPUs this script may use. The TSan tests run on one CPU: OpenCV's parallel_for_ hands work to TBB's threads,
# and TBB is not instrumented, so ThreadSanitizer cannot see that parallel_for_ waits for them: it would report
# every loop body (the ORB extractor's pyramid levels) as racing with its caller. On one CPU, TBB and OpenCV start
# no threads of their own, while hoidslam's threads still run interleaved; ThreadSanitizer judges the
# synchronisation between accesses, not whether they happened at the same moment, so it checks them as it would
# on many CPUs. (OPENCV_FOR_THREADS_NUM=1 does not stop OpenCV 4.6's TBB backend from starting its threads.)
mapfile -t cpus < <(taskset -cp $$ | sed 's/.*: *//' | tr ',' '\n' |
  awk -F- '{ if (NF == 2) { for (c = $1; c <= $2; c++) print c } else print $1 }')
all_cpus="$(IFS=,; echo "${cpus[*]}")"
tsan_cpu="${cpus[0]}"
# Two at a time on one CPU too: the paced tests spend much of their time waiting for the camera's clock.
asan_jobs=$((${#cpus[@]} > 2 ? ${#cpus[@]} : 2))

status=0
case "$which" in
  asan)
    build asan "$asan_build" all
    run_tests asan "$asan_build" "$all_cpus" "$asan_jobs" "$@" || status=1
    ;;
  tsan)
    build tsan "$tsan_build" threaded_tests
    run_tests tsan "$tsan_build" "$tsan_cpu" 2 -L threaded "$@" || status=1
    ;;
  all)
    build asan "$asan_build" all
    build tsan "$tsan_build" threaded_tests
    if ((${#cpus[@]} > 1)); then
      # The TSan tests keep to one CPU; the ASan suite runs beside them on all, and has every CPU to itself once
      # the shorter TSan run ends (docs/testing.md). Each run's output is printed whole when it ends (the ASan
      # run's first), not interleaved.
      tsan_log="$(mktemp)"
      run_tests tsan "$tsan_build" "$tsan_cpu" 2 -L threaded "$@" >"$tsan_log" 2>&1 &
      tsan_pid=$!
      run_tests asan "$asan_build" "$all_cpus" "$asan_jobs" "$@" || status=1
      wait "$tsan_pid" || status=1
      cat "$tsan_log"
      rm -f "$tsan_log"
    else
      run_tests asan "$asan_build" "$all_cpus" "$asan_jobs" "$@" || status=1
      run_tests tsan "$tsan_build" "$tsan_cpu" 2 -L threaded "$@" || status=1
    fi
    ;;
esac
exit "$status"
