#!/usr/bin/env bash
# Builds hoidslam with GCC's sanitizers and runs its tests under them.
#
#   scripts/sanitize.sh asan     AddressSanitizer + UndefinedBehaviorSanitizer (leaks included): the whole test suite
#   scripts/sanitize.sh tsan     ThreadSanitizer: the tests labelled `threaded` (ctest -L threaded), those that run
#                                hoidslam's own threads (see hoidslam_threaded_tests in cmake/HoidslamModule.cmake)
#   scripts/sanitize.sh [all]    both, one after the other (CI runs this after scripts/test.sh)
#
# Further arguments go to ctest, e.g. `scripts/sanitize.sh tsan -R CliRun`. Build folders: build-asan/ and
# build-tsan/ in the checkout ($HOIDSLAM_ASAN_BUILD_DIR, $HOIDSLAM_TSAN_BUILD_DIR); the builds are incremental.
# Needs the packages scripts/setup.sh installs (GCC brings the sanitizer runtimes).
#
# Any sanitizer report fails the run, whichever process wrote it: a test, or a hoidslam process a test started
# (whose exit status the test may not look at). Reports are written to <build>/sanitizer-reports/ and printed at
# the end. Undefined behaviour aborts at once (-fno-sanitize-recover). Findings in third-party libraries are
# suppressed in scripts/sanitizers/, each entry with the reason it is not hoidslam's.
#
# To keep CI short the builds are -O1 with line tables only (-g1), without the benchmark programs, and the TSan
# build makes only the executables its tests run. The TSan tests run on one CPU (see below).
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

# sanitize <name> <build folder> <-fsanitize flags> <build target> <command prefix for ctest> [ctest arguments...]
sanitize() {
  local name="$1" build="$2" flags="$3 -fno-omit-frame-pointer" target="$4" launcher="$5"
  shift 5
  echo "== hoidslam sanitize: $name build in $build"
  cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" -DHOIDSLAM_BUILD_BENCHMARKS=OFF
  cmake --build "$build" -j "$(nproc)" --target "$target"

  local reports="$build/sanitizer-reports"
  rm -rf "$reports"
  mkdir -p "$reports"
  export ASAN_OPTIONS="log_path=$reports/asan:detect_leaks=1:check_initialization_order=1"
  export UBSAN_OPTIONS="log_path=$reports/ubsan:print_stacktrace=1"
  export TSAN_OPTIONS="log_path=$reports/tsan:suppressions=$suppressions/tsan.supp:second_deadlock_stack=1"
  echo "== hoidslam sanitize: $name tests"
  local status=0
  $launcher ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "$@" || status=$?
  if compgen -G "$reports/*" >/dev/null; then
    for report in "$reports"/*; do
      echo "== $name report $report"
      cat "$report"
    done
    status=1
  fi
  ((status == 0)) && echo "== hoidslam sanitize: $name clean"
  return "$status"
}

status=0
if [[ "$which" == asan || "$which" == all ]]; then
  sanitize asan "${HOIDSLAM_ASAN_BUILD_DIR:-$repo/build-asan}" "-fsanitize=address,undefined -fno-sanitize-recover=all" \
    all "" "$@" || status=1
fi
if [[ "$which" == tsan || "$which" == all ]]; then
  # On one CPU. OpenCV's parallel_for_ hands work to TBB's threads, and TBB is not instrumented, so ThreadSanitizer
  # cannot see that parallel_for_ waits for them: it would report every loop body (the ORB extractor's pyramid
  # levels) as racing with its caller. On one CPU, TBB and OpenCV start no threads of their own, while hoidslam's
  # threads still run interleaved; ThreadSanitizer judges the synchronisation between accesses, not whether they
  # happened at the same moment, so it checks them as it would on many CPUs.
  first_cpu="$(taskset -cp $$ | sed 's/.*: *//; s/[-,].*//')"
  sanitize tsan "${HOIDSLAM_TSAN_BUILD_DIR:-$repo/build-tsan}" "-fsanitize=thread" threaded_tests \
    "taskset -c $first_cpu" -L threaded "$@" || status=1
fi
exit "$status"
