#include "hoidslam/io/settings_yaml.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"

namespace hoidslam::io::yaml {
namespace {

using namespace std::string_literals;  // "..."s keeps a NUL byte
using core::InputError;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;
using Kind = Value::Kind;

Value ParseText(const std::string& text) { return Parse(text, "my.yaml"); }

// The value of `key`, which must be present.
const Value& At(const Value& mapping, std::string_view key) {
  const Value* value = mapping.Find(key);
  if (value == nullptr) throw std::runtime_error("no key " + std::string(key));
  return *value;
}

TEST(SettingsYaml, ReadsNumbersAsIntegersOrRealsAndEverythingElseAsText) {
  const Value root = ParseText(
      "%YAML:1.0\n"
      "a: 1000\nb: -3\nc: +4\nd: 1000.0\ne: 1.\nf: .5\ng: -3.2e-3\nh: 99999999999999999999\n"
      "i: .inf\nj: -.inf\nk: .nan\n"
      "l: PinHole\nm: \"1.0\"\nn: 'it''s'\no: \"a\\\"b\\\\c\\td\"\np: inf\nq: nan(1)\nr: 1.2.3\ns: 0x10\n"
      "t: two words  # and a comment\nu: a#b\nv: 12:30\nw:7\n");
  ASSERT_EQ(root.kind, Kind::kMapping);
  EXPECT_EQ(root.entries.size(), 23u);
  using Integers = std::vector<std::pair<std::string, std::int64_t>>;
  for (const auto& [key, integer] : Integers{{"a", 1000}, {"b", -3}, {"c", 4}, {"w", 7}}) {
    SCOPED_TRACE(key);
    EXPECT_EQ(At(root, key).kind, Kind::kInteger);
    EXPECT_EQ(At(root, key).integer, integer);
    EXPECT_EQ(At(root, key).real, static_cast<double>(integer));
  }
  for (const auto& [key, real] : std::vector<std::pair<std::string, double>>{
           {"d", 1000.0}, {"e", 1.0}, {"f", 0.5}, {"g", -3.2e-3}, {"h", 1e20}, {"i", INFINITY}, {"j", -INFINITY}}) {
    SCOPED_TRACE(key);
    EXPECT_EQ(At(root, key).kind, Kind::kReal);
    EXPECT_DOUBLE_EQ(At(root, key).real, real);
  }
  EXPECT_EQ(At(root, "k").kind, Kind::kReal);
  EXPECT_TRUE(std::isnan(At(root, "k").real));
  for (const auto& [key, text] : std::vector<std::pair<std::string, std::string>>{
           {"l", "PinHole"}, {"m", "1.0"}, {"n", "it's"}, {"o", "a\"b\\c\td"}, {"p", "inf"}, {"q", "nan(1)"},
           {"r", "1.2.3"}, {"s", "0x10"}, {"t", "two words"}, {"u", "a#b"}, {"v", "12:30"}}) {
    SCOPED_TRACE(key);
    EXPECT_EQ(At(root, key).kind, Kind::kText);
    EXPECT_EQ(At(root, key).text, text);
  }
  EXPECT_EQ(At(root, "a").line, 2u);
  EXPECT_EQ(At(root, "v").line, 23u);
}

TEST(SettingsYaml, ReadsListsInBracketsOverSeveralLinesAndAsDashLines) {
  const Value root = ParseText(
      "%YAML:1.0\n"
      "classes: [ \"person\", cup, 'a, b' ]\n"
      "empty: []\n"
      "numbers: [1, 2.5,  # first row\n"
      "\n"
      "          3,\n"
      "          4, ]\n"
      "dashes:\n"
      "  - person\n"
      "  - \"cup\"  # a comment\n"
      "flush:\n"
      "- 7\n"
      "after: 1\n");
  EXPECT_EQ(root.entries.size(), 6u);
  const Value& classes = At(root, "classes");
  ASSERT_EQ(classes.kind, Kind::kList);
  ASSERT_EQ(classes.items.size(), 3u);
  EXPECT_EQ(classes.items[0].text, "person");
  EXPECT_EQ(classes.items[1].text, "cup");
  EXPECT_EQ(classes.items[2].text, "a, b");
  EXPECT_EQ(At(root, "empty").kind, Kind::kList);
  EXPECT_TRUE(At(root, "empty").items.empty());
  const Value& numbers = At(root, "numbers");
  ASSERT_EQ(numbers.items.size(), 4u);
  EXPECT_EQ(numbers.items[1].real, 2.5);
  EXPECT_EQ(numbers.items[3].integer, 4);
  EXPECT_EQ(numbers.items[3].line, 7u);
  const Value& dashes = At(root, "dashes");
  ASSERT_EQ(dashes.kind, Kind::kList);
  ASSERT_EQ(dashes.items.size(), 2u);
  EXPECT_EQ(dashes.items[1].text, "cup");
  ASSERT_EQ(At(root, "flush").items.size(), 1u);
  EXPECT_EQ(At(root, "flush").items[0].integer, 7);
  EXPECT_EQ(At(root, "after").integer, 1);
}

// ORB-SLAM3's files for cameras with an IMU hold OpenCV matrices; hoidslam reads none, but the file must load.
TEST(SettingsYaml, ReadsAnOpenCvMatrixAsAMappingUnderItsKey) {
  const Value root = ParseText(
      "%YAML:1.0\n"
      "Tbc: !!opencv-matrix\n"
      "   rows: 2\n"
      "   cols: 2\n"
      "   dt: f\n"
      "   data:[1.0, 0.0,\n"
      "          0.0, 1.0]\n"
      "Camera.fx: 535.4\n"
      "Empty:\n"
      "Viewer.KeyFrameSize: 0.05\n");
  const Value& tbc = At(root, "Tbc");
  ASSERT_EQ(tbc.kind, Kind::kMapping);
  EXPECT_EQ(tbc.line, 2u);
  EXPECT_EQ(At(tbc, "rows").integer, 2);
  EXPECT_EQ(At(tbc, "dt").text, "f");
  EXPECT_EQ(At(tbc, "data").items.size(), 4u);
  EXPECT_EQ(At(root, "Camera.fx").real, 535.4);
  EXPECT_EQ(At(root, "Empty").kind, Kind::kNone);
  EXPECT_EQ(At(root, "Viewer.KeyFrameSize").real, 0.05);
  EXPECT_EQ(root.Find("rows"), nullptr);
}

TEST(SettingsYaml, AcceptsTheHeaderFormsMarkersCommentsWindowsLineEndingsAndAByteOrderMark) {
  for (const std::string& text :
       {std::string("%YAML:1.0\nCamera.fx: 535.4\n"), std::string("%YAML 1.2\n---\nCamera.fx: 535.4\n...\n# end\n"),
        std::string("\xEF\xBB\xBF%YAML:1.0\r\n# comment\r\n\r\n---  # OpenCV writes this\r\nCamera.fx: 535.4\r\n"),
        std::string("%YAML:1.0\n  Camera.fx: 535.4  \n\t\n"), std::string("%YAML:1.0\nCamera.fx:\t535.4")}) {
    SCOPED_TRACE(text);
    const Value root = ParseText(text);
    ASSERT_EQ(root.entries.size(), 1u);
    EXPECT_EQ(root.entries[0].key, "Camera.fx");
    EXPECT_EQ(root.entries[0].value.real, 535.4);
  }
  const Value empty = ParseText("%YAML:1.0\n# nothing yet\n");
  EXPECT_EQ(empty.kind, Kind::kMapping);
  EXPECT_TRUE(empty.entries.empty());
}

TEST(SettingsYaml, RefusesAFirstLineWithMoreThanTheVersion) {
  for (const std::string& text : {std::string("%YAML:1.0 Camera.fx: 535.4\n"),
                                  std::string("%YAML:1.0\rCamera.fx: 535.4\rCamera.fy: 539.2\r")}) {
    SCOPED_TRACE(text);
    EXPECT_THAT([&] { ParseText(text); }, ThrowsMessage<InputError>(HasSubstr("my.yaml:1: ")));
  }
}

TEST(SettingsYaml, RefusesAFileThatIsNotYamlWithoutALine) {
  for (const std::string& text : {std::string(""), std::string("Camera.fx: 535.4\n"), std::string("%YAMLish\n"),
                                  std::string("<?xml version=\"1.0\"?>\n<opencv_storage/>\n"),
                                  std::string("{\"Camera.fx\": 535.4}\n")}) {
    SCOPED_TRACE(text);
    EXPECT_THAT([&] { ParseText(text); },
                ThrowsMessage<InputError>(HasSubstr("my.yaml: not a settings file: it must be YAML beginning with")));
  }
}

struct Refused {
  std::string body;     // the file after its %YAML:1.0 line
  std::size_t line;     // the line the error must name
  std::string message;  // and a part of its explanation
};

void PrintTo(const Refused& refused, std::ostream* out) { *out << refused.body; }

class SettingsYamlRefuses : public ::testing::TestWithParam<Refused> {};

TEST_P(SettingsYamlRefuses, NamingTheLine) {
  const Refused& refused = GetParam();
  EXPECT_THAT([&] { ParseText("%YAML:1.0\n" + refused.body); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("my.yaml:" + std::to_string(refused.line) + ": "),
                                              HasSubstr(refused.message))));
}

INSTANTIATE_TEST_SUITE_P(
    WhatSettingsFilesDoNotUse, SettingsYamlRefuses,
    ::testing::Values(
        Refused{"a: 1\nb: [x, y\n", 3, "the list is not closed with ]"},
        Refused{"b: [x, y\nc: z\n", 2, "the list is not closed with ]"},
        Refused{"b: [x, #y]\nc: z\n", 2, "the list is not closed with ]"},
        Refused{"a: [\"x\" \"y\"]\n", 2, "missing ',' between the elements"},
        Refused{"a: [x,\n , y]\n", 3, "an empty element"},
        Refused{"a: [x] y\n", 2, "'y' after the list"},
        Refused{"a: [[1, 2]]\n", 2, "a value beginning with '['"},
        Refused{"a: {b: 1}\n", 2, "a value beginning with '{'"},
        Refused{"a: &anchor 1\n", 2, "a value beginning with '&'"},
        Refused{"a: !str 5\n", 2, "a tag before a value is not supported"},
        Refused{"a: !\n", 2, "a tag without a name"},
        Refused{"a: 010\n", 2, "the integer 010 begins with 0"},
        Refused{"a #note: 5\n", 2, "a comment begins before the ':'"},
        Refused{"Tbc: !!opencv-matrix\n   rows: 4\n  cols: 4\n", 4, "indented differently from the lines above it"},
        Refused{"a: 1\rb: 2\n", 2, "a carriage return inside a line"},
        Refused{"a: |\n  text\n", 2, "a value beginning with '|'"},
        Refused{"a: - 1\n", 2, "a value beginning with '-'"},
        Refused{"a: \"open\n", 2, "the quoted value is not closed on its line"},
        Refused{"a: \"\\q\"\n", 2, "the escape \\q is not supported"},
        Refused{"a: \"x\" y\n", 2, "'y' after the quoted value"},
        Refused{"a: b: c\n", 2, "':' in the value 'b: c'"},
        Refused{"a: 1\nthis is not yaml\n", 3, "expected 'key: value'"},
        Refused{"\"a\": 1\n", 2, "'\"a\"' is not a key"},
        Refused{"a: 1\nb: 2\na: 3\n", 4, "a is given more than once (first on line 2)"},
        Refused{"m:\n  x: 1\n  x: 2\n", 4, "x is given more than once (first on line 3)"},
        Refused{"a: 1\n  b: 2\n", 3, "indented under a key that already has a value"},
        Refused{"  a: 1\nb: 2\n", 3, "indented less than the keys above it"},
        Refused{"m:\n  x: 1\n  - 2\n", 4, "a list element where 'key: value' belongs"},
        Refused{"a:\n  -\n", 3, "a list element without a value"},
        Refused{"- 1\n- 2\n", 2, "expected 'key: value' lines at the top level"},
        Refused{"a:\n\tb: 1\n", 3, "a tab in the indentation"},
        Refused{"a: 1\n---\nb: 2\n", 3, "a second document"},
        Refused{"--- - s\n-\n", 2, "the document marker --- must stand alone on its line"},
        Refused{"a: 1\n...\nb: 2\n", 4, "text after the end of the document"},
        Refused{"%TAG ! tag:x\na: 1\n", 2, "a directive (%) after the first line"},
        Refused{"a: 1\nb: 'x\0'\n"s, 3, "a NUL byte: a settings file is text"},
        Refused{"a: 1e400\n", 2, "the number 1e400 is out of range"},
        Refused{"a:\n b:\n  c:\n   d:\n    e:\n     f:\n      g:\n       h:\n        i:\n         j:\n          k:\n"
                "           l:\n            m:\n             n:\n              o:\n               p:\n"
                "                q:\n                 r: 1\n",
                19, "nested deeper than 16 levels"}),
    [](const ::testing::TestParamInfo<Refused>& info) { return std::to_string(info.index); });

}  // namespace
}  // namespace hoidslam::io::yaml
