#pragma once
// Where tests and benchmarks find ../shared (real TUM frames, photos, the test detector model).
//
// The folder is $HOIDSLAM_SHARED_DIR when set, else the path configured at build time (the `shared` folder
// beside the checkout). Outside CI a missing file skips the test with a message; in CI (CI=true) it fails.

#include <filesystem>
#include <string>

namespace hoidslam::testing {

// The shared folder, as configured; not checked for existence.
std::filesystem::path SharedDir();

// SharedDir() / relative.
std::filesystem::path SharedPath(const std::string& relative);

// True when running under CI (environment variable CI=true), where missing shared data is an error.
bool InCi();

}  // namespace hoidslam::testing

// In a GoogleTest body: binds `var` to SharedPath(relative), or skips (fails in CI) when it does not exist.
#define HOIDSLAM_SHARED_PATH_OR_SKIP(var, relative)                                                        \
  const std::filesystem::path var = ::hoidslam::testing::SharedPath(relative);                             \
  if (!std::filesystem::exists(var)) {                                                                     \
    if (::hoidslam::testing::InCi()) FAIL() << "shared test data missing in CI: " << var;                  \
    GTEST_SKIP() << "shared test data not found: " << var << " (set HOIDSLAM_SHARED_DIR)";                 \
  }
