#pragma once
// Small text files for tests: written and read back byte for byte (no newline translation), so a test can
// also write CRLF or malformed content exactly.

#include <filesystem>
#include <string>

namespace hoidslam::testing {

void WriteText(const std::filesystem::path& path, const std::string& text);

// The whole file; empty when it cannot be opened.
std::string ReadText(const std::filesystem::path& path);

}  // namespace hoidslam::testing
