#pragma once
// Where the files hoidslam ships are: the settings (config/), the bag-of-words vocabulary (data/vocabulary/) and
// the viewer's page (web/).

#include <filesystem>

namespace hoidslam::core {

// <prefix>/share/hoidslam when the program or library this code is in was installed into <prefix> (bin/ or lib/
// beside share/), else the source tree the build came from. The installed folder mirrors the source tree's
// layout, so the same relative paths hold in both.
std::filesystem::path ShippedDir();

// The viewer's page bundled by the build (index.html, viewer.js, viewer.css; docs/viewer.md): ShippedDir()/web when
// installed, else the build folder's web/. The live viewer serves it; the run report inlines it.
std::filesystem::path WebDir();

}  // namespace hoidslam::core
