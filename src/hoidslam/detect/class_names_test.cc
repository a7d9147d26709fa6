#include "hoidslam/detect/class_names.h"


#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hoidslam/core/error.h"
#include "support/shared_data.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::detect {
namespace {

using ::hoidslam::testing::WriteText;

using ::testing::HasSubstr;


TEST(CocoClassNames, HasTheEightyClassesTheHoidFilterNames) {
  const auto& names = CocoClassNames();
  ASSERT_EQ(names.size(), 80U);
  EXPECT_EQ(names[0], "person");
  EXPECT_EQ(names[39], "bottle");
  EXPECT_EQ(names[41], "cup");
  EXPECT_EQ(names[56], "chair");
  EXPECT_EQ(names[62], "tv");
  EXPECT_EQ(names[63], "laptop");
  EXPECT_EQ(names[64], "mouse");
  EXPECT_EQ(names[66], "keyboard");
  EXPECT_EQ(names[73], "book");
  EXPECT_EQ(names[79], "toothbrush");
}

TEST(CocoClassNames, AgreesWithDarknetsListExceptForRenamedClasses) {
  HOIDSLAM_SHARED_PATH_OR_SKIP(path, "data/photos/coco.names");
  const std::vector<std::string> darknet = ReadClassNames(path);
  ASSERT_EQ(darknet.size(), 80U);
  const auto& names = CocoClassNames();
  int renamed = 0;  // motorbike, aeroplane, sofa, pottedplant, diningtable, tvmonitor
  for (std::size_t i = 0; i < darknet.size(); ++i) renamed += darknet[i] != names[i] ? 1 : 0;
  EXPECT_EQ(renamed, 6);
  EXPECT_EQ(darknet[62], "tvmonitor");
}

TEST(ReadClassNames, TrimsSpacesAndCarriageReturnsAndIgnoresTrailingBlankLines) {
  testing::TempDir dir;
  WriteText(dir / "names.txt", "  hand \r\nmug\r\n\n\n");
  EXPECT_THAT(ReadClassNames(dir / "names.txt"), ::testing::ElementsAre("hand", "mug"));
}

TEST(ReadClassNames, BlankLineInsideTheListIsNamedByLine) {
  testing::TempDir dir;
  WriteText(dir / "names.txt", "hand\n\nmug\n");
  try {
    ReadClassNames(dir / "names.txt");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("names.txt:2:"));
  }
}

TEST(ReadClassNames, MissingOrEmptyFileIsAnInputError) {
  testing::TempDir dir;
  EXPECT_THROW(ReadClassNames(dir / "absent.txt"), core::InputError);
  WriteText(dir / "empty.txt", "\n \n");
  try {
    ReadClassNames(dir / "empty.txt");
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("empty.txt"));
  }
}

}  // namespace
}  // namespace hoidslam::detect
