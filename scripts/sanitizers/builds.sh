# Sourced by scripts/sanitize.sh and scripts/fuzz.sh: how the sanitizer builds are configured, so that both scripts
# configure the ASan build identically and share one build folder (the fuzz targets are part of it).
#
# Both builds use clang 14 (about 30% less compile time than GCC 12 for the same -O1 sanitizer build; libFuzzer
# exists only for clang), a unity build (CMAKE_UNITY_BUILD: each target's sources compiled in batches, see
# CMakeLists.txt), the lld linker, -O1 and line tables only (-gline-tables-only, enough for file and line in every
# report), no benchmark programs, no Python module and no test of the installed package (an instrumented
# libhoidslam.so cannot be loaded by an uninstrumented python3 or linked into the example program).

hoidslam_clang() {
  command -v clang++-14 || command -v clang++ || {
    echo "clang++ not found; scripts/setup.sh installs clang-14" >&2
    return 1
  }
}

# hoidslam_configure_sanitizer_build <repo> <build folder> <-fsanitize flags> [more cmake arguments...]
hoidslam_configure_sanitizer_build() {
  local repo="$1" build="$2" flags="$3 -fno-omit-frame-pointer" compiler
  shift 3
  compiler="$(hoidslam_clang)" || return 2
  cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$compiler" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags -fuse-ld=lld" -DCMAKE_UNITY_BUILD=ON \
    -DHOIDSLAM_BUILD_BENCHMARKS=OFF -DHOIDSLAM_BUILD_PYTHON=OFF -DHOIDSLAM_TEST_INSTALL=OFF "$@" >/dev/null
}

# The ASan build: AddressSanitizer + UndefinedBehaviorSanitizer (every report aborts) for the whole test suite, and
# with them the libFuzzer targets of fuzz/ (HOIDSLAM_BUILD_FUZZERS: core, io, synth and bow also carry libFuzzer's
# coverage counters; see cmake/HoidslamFuzzing.cmake).
hoidslam_configure_asan() {
  hoidslam_configure_sanitizer_build "$1" "$2" "-fsanitize=address,undefined -fno-sanitize-recover=all" \
    -DHOIDSLAM_BUILD_FUZZERS=ON
}

# The TSan build: ThreadSanitizer, for the tests labelled `threaded`.
hoidslam_configure_tsan() {
  hoidslam_configure_sanitizer_build "$1" "$2" "-fsanitize=thread" -DHOIDSLAM_BUILD_FUZZERS=OFF
}
