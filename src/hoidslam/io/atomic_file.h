#pragma once
// Output files are complete or absent: everything is written to a temporary sibling and renamed into place
// only when the writer commits. A writer destroyed without Commit() (an exception, an interrupted run)
// removes its temporary file and leaves any earlier file at the path untouched.

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace hoidslam::io {

class AtomicFile {
 public:
  // Opens a temporary file beside `path`; throws InputError naming `path` when the folder is not writable.
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return stream_; }
  const std::filesystem::path& path() const { return path_; }

  // Flushes, checks that every write succeeded, and renames the temporary file to path().
  void Commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_path_;
  std::ofstream stream_;
  bool committed_ = false;
};

// A folder that appears complete or not at all: everything is written into a temporary sibling
// "<path>.partial-<pid>", which Commit() renames to `path`. An existing folder at `path` is replaced only then:
// it is renamed aside to "<path>.old-<pid>", the new one renamed in, and the old one removed, so `path` holds
// either the old folder or the new one at every moment. Destroyed without Commit(), the temporary folder is
// removed and `path` is untouched. A staging folder "<path>.partial-<pid>" that a killed job left (its pid no longer
// running) is removed when the next AtomicFolder for `path` is made: stale_removed() lists them.
class AtomicFolder {
 public:
  // `path` is taken as io::NormalFolder(path). Throws InputError naming `parameter` when `path` is a file, is the
  // working directory or holds it (replacing it would remove the folder the program runs in), or exists, is not
  // empty and `replace` is false (`replace_hint` then says how to replace it, e.g. "use --force").
  AtomicFolder(const std::filesystem::path& path, bool replace, const std::string& parameter,
               const std::string& replace_hint);
  ~AtomicFolder();
  AtomicFolder(const AtomicFolder&) = delete;
  AtomicFolder& operator=(const AtomicFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  const std::filesystem::path& temporary() const { return temporary_; }  // write here
  const std::vector<std::filesystem::path>& stale_removed() const { return stale_removed_; }

  void Commit();

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  std::vector<std::filesystem::path> stale_removed_;
  bool committed_ = false;
};

// For a file a long job writes at its end (hoidslam run --save-map): throws InputError naming `parameter` and `path`
// unless a file can be written at `path` now: it is not a folder, and its folder exists and takes a new file (a
// temporary one, created beside `path` and removed again). An existing file at `path` is left as it is.
void CheckWritableFile(const std::filesystem::path& path, const std::string& parameter);

// A temporary name beside `path` that keeps its extension (so encoders can tell the format by name).
std::filesystem::path TemporarySibling(const std::filesystem::path& path);

// Encodes `image` by the extension of `path` (cv::imwrite) and renames it into place; throws on failure.
void WriteImageAtomically(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace hoidslam::io
