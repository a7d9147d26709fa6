#include "hoidslam/io/ply_file.h"

#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/temp_dir.h"

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

}  // namespace
}  // namespace hoidslam::io
