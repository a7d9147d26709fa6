#pragma once
// Finding and reading the files and folders users give: one place for the rules, so every command and module
// treats paths and images alike and names the file in every error.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace hoidslam::io {

// `folder` made absolute and normal, without a trailing separator, so that its filename() is the folder's name
// also for "seq/", "." or "..". Symbolic links are kept: the name is the one the user gave.
std::filesystem::path NormalFolder(const std::filesystem::path& folder);

// True for .png, .jpg and .jpeg, in any letter case.
bool IsImageFile(const std::filesystem::path& path);

// The image files of `folder`, sorted by file name; throws InputError naming the folder when it does not exist.
std::vector<std::filesystem::path> ImagesIn(const std::filesystem::path& folder);

// cv::imread with every failure (missing, unreadable, corrupt, truncated) an InputError naming the file;
// `what` says which image it is in the message ("colour", "depth", "texture").
cv::Mat ReadImage(const std::filesystem::path& path, int flags, std::string_view what);

// Every byte of the file `path`. Throws InputError naming the file when it does not exist or is not a regular file
// ("<what> does not exist or is not a file") or cannot be read ("cannot read the <what>"); `what` says which file
// it is ("map file", "vocabulary file").
std::vector<std::uint8_t> ReadBinaryFile(const std::filesystem::path& path, std::string_view what);

// The SHA-256 of the file's bytes in lower-case hex, as `sha256sum` prints it: a model's identity in summary.json.
// Throws InputError naming the file as ReadBinaryFile does.
std::string FileSha256(const std::filesystem::path& path, std::string_view what);

}  // namespace hoidslam::io
