#pragma once
// Line-oriented text files in the TUM style: '#' comment lines and blank lines are skipped, fields are
// separated by spaces, tabs or commas. Used by every TUM list reader so they all tolerate the same things.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string_view>
#include <vector>

namespace hoidslam::io {

// Calls `on_line(line_number, fields)` for every data line of `path` (line numbers count from 1).
// Throws InputError naming the file when it cannot be opened.
void ForEachDataLine(const std::filesystem::path& path,
                     const std::function<void(std::size_t, const std::vector<std::string_view>&)>& on_line);

// Parses a whole field as a finite number; throws InputError "<file>:<line>: ..." otherwise.
double ParseDouble(std::string_view field, const std::filesystem::path& path, std::size_t line_number);

}  // namespace hoidslam::io
