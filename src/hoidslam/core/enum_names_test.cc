#include "hoidslam/core/enum_names.h"

#include <gtest/gtest.h>

namespace hoidslam::core {
namespace {

enum class Colour { kRed, kGreen, kBlue };
constexpr EnumNames<Colour, 3> kColourNames = {{{Colour::kRed, "red"}, {Colour::kGreen, "green"}, {Colour::kBlue, "blue"}}};

TEST(EnumNames, NamesAndParsesEveryValue) {
  for (const auto& [value, name] : kColourNames) {
    EXPECT_EQ(EnumName(kColourNames, value), name);
    EXPECT_EQ(ParseEnumName(kColourNames, name, "colour", "colour"), value);
  }
  EXPECT_EQ(EnumName(kColourNames, static_cast<Colour>(7)), "unknown");
}

TEST(EnumNames, UnknownNameListsTheChoices) {
  try {
    ParseEnumName(kColourNames, "mauve", "Paint.colour", "colour");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "parameter Paint.colour: unknown colour 'mauve' (expected red, green or blue)");
  }
}

}  // namespace
}  // namespace hoidslam::core
