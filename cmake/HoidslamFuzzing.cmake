# Flags of the fuzz build (HOIDSLAM_BUILD_FUZZERS=ON; scripts/sanitize.sh asan and scripts/fuzz.sh share it): every
# target is compiled with AddressSanitizer and UndefinedBehaviorSanitizer, and a sanitizer report aborts the run,
# so libFuzzer records it as a crash. libFuzzer's coverage instrumentation (-fsanitize=fuzzer-no-link) goes only
# into what the fuzz targets reach: the modules listed in HOIDSLAM_FUZZ_COVERAGE_MODULES (hoidslam_module adds it),
# the test-support library and the targets themselves. The rest of the build (the other modules, the tests) is an
# ordinary ASan+UBSan build, so the same folder also runs the whole test suite without the cost of coverage
# counters in the SLAM code (the sanitizer runtime has no-op defaults for the coverage callbacks in programs
# without libFuzzer). Only clang has libFuzzer (Debian: clang-14 with libclang-rt-14-dev).
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "HOIDSLAM_BUILD_FUZZERS needs clang (e.g. -DCMAKE_CXX_COMPILER=clang++-14), "
                      "not ${CMAKE_CXX_COMPILER_ID}")
endif()
add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined)
set(HOIDSLAM_FUZZ_COVERAGE_MODULES core io synth bow)
set(HOIDSLAM_FUZZ_COVERAGE_FLAGS -fsanitize=fuzzer-no-link)
