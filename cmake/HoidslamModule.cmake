# hoidslam_module(<name>
#   SOURCES  <files...>          library sources of src/hoidslam/<name>/
#   DEPENDS  <modules...>        other hoidslam modules this one may use (DESIGN.md layering)
#   LIBS     <targets...>        third-party targets
#   TESTS    <files...>          GoogleTest sources, built into <name>_tests and registered with CTest
#   THREADED_TESTS <files...>    tests that run hoidslam's own threads, built into <name>_threaded_tests: see
#                                hoidslam_threaded_tests below
#   BENCHMARKS <files...>)       Google Benchmark sources, built into <name>_bench
#
# Each module is its own static library `hoidslam_<name>`, so the layering in DESIGN.md is enforced by the
# link graph: a module can only include what it DEPENDS on.
function(hoidslam_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPENDS;LIBS;TESTS;THREADED_TESTS;BENCHMARKS" ${ARGN})
  set(target hoidslam_${name})
  add_library(${target} STATIC ${M_SOURCES})
  add_library(hoidslam::${name} ALIAS ${target})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR}/src)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  foreach(dep IN LISTS M_DEPENDS)
    target_link_libraries(${target} PUBLIC hoidslam_${dep})
  endforeach()
  target_link_libraries(${target} PUBLIC ${M_LIBS})
  if(HOIDSLAM_BUILD_FUZZERS AND name IN_LIST HOIDSLAM_FUZZ_COVERAGE_MODULES)
    target_compile_options(${target} PRIVATE ${HOIDSLAM_FUZZ_COVERAGE_FLAGS})  # cmake/HoidslamFuzzing.cmake
  endif()

  if(HOIDSLAM_BUILD_TESTS AND M_TESTS)
    hoidslam_test_executable(${name}_tests ${target} ${M_TESTS})
    gtest_discover_tests(${name}_tests TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 60)
  endif()
  if(HOIDSLAM_BUILD_TESTS AND M_THREADED_TESTS)
    hoidslam_test_executable(${name}_threaded_tests ${target} ${M_THREADED_TESTS})
    hoidslam_threaded_tests(${name}_threaded_tests TEST_PREFIX "${name}.")
  endif()

  if(HOIDSLAM_BUILD_BENCHMARKS AND M_BENCHMARKS)
    add_executable(${name}_bench ${M_BENCHMARKS})
    target_compile_options(${name}_bench PRIVATE -Wall -Wextra)
    target_link_libraries(${name}_bench PRIVATE ${target} hoidslam_test_support benchmark::benchmark_main)
  endif()
endfunction()

# hoidslam_test_executable(<executable> <module library> <GoogleTest sources...>): a module's test executable.
function(hoidslam_test_executable executable library)
  add_executable(${executable} ${ARGN})
  target_compile_options(${executable} PRIVATE -Wall -Wextra)
  target_link_libraries(${executable} PRIVATE ${library} hoidslam_test_support GTest::gtest_main GTest::gmock)
endfunction()

# hoidslam_threaded_tests(<test executable> TEST_PREFIX <prefix> [PROPERTIES <CTest test properties...>])
#
# Registers a test executable whose tests run more than one of hoidslam's threads (tracking and local mapping, the
# detector thread, the paced replay's decoders, the synthetic sequence writer's workers), directly or through the
# hoidslam binary it starts. Its tests get the CTest label `threaded`, and the target `threaded_tests` builds it:
# scripts/sanitize.sh tsan builds that target and runs `ctest -L threaded` under ThreadSanitizer. A module lists
# the test files of its threaded code as THREADED_TESTS; the other tests stay out of the ThreadSanitizer run, which
# is many times slower than the others and has one CPU (docs/testing.md).
function(hoidslam_threaded_tests target)
  cmake_parse_arguments(T "" "TEST_PREFIX" "PROPERTIES" ${ARGN})
  gtest_discover_tests(${target} TEST_PREFIX "${T_TEST_PREFIX}" DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS threaded ${T_PROPERTIES})
  add_dependencies(threaded_tests ${target})
endfunction()
