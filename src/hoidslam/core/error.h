#pragma once
// Errors. Every failure a user can cause (a missing file, a bad line, an out-of-range setting) is an
// InputError whose message names the file and line or the parameter; the CLI prints it and exits non-zero.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace hoidslam::core {

// Base of all hoidslam errors.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A problem with something the user gave us: a file, a line in it, or a parameter.
class InputError : public Error {
 public:
  // The message is kept on one line whatever the input held: control characters (a line break inside a quoted
  // value, say) are written as escapes such as \n, \r or \x1b; tabs stay.
  explicit InputError(const std::string& what);

  // "<file>: <what>"
  static InputError InFile(const std::filesystem::path& file, const std::string& what);
  // "<file>:<line>: <what>" (lines count from 1)
  static InputError AtLine(const std::filesystem::path& file, std::size_t line, const std::string& what);
  // "parameter <name>: <what>"
  static InputError ForParameter(const std::string& name, const std::string& what);
};

// A long job stopped early because the user asked it to (Ctrl-C); it has left no partial output behind.
class Interrupted : public Error {
 public:
  Interrupted() : Error("interrupted") {}
};

}  // namespace hoidslam::core
