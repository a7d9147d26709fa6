#include "hoidslam/core/shipped_dir.h"

#include <dlfcn.h>

#include <array>
#include <system_error>

namespace hoidslam::core {
namespace {

// <prefix>/share/hoidslam of a binary installed into <prefix>/bin, <prefix>/lib or <prefix>/lib/<multiarch>,
// when it holds the settings; else empty.
std::filesystem::path InstalledBeside(const std::filesystem::path& binary) {
  std::error_code error;
  std::filesystem::path prefix = std::filesystem::canonical(binary, error).parent_path();
  if (error) return {};
  for (int up = 0; up < 2; ++up) {
    prefix = prefix.parent_path();
    const std::filesystem::path shipped = prefix / "share" / "hoidslam";
    if (std::filesystem::is_directory(shipped / "config", error)) return shipped;
  }
  return {};
}

}  // namespace

std::filesystem::path ShippedDir() {
  // The shared library this code is in (libhoidslam.so, loaded by a program or by Python), else the program.
  Dl_info info{};
  const bool in_library = dladdr(reinterpret_cast<const void*>(&ShippedDir), &info) != 0 && info.dli_fname != nullptr;
  const std::array<std::filesystem::path, 2> binaries = {in_library ? info.dli_fname : "", "/proc/self/exe"};
  for (const std::filesystem::path& binary : binaries) {
    if (binary.empty()) continue;
    if (std::filesystem::path shipped = InstalledBeside(binary); !shipped.empty()) return shipped;
  }
  return HOIDSLAM_SOURCE_DIR;
}

std::filesystem::path WebDir() {
  // The bundle, not index.html: in the build tree ShippedDir is the source folder, whose web/ has the sources only.
  const std::filesystem::path installed = ShippedDir() / "web";
  if (std::filesystem::exists(installed / "viewer.js")) return installed;
  return HOIDSLAM_BUILD_WEB_DIR;
}

}  // namespace hoidslam::core
