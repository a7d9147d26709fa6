#pragma once
// The YAML that ORB-SLAM3 settings files are written in, read by hoidslam itself. cv::FileStorage (OpenCV 4.6)
// crashes or never returns on some malformed files (docs/fuzzing.md), and a user's typo must get an error, so
// this reader takes the part of YAML that settings files use and refuses the rest, naming the line:
//
//   %YAML:1.0                      the first line (a UTF-8 byte-order mark before it is skipped)
//   ---                            optional, before the first key; "..." ends the document
//   # a comment                    on a line of its own, or after a value
//   Camera.fx: 535.4               a key and its value, one per line
//   HOID.dynamicClasses: [a, "b"]  a list of values, which may run over several lines
//   Tbc: !!opencv-matrix           a tag is skipped; a key without a value on its line takes the indented
//      rows: 4                     block below it: a mapping of its own (as OpenCV writes matrices) or
//      data: [1, 0, 0, 0, ...]     "- value" lines (a list)
//
// Values are "double-quoted" (escapes \\ \" \/ \n \r \t), 'single-quoted' ('' is a quote) or plain. A plain value
// that is a whole number is an integer; one that is a decimal number a real (also YAML's .inf, -.inf, .nan);
// anything else is text. Flow mappings, anchors, aliases, block scalars, lists of lists and values over several
// lines (other than lists) are syntax errors, as are repeated keys.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hoidslam::io::yaml {

struct Entry;

struct Value {
  enum class Kind { kNone, kInteger, kReal, kText, kList, kMapping };

  Kind kind = Kind::kNone;    // kNone: a key with nothing after it
  std::size_t line = 0;       // the line the value begins on, counting from 1
  std::int64_t integer = 0;   // kInteger
  double real = 0.0;          // kReal, and kInteger's value as a double
  std::string text;           // kText
  std::vector<Value> items;   // kList
  std::vector<Entry> entries; // kMapping, in the file's order

  // The value of `key` in a mapping; nullptr when the key is absent (or this is not a mapping).
  const Value* Find(std::string_view key) const;
};

struct Entry {
  std::string key;
  Value value;
};

// Reads `text`, a settings file's contents, as a mapping (empty when the file has only its header). `path` names
// the file in errors. Throws core::InputError: "<path>: not a settings file: ..." when the first line is not
// %YAML, "<path>:<line>: ..." for anything else the reader refuses.
Value Parse(std::string_view text, const std::filesystem::path& path);

}  // namespace hoidslam::io::yaml
