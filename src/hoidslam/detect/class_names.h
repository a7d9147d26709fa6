#pragma once
// Class names of a detector's outputs, in model order.

#include <filesystem>
#include <string>
#include <vector>

namespace hoidslam::detect {

// The 80 COCO classes in the order COCO-trained YOLO models use, with today's names ("tv", "couch",
// "motorcycle", ...): person = 0, bottle = 39, cup = 41, chair = 56, tv = 62, laptop = 63, mouse = 64,
// keyboard = 66, book = 73. The HOID filter matches classes by these names.
const std::vector<std::string>& CocoClassNames();

// Reads one class name per line (surrounding spaces and a trailing '\r' are dropped; blank lines at the end are
// ignored). Throws InputError naming the file and line for a missing file, a blank line inside the list or an
// empty list.
std::vector<std::string> ReadClassNames(const std::filesystem::path& path);

}  // namespace hoidslam::detect
