#include "hoidslam/io/ply_file.h"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/input_error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::io {
namespace {

using ::testing::HasSubstr;

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

// A unit cube's surface, as a box mesh is written.
TriangleMesh UnitCube() {
  TriangleMesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

template <typename T>
void Append(std::string& bytes, T value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof(value));
}

TEST(WritePlyMesh, BinaryVerticesThenTrianglesUnderTheComment) {
  testing::TempDir dir;
  WritePlyMesh(dir / "cube.ply", UnitCube(), "hoidslam static geometry of seq");
  const std::string content = ::hoidslam::testing::ReadText(dir / "cube.ply");
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment hoidslam static geometry of seq\nelement vertex 8\n"
      "property float x\nproperty float y\nproperty float z\nelement face 12\n"
      "property list uchar int vertex_indices\nend_header\n";
  ASSERT_EQ(content.substr(0, header.size()), header);
  ASSERT_EQ(content.size(), header.size() + 8 * 12 + 12 * 13);
  float last[3];  // the last vertex, (1, 1, 1)
  std::memcpy(last, content.data() + header.size() + 7 * 12, sizeof(last));
  EXPECT_THAT(last, ::testing::ElementsAre(1.0F, 1.0F, 1.0F));
  const char* face = content.data() + header.size() + 8 * 12 + 11 * 13;  // the last face: 3, then 3 7 5
  std::int32_t corners[3];
  std::memcpy(corners, face + 1, sizeof(corners));
  EXPECT_EQ(face[0], 3);
  EXPECT_THAT(corners, ::testing::ElementsAre(3, 7, 5));
}

TEST(ReadPlyMesh, ReadsWhatWritePlyMeshWrote) {
  testing::TempDir dir;
  const TriangleMesh cube = UnitCube();
  WritePlyMesh(dir / "cube.ply", cube, "a comment\nof two lines");
  const TriangleMesh read = ReadPlyMesh(dir / "cube.ply");
  EXPECT_EQ(read.vertices, cube.vertices);
  EXPECT_EQ(read.triangles, cube.triangles);
  EXPECT_THAT(::hoidslam::testing::ReadText(dir / "cube.ply"), HasSubstr("comment a comment of two lines\n"));
  WritePlyMesh(dir / "empty.ply", {}, "nothing");
  EXPECT_TRUE(ReadPlyMesh(dir / "empty.ply").vertices.empty());
}

// One triangle with normals and colours, byte for byte as Open3D 0.16 writes it (write_triangle_mesh, binary and
// write_ascii=True): double x y z nx ny nz, uchar red green blue, faces "list uchar uint".
constexpr std::string_view kOpen3dHeader =
    "comment Created by Open3D\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
    "property double nx\nproperty double ny\nproperty double nz\nproperty uchar red\nproperty uchar green\n"
    "property uchar blue\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
const std::vector<Eigen::Vector3f> kOpen3dVertices = {{0.0F, 0.0F, 0.0F}, {1.0F, 0.0F, 0.0F}, {0.0F, 2.0F, 0.5F}};

TEST(ReadPlyMesh, ReadsOpen3dMeshesBinaryAndAscii) {
  testing::TempDir dir;
  std::string binary = "ply\nformat binary_little_endian 1.0\n" + std::string(kOpen3dHeader);
  for (std::size_t i = 0; i < 3; ++i) {
    for (int axis = 0; axis < 3; ++axis) Append<double>(binary, kOpen3dVertices[i][axis]);
    for (const double n : {0.0, 0.0, 1.0}) Append(binary, n);
    for (std::size_t c = 0; c < 3; ++c) Append<std::uint8_t>(binary, c == i ? 255 : 0);
  }
  Append<std::uint8_t>(binary, 3);
  for (const std::uint32_t index : {0U, 1U, 2U}) Append(binary, index);
  ASSERT_EQ(binary.size(), 482U);  // Open3D's file
  ::hoidslam::testing::WriteText(dir / "binary.ply", binary);
  ::hoidslam::testing::WriteText(dir / "ascii.ply", "ply\nformat ascii 1.0\n" + std::string(kOpen3dHeader) +
                                                        "0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n"
                                                        "0 2 0.5 0 0 1 0 0 255\n3 0 1 2\n");
  for (const char* name : {"binary.ply", "ascii.ply"}) {
    const TriangleMesh mesh = ReadPlyMesh(dir / name);
    EXPECT_EQ(mesh.vertices, kOpen3dVertices) << name;
    EXPECT_EQ(mesh.triangles, std::vector<Eigen::Vector3i>(1, {0, 1, 2})) << name;
    EXPECT_EQ(mesh.rgb, (std::vector<cv::Vec3b>{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}})) << name;
  }
}

