#include "hoidslam/io/files.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <iterator>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <openssl/sha.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io {

namespace fs = std::filesystem;
using core::InputError;

fs::path NormalFolder(const fs::path& folder) {
  fs::path normal = fs::absolute(folder).lexically_normal();
  return normal.has_filename() ? normal : normal.parent_path();
}

bool IsImageFile(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg";
}

std::vector<fs::path> ImagesIn(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw InputError::InFile(folder, "image folder does not exist");
  std::vector<fs::path> images;
  for (const fs::directory_entry& item : fs::directory_iterator(folder)) {
    if (item.is_regular_file() && IsImageFile(item.path())) images.push_back(item.path());
  }
  std::sort(images.begin(), images.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  return images;
}

cv::Mat ReadImage(const fs::path& path, int flags, std::string_view what) {
  if (!fs::is_regular_file(path)) throw InputError::InFile(path, fmt::format("{} image does not exist", what));
  cv::Mat image;
  try {
    image = cv::imread(path.string(), flags);
  } catch (const cv::Exception& e) {
    throw InputError::InFile(path, fmt::format("cannot decode the {} image: {}", what, e.err));
  }
  if (image.empty()) {
    throw InputError::InFile(path, fmt::format("cannot decode the {} image: expected a PNG or JPEG file, found a "
                                               "corrupt, truncated or unsupported one",
                                               what));
  }
  return image;
}

std::vector<std::uint8_t> ReadBinaryFile(const fs::path& path, std::string_view what) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    throw InputError::InFile(path, fmt::format("{} does not exist or is not a file", what));
  }
  std::ifstream file(path, std::ios::binary);
  std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
  if (!file.good() && !file.eof()) throw InputError::InFile(path, fmt::format("cannot read the {}", what));
  return bytes;
}

std::string FileSha256(const fs::path& path, std::string_view what) {
  const std::vector<std::uint8_t> bytes = ReadBinaryFile(path, what);
  std::array<unsigned char, SHA256_DIGEST_LENGTH> digest{};
  SHA256(bytes.data(), bytes.size(), digest.data());
  std::string hex;
  for (const unsigned char byte : digest) hex += fmt::format("{:02x}", byte);
  return hex;
}

}  // namespace hoidslam::io
