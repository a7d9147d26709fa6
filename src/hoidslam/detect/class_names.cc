#include "hoidslam/detect/class_names.h"

#include <fstream>

#include "hoidslam/core/error.h"

namespace hoidslam::detect {

const std::vector<std::string>& CocoClassNames() {
  static const std::vector<std::string> kNames = {
      "person",         "bicycle",    "car",           "motorcycle",    "airplane",     "bus",           "train",
      "truck",          "boat",       "traffic light", "fire hydrant",  "stop sign",    "parking meter", "bench",
      "bird",           "cat",        "dog",           "horse",         "sheep",        "cow",           "elephant",
      "bear",           "zebra",      "giraffe",       "backpack",      "umbrella",     "handbag",       "tie",
      "suitcase",       "frisbee",    "skis",          "snowboard",     "sports ball",  "kite",          "baseball bat",
      "baseball glove", "skateboard", "surfboard",     "tennis racket", "bottle",       "wine glass",    "cup",
      "fork",           "knife",      "spoon",         "bowl",          "banana",       "apple",         "sandwich",
      "orange",         "broccoli",   "carrot",        "hot dog",       "pizza",        "donut",         "cake",
      "chair",          "couch",      "potted plant",  "bed",           "dining table", "toilet",        "tv",
      "laptop",         "mouse",      "remote",        "keyboard",      "cell phone",   "microwave",     "oven",
      "toaster",        "sink",       "refrigerator",  "book",          "clock",        "vase",          "scissors",
      "teddy bear",     "hair drier", "toothbrush"};
  return kNames;
}

std::vector<std::string> ReadClassNames(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw core::InputError::InFile(path, "cannot open the class names file");
  std::vector<std::string> names;
  std::size_t first_blank_line = 0;  // line number of the first blank line not yet followed by a name
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t begin = line.find_first_not_of(" \t\r");
    if (begin == std::string::npos) {
      if (first_blank_line == 0) first_blank_line = number;
      continue;
    }
    if (first_blank_line != 0) {
      throw core::InputError::AtLine(path, first_blank_line, "blank line inside the class names list");
    }
    const std::size_t end = line.find_last_not_of(" \t\r");
    names.push_back(line.substr(begin, end - begin + 1));
  }
  if (in.bad()) throw core::InputError::InFile(path, "read error");
  if (names.empty()) throw core::InputError::InFile(path, "no class names (expected one name per line)");
  return names;
}

}  // namespace hoidslam::detect
