# Flags of the fuzz build (HOIDSLAM_BUILD_FUZZERS=ON, scripts/fuzz.sh): every module is compiled with
# libFuzzer's coverage instrumentation and with AddressSanitizer and UndefinedBehaviorSanitizer, and a sanitizer
# report aborts the run, so libFuzzer records it as a crash. Only clang has libFuzzer (Debian: clang-14 with
# libclang-rt-14-dev).
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "HOIDSLAM_BUILD_FUZZERS needs clang (e.g. -DCMAKE_CXX_COMPILER=clang++-14), "
                      "not ${CMAKE_CXX_COMPILER_ID}")
endif()
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined)
