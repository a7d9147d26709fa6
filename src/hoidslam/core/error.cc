#include "hoidslam/core/error.h"

#include <fmt/format.h>

namespace hoidslam::core {

InputError InputError::InFile(const std::filesystem::path& file, const std::string& what) {
  return InputError(fmt::format("{}: {}", file.string(), what));
}

InputError InputError::AtLine(const std::filesystem::path& file, std::size_t line, const std::string& what) {
  return InputError(fmt::format("{}:{}: {}", file.string(), line, what));
}

InputError InputError::ForParameter(const std::string& name, const std::string& what) {
  return InputError(fmt::format("parameter {}: {}", name, what));
}

}  // namespace hoidslam::core
