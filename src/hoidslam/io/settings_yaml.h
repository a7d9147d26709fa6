#pragma once
// The YAML that ORB-SLAM3 settings files are written in, read by hoidslam itself. cv::FileStorage (OpenCV 4.6)
// crashes or never returns on some malformed files (docs/fuzzing.md), and a user's typo must get an error, so
// this reader takes the part of YAML that settings files use, in time linear in the file's size, and refuses the
// rest, naming the line:
//
//   %YAML:1.0                      the first line (a UTF-8 byte-order mark before it is skipped)
//   ---                            optional, before the first key; "..." ends the document
//   # a comment                    on a line of its own, or after a value
//   Camera.fx: 535.4               a key and its value, one per line (as in OpenCV, the first ':' ends the key,
//                                  so "Viewer.PointSize:2" is read too)
//   HOID.dynamicClasses: [a, "b"]  a list of values, which may run over lines indented more than its key
//   Tbc: !!opencv-matrix           a key without a value on its line takes the indented block below it: a
//      rows: 4                     mapping of its own (as OpenCV writes matrices) or "- value" lines (a
//      data: [1, 0, 0, 0, ...]     list); a tag may open the block, and is skipped
//
// Values are "double-quoted" (escapes \\ \" \/ \n \r \t), 'single-quoted' ('' is a quote) or plain. A plain value
// that is a whole number is an integer (a leading 0, which OpenCV reads as octal, is refused); one that is a
// decimal number a real (also YAML's .inf, -.inf, .nan); anything else is text. Flow mappings, anchors, aliases,
// block scalars, lists of lists, tags before a value, values over several lines (other than lists), repeated
// keys, tabs in the indentation, NUL bytes and carriage returns other than in CRLF are errors.

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
// the file in errors. Throws core::InputError: "<path>: not a settings file: ..." when the file does not begin
// with %YAML:1. (or %YAML 1.), "<path>:<line>: ..." for anything else the reader refuses.
Value Parse(std::string_view text, const std::filesystem::path& path);

}  // namespace hoidslam::io::yaml
