#include "hoidslam/io/atomic_file.h"

#include <atomic>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io {

using core::InputError;

std::filesystem::path TemporarySibling(const std::filesystem::path& path) {
  // pid + a process-wide counter keep concurrent writers (threads or processes) apart.
  static std::atomic<unsigned> counter{0};
  const std::string name =
      fmt::format(".{}.tmp-{}-{}{}", path.stem().string(), ::getpid(), counter++, path.extension().string());
  return path.parent_path() / name;
}

AtomicFile::AtomicFile(std::filesystem::path path)
    : path_(std::move(path)), temporary_path_(TemporarySibling(path_)) {
  stream_.open(temporary_path_, std::ios::binary | std::ios::trunc);
  if (!stream_) throw InputError::InFile(path_, "cannot open for writing (does the folder exist and is it writable?)");
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  stream_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_path_, ignored);
}

void AtomicFile::Commit() {
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  stream_.close();
  if (!written || stream_.fail()) throw InputError::InFile(path_, "write failed (disk full?)");
  std::error_code error;
  std::filesystem::rename(temporary_path_, path_, error);
  if (error) throw InputError::InFile(path_, "cannot move the finished file into place: " + error.message());
  committed_ = true;
}

void WriteImageAtomically(const std::filesystem::path& path, const cv::Mat& image) {
  const std::filesystem::path temporary = TemporarySibling(path);
  bool written = false;
  try {
    written = cv::imwrite(temporary.string(), image);
  } catch (const cv::Exception& e) {
    std::filesystem::remove(temporary);
    throw InputError::InFile(path, std::string("cannot encode image: ") + e.what());
  }
  std::error_code error;
  if (written) std::filesystem::rename(temporary, path, error);
  if (!written || error) {
    std::filesystem::remove(temporary, error);
    throw InputError::InFile(path, "cannot write image (does the folder exist and is it writable?)");
  }
}

}  // namespace hoidslam::io
