#include "hoidslam/io/ply_file.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/input_error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::io {
namespace {

TEST(WritePly, HeaderThenOneBinaryRecordPerPoint) {
  testing::TempDir dir;
  const std::vector<ColoredPoint> points = {{{1.0, -2.0, 3.5}, {10, 20, 30}}, {{0.25, 0.5, -0.75}, {255, 0, 128}}};
  WritePly(dir / "map.ply", points);

  std::ifstream in(dir / "map.ply", std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string content = buffer.str();
  const std::string end = "end_header\n";
  const std::size_t body = content.find(end);
  ASSERT_NE(body, std::string::npos);
  const std::string header = content.substr(0, body);
  EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0U);
  EXPECT_NE(header.find("element vertex 2\n"), std::string::npos);
  ASSERT_EQ(content.size(), body + end.size() + 2 * 15);

  const char* record = content.data() + body + end.size() + 15;  // the second point
  float xyz[3];
  std::memcpy(xyz, record, sizeof(xyz));
  EXPECT_FLOAT_EQ(xyz[0], 0.25F);
  EXPECT_FLOAT_EQ(xyz[1], 0.5F);
  EXPECT_FLOAT_EQ(xyz[2], -0.75F);
  // Written as RGB: the BGR (255, 0, 128) becomes red 128, green 0, blue 255.
  EXPECT_EQ(static_cast<unsigned char>(record[12]), 128);
  EXPECT_EQ(static_cast<unsigned char>(record[13]), 0);
  EXPECT_EQ(static_cast<unsigned char>(record[14]), 255);
}

TEST(WritePly, EmptyCloudIsAValidFile) {
  testing::TempDir dir;
  WritePly(dir / "empty.ply", {});
  std::ifstream in(dir / "empty.ply");
  std::stringstream buffer;
  buffer << in.rdbuf();
  EXPECT_NE(buffer.str().find("element vertex 0\n"), std::string::npos);
}

TEST(ReadPly, ReadsWhatWritePlyWroteInOrder) {
  testing::TempDir dir;
  const std::vector<ColoredPoint> points = {{{1.0, -2.0, 3.5}, {10, 20, 30}}, {{0.25, 0.5, -0.75}, {255, 0, 128}}};
  WritePly(dir / "map.ply", points);
  const std::vector<ColoredPoint> read = ReadPly(dir / "map.ply");
  ASSERT_EQ(read.size(), 2U);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(read[i].position, points[i].position) << i;  // floats of these values hold them exactly
    EXPECT_EQ(read[i].bgr, points[i].bgr) << i;
  }
  WritePly(dir / "empty.ply", {});
  EXPECT_TRUE(ReadPly(dir / "empty.ply").empty());
}

TEST(ReadPly, NamesTheFileOfAnotherLayoutOrAShortBody) {
  testing::TempDir dir;
  using ::hoidslam::testing::InputErrorOf;
  using ::hoidslam::testing::WriteText;
  EXPECT_THAT(InputErrorOf([&] { ReadPly(dir / "missing.ply"); }), ::testing::HasSubstr("missing.ply"));
  WriteText(dir / "ascii.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n");
  EXPECT_THAT(InputErrorOf([&] { ReadPly(dir / "ascii.ply"); }),
              ::testing::HasSubstr("ascii.ply: not a point cloud as hoidslam writes it"));
  WritePly(dir / "map.ply", std::vector<ColoredPoint>(3));
  std::string bytes = ::hoidslam::testing::ReadText(dir / "map.ply");
  WriteText(dir / "short.ply", bytes.substr(0, bytes.size() - 1));
  EXPECT_THAT(InputErrorOf([&] { ReadPly(dir / "short.ply"); }),
              ::testing::HasSubstr("short.ply: the header says 3 points, the 44 bytes after it hold 2.933"));
  WriteText(dir / "endless.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3");
  EXPECT_THAT(InputErrorOf([&] { ReadPly(dir / "endless.ply"); }), ::testing::HasSubstr("header never ends"));
}

}  // namespace
}  // namespace hoidslam::io
