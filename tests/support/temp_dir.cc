#include "support/temp_dir.h"

#include <stdexcept>
#include <string>

#include <stdlib.h>  // mkdtemp

namespace hoidslam::testing {

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "hoidslam-test-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create a temporary folder");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace hoidslam::testing
