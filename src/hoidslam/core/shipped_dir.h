#pragma once
// Where the files hoidslam ships are: the settings (config/) and the bag-of-words vocabulary (data/vocabulary/).

#include <filesystem>

namespace hoidslam::core {

// <prefix>/share/hoidslam when the program or library this code is in was installed into <prefix> (bin/ or lib/
// beside share/), else the source tree the build came from. The installed folder mirrors the source tree's
// layout, so the same relative paths hold in both.
std::filesystem::path ShippedDir();

}  // namespace hoidslam::core
