#include "hoidslam/io/atomic_file.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <unistd.h>

#include "hoidslam/core/error.h"
#include "hoidslam/io/files.h"

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

void CheckWritableFile(const std::filesystem::path& path, const std::string& parameter) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error)) {
    throw InputError::ForParameter(parameter, fmt::format("{} is a folder: give the name of a file to write",
                                                          path.string()));
  }
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, error)) {
    throw InputError::ForParameter(parameter, fmt::format("cannot write {}: the folder {} does not exist",
                                                          path.string(), folder.string()));
  }
  try {
    const AtomicFile probe(path);  // removed again on destruction: never committed
  } catch (const InputError&) {
    throw InputError::ForParameter(parameter, fmt::format("cannot write {}: cannot create a file in the folder {}",
                                                          path.string(), folder.string()));
  }
}

namespace {

// "<path>.<what>-<pid>" beside `path`. The pid keeps two jobs writing the same folder apart.
std::filesystem::path FolderSibling(const std::filesystem::path& path, std::string_view what) {
  return path.parent_path() / fmt::format("{}.{}-{}", path.filename().string(), what, ::getpid());
}

// The staging folders "<path>.partial-<pid>" beside `path` that jobs no longer running left (killed before they could
// clean up), removed: nothing else writes there. A pid still running, ours included, is left alone.
std::vector<std::filesystem::path> RemoveStaleStagingFolders(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::vector<fs::path> removed;
  const std::string prefix = path.filename().string() + ".partial-";
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(path.parent_path(), error)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(prefix)) continue;
    const std::string digits = name.substr(prefix.size());
    if (digits.empty() || digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) continue;
    const auto pid = static_cast<pid_t>(std::stol(digits));
    if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    std::error_code ignored;
    if (fs::remove_all(entry.path(), ignored) > 0 && !ignored) removed.push_back(entry.path());
  }
  return removed;
}

// True when `folder` is `path` or one of its ancestors, component by component.
bool HoldsOrIs(const std::filesystem::path& folder, const std::filesystem::path& path) {
  const auto [folder_end, unused] = std::mismatch(folder.begin(), folder.end(), path.begin(), path.end());
  return folder_end == folder.end();
}

}  // namespace

AtomicFolder::AtomicFolder(const std::filesystem::path& path, bool replace, const std::string& parameter,
                           const std::string& replace_hint)
    : path_(NormalFolder(path)), temporary_(FolderSibling(path_, "partial")) {
  namespace fs = std::filesystem;
  // "/", "." or ".." would put the temporary folder inside `path`, or remove the folder the program runs in.
  // Symbolic links are resolved so that no other spelling of those folders gets through.
  std::error_code error;
  fs::path resolved = fs::weakly_canonical(path_, error);
  if (error) resolved = path_;
  const fs::path cwd = fs::current_path();
  if (HoldsOrIs(path_, cwd) || HoldsOrIs(resolved, cwd)) {
    throw InputError::ForParameter(parameter, fmt::format("{} is the working directory {} or holds it; give a "
                                                          "folder of its own",
                                                          path.string(), cwd.string()));
  }
  if (fs::exists(path_)) {
    if (!fs::is_directory(path_)) throw InputError::ForParameter(parameter, path_.string() + " is a file");
    if (!replace && !fs::is_empty(path_)) {
      throw InputError::ForParameter(parameter,
                                     fmt::format("{} exists and is not empty ({})", path_.string(), replace_hint));
    }
  }
  stale_removed_ = RemoveStaleStagingFolders(path_);
  fs::remove_all(temporary_, error);  // a leftover of an earlier job that had our pid
  if (!error) fs::create_directories(temporary_, error);
  if (error) throw InputError::InFile(path_, "cannot create the output folder: " + error.message());
}

AtomicFolder::~AtomicFolder() {
  if (committed_) return;
  std::error_code ignored;
  std::filesystem::remove_all(temporary_, ignored);
}

void AtomicFolder::Commit() {
  namespace fs = std::filesystem;
  std::error_code error;
  const bool replacing = fs::exists(path_);
  const fs::path old = FolderSibling(path_, "old");
  if (replacing) {
    fs::remove_all(old, error);  // a leftover of an earlier job that had our pid
    if (!error) fs::rename(path_, old, error);
    if (error) throw InputError::InFile(path_, "cannot move the old folder aside: " + error.message());
  }
  fs::rename(temporary_, path_, error);
  if (error) {
    std::string what = "cannot move the finished folder into place: " + error.message();
    std::error_code restore;
    if (replacing) fs::rename(old, path_, restore);
    if (restore) what += fmt::format("; the old folder is left in {} ({})", old.string(), restore.message());
    throw InputError::InFile(path_, what);
  }
  committed_ = true;
  if (replacing) {
    fs::remove_all(old, error);
    if (error) {
      throw InputError::InFile(old, "the new folder is in place, but the old one it replaced could not be removed "
                                    "from here: " + error.message());
    }
  }
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
