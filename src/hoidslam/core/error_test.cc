#include "hoidslam/core/error.h"

#include <string>

#include <gtest/gtest.h>

namespace hoidslam::core {
namespace {

TEST(InputError, NamesFileAndLine) {
  const InputError e = InputError::AtLine("data/rgb.txt", 12, "expected 2 columns, found 1");
  EXPECT_STREQ(e.what(), "data/rgb.txt:12: expected 2 columns, found 1");
}

TEST(InputError, NamesParameter) {
  const InputError e = InputError::ForParameter("HOID.minInteractionArea", "must be in (0, 1], got 1.5");
  EXPECT_STREQ(e.what(), "parameter HOID.minInteractionArea: must be in (0, 1], got 1.5");
}

TEST(InputError, KeepsTheMessageOnOneLine) {
  using namespace std::string_literals;  // "..."s keeps the NUL byte
  const InputError e = InputError::ForParameter("HOID.mode", "unknown mode 'a\nb\r\x1b\0c\td'"s);
  EXPECT_STREQ(e.what(), "parameter HOID.mode: unknown mode 'a\\nb\\r\\x1b\\x00c\td'");
}

TEST(InputError, IsAnError) {
  try {
    throw InputError::InFile("model.onnx", "no such file");
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "model.onnx: no such file");
  }
}

}  // namespace
}  // namespace hoidslam::core
