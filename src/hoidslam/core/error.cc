#include "hoidslam/core/error.h"

#include <fmt/format.h>

namespace hoidslam::core {
namespace {

std::string OneLine(const std::string& text) {
  std::string line;
  line.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') {
      line += "\\n";
    } else if (c == '\r') {
      line += "\\r";
    } else if ((byte < 0x20 && c != '\t') || byte == 0x7F) {
      line += fmt::format("\\x{:02x}", byte);
    } else {
      line += c;
    }
  }
  return line;
}

}  // namespace

InputError::InputError(const std::string& what) : Error(OneLine(what)) {}

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
