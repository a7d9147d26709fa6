#include "hoidslam/io/text_lines.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io {

using core::InputError;

void ForEachDataLine(const std::filesystem::path& path,
                     const std::function<void(std::size_t, const std::vector<std::string_view>&)>& on_line) {
  if (!std::filesystem::is_regular_file(path)) throw InputError::InFile(path, "no such file");
  std::ifstream in(path);
  if (!in) throw InputError::InFile(path, "cannot open for reading");
  std::string line;
  std::vector<std::string_view> fields;
  for (std::size_t line_number = 1; std::getline(in, line); ++line_number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // files written on Windows
    fields.clear();
    std::size_t start = 0;
    while (start < line.size()) {
      const std::size_t begin = line.find_first_not_of(" \t,", start);
      if (begin == std::string::npos) break;
      const std::size_t end = std::min(line.find_first_of(" \t,", begin), line.size());
      fields.emplace_back(line.data() + begin, end - begin);
      start = end;
    }
    if (fields.empty() || fields.front().front() == '#') continue;
    on_line(line_number, fields);
  }
  if (in.bad()) throw InputError::InFile(path, "read error");
}

double ParseDouble(std::string_view field, const std::filesystem::path& path, std::size_t line_number) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size() || !std::isfinite(value)) {
    throw InputError::AtLine(path, line_number, fmt::format("'{}' is not a number", field));
  }
  return value;
}

}  // namespace hoidslam::io