TEST(WritePlyMesh, ColoursRoundTripAndMustBeOneAVertex) {
  testing::TempDir dir;
  TriangleMesh cube = UnitCube();
  for (std::size_t i = 0; i < cube.vertices.size(); ++i) {
    cube.rgb.emplace_back(static_cast<std::uint8_t>(30 * i), 7, static_cast<std::uint8_t>(255 - i));
  }
  WritePlyMesh(dir / "cube.ply", cube, "coloured");
  EXPECT_THAT(::hoidslam::testing::ReadText(dir / "cube.ply"),
              HasSubstr("property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"));
  const TriangleMesh read = ReadPlyMesh(dir / "cube.ply");
  EXPECT_EQ(read.vertices, cube.vertices);
  EXPECT_EQ(read.triangles, cube.triangles);
  EXPECT_EQ(read.rgb, cube.rgb);
  WritePlyMesh(dir / "plain.ply", UnitCube(), "plain");
  EXPECT_TRUE(ReadPlyMesh(dir / "plain.ply").rgb.empty());
  cube.rgb.pop_back();
  EXPECT_THROW(WritePlyMesh(dir / "bad.ply", cube, "seven colours"), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
}

TEST(ReadPlyMesh, NamesTheFileOfABrokenMesh) {
  testing::TempDir dir;
  using ::hoidslam::testing::InputErrorOf;
  using ::hoidslam::testing::WriteText;
  const auto error = [&](const std::string& name, const std::string& content) {
    WriteText(dir / name, content);
    return InputErrorOf([&] { ReadPlyMesh(dir / name); });
  };
  const std::string ascii = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_THAT(error("quad.ply", ascii + "4 0 1 2 0\n"),
              HasSubstr("quad.ply: face 0: 4 vertices: hoidslam reads triangle meshes only"));
  EXPECT_THAT(error("index.ply", ascii + "3 0 1 3\n"),
              HasSubstr("index.ply: face 0: vertex index 3 is out of range (3 vertices)"));
  EXPECT_THAT(error("cut.ply", ascii + "3 0 1\n"),
              HasSubstr("cut.ply: face 0: the file ends early (the header says 'element face 1')"));
  EXPECT_THAT(error("more.ply", ascii + "3 0 1 2\n3 0 1 2\n"), HasSubstr("more.ply: 8 bytes follow the last element"));
  EXPECT_THAT(error("word.ply", ascii + "3 0 one 2\n"), HasSubstr("word.ply: face 0: 'one' is not of type int"));
  EXPECT_THAT(error("byte.ply", ascii + "256 0 1 2\n"), HasSubstr("byte.ply: face 0: '256' is not of type uchar"));
  EXPECT_THAT(error("nox.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n1\n"),
              HasSubstr("nox.ply: the vertices have no float or double property x"));
  EXPECT_THAT(error("format.ply", "ply\nformat binary_big_endian 1.0\nend_header\n"),
              HasSubstr("format.ply:2: 'format binary_big_endian 1.0': hoidslam reads"));
  EXPECT_THAT(error("keyword.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nsomething\n"),
              HasSubstr("keyword.ply:5: 'something' is not a PLY header line"));
  EXPECT_THAT(error("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n"),
              HasSubstr("type.ply:4: 'property float128 x': unknown type"));
  EXPECT_THAT(error("text.txt", "hello\n"), HasSubstr("text.txt: not a PLY file"));
  EXPECT_THAT(InputErrorOf([&] { ReadPlyMesh(dir / "missing.ply"); }), HasSubstr("missing.ply"));

  // Binary: counts beyond what the file holds are refused before anything is read, a short face at its end.
  WritePlyMesh(dir / "cube.ply", UnitCube(), "cube");
  const std::string cube = ::hoidslam::testing::ReadText(dir / "cube.ply");
  std::string huge = cube;
  huge.replace(huge.find("element face 12"), 15, "element face 99999999999999");
  EXPECT_THAT(error("huge.ply", huge),
              HasSubstr("huge.ply: 'element face 99999999999999' needs 1 bytes or more per face, more than the 252 "
                        "bytes after the header hold"));
  EXPECT_THAT(error("short.ply", cube.substr(0, cube.size() - 2)),
              HasSubstr("short.ply: face 11: the file ends early (the header says 'element face 12')"));
  EXPECT_THAT(error("endless.ply", cube.substr(0, cube.find("end_header"))), HasSubstr("header never ends"));
}

TEST(VoxelCentresPly, ReadsBackTheCentresAndExactlyTheVoxelSize) {
  testing::TempDir dir;
  const VoxelCentres voxels{0.02, {{0.01F, 0.03F, -0.05F}, {1.23F, 4.56F, 7.89F}}};
  WriteVoxelCentresPly(dir / "cells.ply", voxels);
  const std::string content = ::hoidslam::testing::ReadText(dir / "cells.ply");
  EXPECT_EQ(content.substr(0, content.find("end_header")),
            "ply\nformat binary_little_endian 1.0\ncomment voxel_size 0.02\nelement vertex 2\n"
            "property float x\nproperty float y\nproperty float z\n");
  const VoxelCentres read = ReadVoxelCentresPly(dir / "cells.ply");
  EXPECT_EQ(read.voxel_size, 0.02);
  EXPECT_EQ(read.centres, voxels.centres);
  WriteVoxelCentresPly(dir / "none.ply", {1.0 / 3.0, {}});
  const VoxelCentres none = ReadVoxelCentresPly(dir / "none.ply");
  EXPECT_EQ(none.voxel_size, 1.0 / 3.0);
  EXPECT_TRUE(none.centres.empty());
}

TEST(VoxelCentresPly, NamesTheFileWithoutOneGoodVoxelSize) {
  testing::TempDir dir;
  using ::hoidslam::testing::InputErrorOf;
  const auto error = [&](const std::string& name, const std::string& comments, const std::string& faces = "") {
    ::hoidslam::testing::WriteText(dir / name, "ply\nformat ascii 1.0\n" + comments +
                                                   "element vertex 1\nproperty float x\nproperty float y\n"
                                                   "property float z\n" + faces + "end_header\n0.01 0.01 0.01\n");
    return InputErrorOf([&] { ReadVoxelCentresPly(dir / name); });
  };
  EXPECT_EQ(error("good.ply", "comment voxel_size 0.02\n"), "no error");
  EXPECT_THAT(error("none.ply", "comment Created by Open3D\n"),
              HasSubstr("none.ply: no 'comment voxel_size <metres>' line"));
  for (const char* bad : {"0", "-0.02", "inf", "nan", "0.02m", "", "two"}) {
    EXPECT_THAT(error("bad.ply", fmt::format("comment voxel_size {}\n", bad)),
                HasSubstr("bad.ply: 'comment voxel_size"))
        << bad;
  }
  EXPECT_THAT(error("twice.ply", "comment voxel_size 0.02\ncomment voxel_size 0.02\n"),
              HasSubstr("twice.ply: 'comment voxel_size 0.02': the header must say the voxel size once"));
  EXPECT_THAT(error("faces.ply", "comment voxel_size 0.02\n",
                    "element face 0\nproperty list uchar int vertex_indices\n"),
              HasSubstr("faces.ply: a face element: voxel centres are vertices only"));
}

TEST(CellKeys, PackTheCellHoldingAPointAndUnpackItsIndices) {
  const std::uint64_t key = CellKeyOf(Eigen::Vector3d(-0.01, 0.05, 1.0), 0.02);
  EXPECT_EQ(key, PackCell(-1, 2, 50));
  EXPECT_EQ(UnpackCell(key, 0), -1);
  EXPECT_EQ(UnpackCell(key, 1), 2);
  EXPECT_EQ(UnpackCell(key, 2), 50);
  EXPECT_LT(PackCell(-1, 5, 5), PackCell(0, -5, -5)) << "keys sort in (i, j, k) order";
}

}  // namespace
}  // namespace hoidslam::io
