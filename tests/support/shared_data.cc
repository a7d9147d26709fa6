#include "support/shared_data.h"

#include <cstdlib>

namespace hoidslam::testing {

std::filesystem::path SharedDir() {
  if (const char* env = std::getenv("HOIDSLAM_SHARED_DIR"); env != nullptr && *env != '\0') return env;
  return HOIDSLAM_SHARED_DIR_DEFAULT;
}

std::filesystem::path SharedPath(const std::string& relative) { return SharedDir() / relative; }

bool InCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

}  // namespace hoidslam::testing
