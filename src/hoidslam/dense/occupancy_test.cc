#include "hoidslam/dense/occupancy.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <octomap/OcTree.h>
#include <opencv2/imgcodecs.hpp>

#include "hoidslam/dense/test_room.h"
#include "support/geometry.h"
#include "support/input_error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::dense {
namespace {

using ::testing::HasSubstr;

constexpr double kResolution = 0.05;  // OccupancyOptions' default

// A flat wall `distance` metres in front of a camera at the world origin (looking along +z), every pixel seeing it.
cv::Mat WallDepth(float distance) {
  const core::CameraIntrinsics camera;
  return cv::Mat(camera.height, camera.width, CV_32FC1, cv::Scalar(distance));
}

TEST(OccupancyMap, AWallIsOccupiedAtItsDepthFreeBeforeItAndUnknownBehindIt) {
  OccupancyMap map{OccupancyOptions{}};
  map.InsertDepth(WallDepth(2.0F), core::CameraIntrinsics{}, core::Pose::Identity());

  const std::vector<Eigen::Vector3d> centres = map.OccupiedCentres();
  ASSERT_FALSE(centres.empty());
  EXPECT_EQ(map.OccupiedLeaves(), centres.size());
  for (const Eigen::Vector3d& centre : centres) ASSERT_NEAR(centre.z(), 2.0, kResolution) << centre.transpose();
  // The wall spans the field of view: at 2 m, ±1.2 m across and ±0.9 m high.
  EXPECT_GT(centres.size(), 1500U);

  for (const double z : {0.1, 0.5, 1.0, 1.5, 1.9}) {
    EXPECT_EQ(map.At({0.0, 0.0, z}), CellState::kFree) << z;
    EXPECT_EQ(map.At({0.5 * z, 0.3 * z, z}), CellState::kFree) << z;  // inside the view
  }
  EXPECT_EQ(map.At({0.0, 0.0, 2.0}), CellState::kOccupied);
  for (const double z : {2.1, 2.5, 4.0}) EXPECT_EQ(map.At({0.0, 0.0, z}), CellState::kUnknown) << z;
  EXPECT_EQ(map.At({0.0, 0.0, -0.5}), CellState::kUnknown);  // behind the camera
}

TEST(OccupancyMap, ARayDeeperThanTheMaxDepthFreesTheSpaceBeforeItAndMarksNoSurface) {
  OccupancyMap map{OccupancyOptions{}};
  map.InsertDepth(WallDepth(5.0F), core::CameraIntrinsics{}, core::Pose::Identity(), /*max_depth=*/3.0);
  EXPECT_EQ(map.OccupiedLeaves(), 0U);
  for (const double z : {0.5, 1.5, 2.9}) EXPECT_EQ(map.At({0.0, 0.0, z}), CellState::kFree) << z;
  for (const double z : {3.1, 5.0}) EXPECT_EQ(map.At({0.0, 0.0, z}), CellState::kUnknown) << z;
}

TEST(OccupancyMap, APixelWithoutDepthCastsNoRay) {
  for (const float no_depth : {0.0F, -1.0F, std::numeric_limits<float>::quiet_NaN(),
                               std::numeric_limits<float>::infinity()}) {
    SCOPED_TRACE(no_depth);
    OccupancyMap map{OccupancyOptions{}};
    cv::Mat depth = WallDepth(2.0F);
    // A hole of 200 × 200 pixels in the middle: ±0.37 m of the wall at 2 m.
    depth(cv::Rect(220, 140, 200, 200)).setTo(no_depth);
    map.InsertDepth(depth, core::CameraIntrinsics{}, core::Pose::Identity());
    for (const Eigen::Vector3d& centre : map.OccupiedCentres()) {
      ASSERT_FALSE(std::abs(centre.x()) < 0.3 && std::abs(centre.y()) < 0.3) << centre.transpose();
    }
    // The rays around the hole pass further than a cell from the optical axis.
    for (const double z : {1.0, 1.5, 1.9, 2.0}) EXPECT_EQ(map.At({0.0, 0.0, z}), CellState::kUnknown) << z;
  }
}

TEST(OccupancyMap, EveryPixelStepthPixelCastsARay) {
  cv::Mat depth = WallDepth(0.0F);
  depth.at<float>(240, 320) = 2.0F;  // on the grid of every 4th pixel
  depth.at<float>(241, 322) = 2.5F;  // off it
  OccupancyMap map{OccupancyOptions{}};
  map.InsertDepth(depth, core::CameraIntrinsics{}, core::Pose::Identity());
  const std::vector<Eigen::Vector3d> centres = map.OccupiedCentres();
  ASSERT_EQ(centres.size(), 1U);
  EXPECT_NEAR(centres[0].z(), 2.0, kResolution);
}

// A wall two cells thick: the rays of alternate blocks of 4 × 4 pixels end in the cells 2.00–2.05 m and 2.05–2.10 m
// deep. Its cells agree in pairs of layers, so OctoMap merges them into leaves of 2 × 2 × 2 cells.
cv::Mat ThickWallDepth() {
  cv::Mat depth = WallDepth(2.02F);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      if ((u / 4 + v / 4) % 2 == 1) depth.at<float>(v, u) = 2.07F;
    }
  }
  return depth;
}

TEST(OccupancyMap, TheBinaryTreeReadsBackWithOctoMapCellForCell) {
  testing::TempDir dir;
  OccupancyMap map{OccupancyOptions{}};
  map.InsertDepth(ThickWallDepth(), core::CameraIntrinsics{}, core::Pose::Identity());
  map.WriteBinary(dir / "occupancy.bt");

  octomap::OcTree tree((dir / "occupancy.bt").string());
  EXPECT_DOUBLE_EQ(tree.getResolution(), kResolution);
  std::size_t merged = 0;
  for (auto leaf = tree.begin_leafs(), end = tree.end_leafs(); leaf != end; ++leaf) {
    merged += tree.isNodeOccupied(*leaf) && leaf.getDepth() < tree.getTreeDepth() ? 1 : 0;
  }
  ASSERT_GT(merged, 100U) << "the wall should have merged occupied leaves";
  tree.expand();  // every leaf at the finest resolution, as OccupiedLeaves() counts them
  std::size_t occupied = 0;
  for (auto leaf = tree.begin_leafs(), end = tree.end_leafs(); leaf != end; ++leaf) {
    occupied += tree.isNodeOccupied(*leaf) ? 1 : 0;
  }
  EXPECT_EQ(occupied, map.OccupiedLeaves());
  for (const Eigen::Vector3d& centre : map.OccupiedCentres()) {
    ASSERT_NEAR(centre.z(), 2.05, kResolution) << centre.transpose();
    const octomap::OcTreeNode* node = tree.search(centre.x(), centre.y(), centre.z());
    ASSERT_TRUE(node != nullptr && tree.isNodeOccupied(node)) << centre.transpose();
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);  // no temporary left

  const OccupiedCells cells = ReadOccupiedCells(dir / "occupancy.bt");
  EXPECT_DOUBLE_EQ(cells.resolution, kResolution);
  EXPECT_EQ(cells.centres.size(), map.OccupiedLeaves());
}

TEST(ReadOccupiedCells, NamesAFileThatIsNoOctoMap) {
  testing::TempDir dir;
  testing::WriteText(dir / "occupancy.bt", "not a tree\n");
  try {
    ReadOccupiedCells(dir / "occupancy.bt");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("occupancy.bt"), std::string::npos) << e.what();
  }
}

// The test room mapped from its views, its floor frame placed in the SLAM world by T_wf.
std::unique_ptr<OccupancyMap> MapTheRoom(const OccupancyOptions& options, const core::Pose& T_wf) {
  // Rendered once for all the maps of the tests.
  static const std::vector<std::pair<core::Pose, cv::Mat>> views = [] {
    const test_room::Room room = test_room::TestRoom();
    std::vector<std::pair<core::Pose, cv::Mat>> rendered;
    for (const core::Pose& T_fc : test_room::RoomViews(room)) {
      rendered.emplace_back(T_fc, test_room::RenderDepth(room, core::CameraIntrinsics{}, T_fc));
    }
    return rendered;
  }();
  auto map = std::make_unique<OccupancyMap>(options);
  for (const auto& [T_fc, depth] : views) map->InsertDepth(depth, core::CameraIntrinsics{}, T_wf * T_fc);
  return map;
}

// The cell of `grid` holding floor-frame point (x, y); kUnknown outside the grid.
std::int8_t CellAt(const OccupancyGrid& grid, double x, double y) {
  const int column = static_cast<int>(std::floor((x - grid.origin.x()) / grid.resolution));
  const int row = static_cast<int>(std::floor((y - grid.origin.y()) / grid.resolution));
  if (column < 0 || row < 0 || column >= grid.width || row >= grid.height) return OccupancyGrid::kUnknown;
  return grid.cells[static_cast<std::size_t>(row) * static_cast<std::size_t>(grid.width) +
                    static_cast<std::size_t>(column)];
}

// Whether a cell within one cell of (x, y) is occupied: a wall's leaves lie on either side of its plane.
bool OccupiedNear(const OccupancyGrid& grid, double x, double y) {
  for (const double dx : {-kResolution, 0.0, kResolution}) {
    for (const double dy : {-kResolution, 0.0, kResolution}) {
      if (CellAt(grid, x + dx, y + dy) == OccupancyGrid::kOccupied) return true;
    }
  }
  return false;
}

// The SLAM world frames the room is mapped in: the floor's own, and one of a first camera tilted and turned.
const std::vector<std::pair<std::string, core::Pose>> kWorldFrames = {
    {"floor", core::Pose::Identity()},
    {"tilted", testing::PoseFromAxisAngle({0.3, -0.2, 0.8}, {1.0, -2.0, 0.5})},
};

TEST(OccupancyMap, TheProjectionOfARoomHasOccupiedWallsAFreeInsideAndAnUnknownOutside) {
  for (const auto& [name, T_wf] : kWorldFrames) {
    SCOPED_TRACE(name);
    const OccupancyGrid grid = MapTheRoom(OccupancyOptions{}, T_wf)->Project(T_wf.inverse());
    EXPECT_EQ(grid.resolution, kResolution);
    EXPECT_TRUE(grid.T_fw.isApprox(T_wf.inverse()));
    // The grid spans the room's walls, 4 × 3 m, to within a cell on each side.
    EXPECT_NEAR(grid.origin.x(), 0.0, 2 * kResolution);
    EXPECT_NEAR(grid.origin.y(), 0.0, 2 * kResolution);
    EXPECT_NEAR(grid.width * kResolution, 4.0, 3 * kResolution);
    EXPECT_NEAR(grid.height * kResolution, 3.0, 3 * kResolution);

    for (double s = 0.1; s < 2.95; s += 0.1) {
      EXPECT_TRUE(OccupiedNear(grid, 0.0, s)) << "wall x = 0 at y " << s;
      EXPECT_TRUE(OccupiedNear(grid, 4.0, s)) << "wall x = 4 at y " << s;
    }
    for (double s = 0.1; s < 3.95; s += 0.1) {
      EXPECT_TRUE(OccupiedNear(grid, s, 0.0)) << "wall y = 0 at x " << s;
      EXPECT_TRUE(OccupiedNear(grid, s, 3.0)) << "wall y = 3 at x " << s;
    }
    // The crate's top is in the band; the floor around it is below, the shelf above.
    EXPECT_EQ(CellAt(grid, 0.75, 0.75), OccupancyGrid::kOccupied);
    for (double x = 0.2; x < 3.85; x += 0.1) {
      for (double y = 0.2; y < 2.85; y += 0.1) {
        if (x > 0.35 && x < 1.15 && y > 0.35 && y < 1.15) continue;  // the crate
        EXPECT_EQ(CellAt(grid, x, y), OccupancyGrid::kFree) << x << ", " << y;
      }
    }
    for (const auto& [x, y] : {std::pair{-0.5, 1.5}, {4.5, 1.5}, {2.0, -0.5}, {2.0, 3.5}}) {
      EXPECT_EQ(CellAt(grid, x, y), OccupancyGrid::kUnknown) << x << ", " << y;
    }
  }
}

TEST(OccupancyMap, OnlyTheHeightBandMakesObstacles) {
  struct Case {
    double band_low, band_high;
    std::int8_t under_shelf, open_floor;  // cells at (2.0, 2.8) and (3.0, 1.5)
  };
  for (const Case& c : {Case{0.1, 1.8, OccupancyGrid::kFree, OccupancyGrid::kFree},
                        Case{0.1, 2.1, OccupancyGrid::kOccupied, OccupancyGrid::kFree},  // the shelf
                        Case{-0.1, 1.8, OccupancyGrid::kOccupied, OccupancyGrid::kOccupied}}) {  // the floor
    SCOPED_TRACE(::testing::Message() << c.band_low << ":" << c.band_high);
    OccupancyOptions options;
    options.band_low = c.band_low;
    options.band_high = c.band_high;
    const OccupancyGrid grid = MapTheRoom(options, core::Pose::Identity())->Project(core::Pose::Identity());
    EXPECT_EQ(CellAt(grid, 2.0, 2.8), c.under_shelf);
    EXPECT_EQ(CellAt(grid, 3.0, 1.5), c.open_floor);
  }
}

TEST(OccupancyMap, AMapWithoutDepthProjectsToAnEmptyGrid) {
  OccupancyMap map{OccupancyOptions{}};
  map.InsertDepth(WallDepth(0.0F), core::CameraIntrinsics{}, core::Pose::Identity());
  const OccupancyGrid grid = map.Project(core::Pose::Identity());
  EXPECT_EQ(grid.width, 0);
  EXPECT_EQ(grid.height, 0);
  EXPECT_TRUE(grid.cells.empty());
}

// The "key: value" lines of a YAML file.
std::map<std::string, std::string> ReadKeys(const std::filesystem::path& path) {
  std::map<std::string, std::string> keys;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    const std::size_t colon = line.find(": ");
    if (line.starts_with('#') || colon == std::string::npos) continue;
    keys[line.substr(0, colon)] = line.substr(colon + 2);
  }
  return keys;
}

// The numbers of a flow sequence such as "[[1, 2], [3, 4]]", in order.
std::vector<double> Numbers(std::string text) {
  for (char& c : text) {
    if (c == '[' || c == ']' || c == ',') c = ' ';
  }
  std::istringstream in(text);
  std::vector<double> numbers;
  for (double x; in >> x;) numbers.push_back(x);
  return numbers;
}

TEST(WriteOccupancyGrid, ThePgmIsTrinaryWithTheHighestYOnTop) {
  testing::TempDir dir;
  OccupancyGrid grid;
  grid.width = 3;
  grid.height = 2;
  grid.cells = {100, 0, -1,    // row 0: the lowest y
                0, -1, 100};  // row 1
  WriteOccupancyGrid(grid, dir / "occupancy.pgm", dir / "occupancy.yaml");

  std::ifstream pgm(dir / "occupancy.pgm", std::ios::binary);
  std::string magic;
  pgm >> magic;
  EXPECT_EQ(magic, "P5");  // binary
  const cv::Mat image = cv::imread((dir / "occupancy.pgm").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_8UC1);
  ASSERT_EQ(image.size(), cv::Size(3, 2));
  const cv::Mat expected = (cv::Mat_<std::uint8_t>(2, 3) << 254, 205, 0,  // the top row: grid row 1
                            0, 254, 205);
  EXPECT_EQ(cv::norm(image, expected, cv::NORM_INF), 0.0) << image;

  const std::map<std::string, std::string> keys = ReadKeys(dir / "occupancy.yaml");
  EXPECT_EQ(keys.at("image"), "occupancy.pgm");
  EXPECT_EQ(keys.at("resolution"), "0.05");
  EXPECT_EQ(keys.at("origin"), "[0, 0, 0.0]");
  EXPECT_EQ(keys.at("negate"), "0");
  EXPECT_EQ(keys.at("occupied_thresh"), "0.65");
  EXPECT_EQ(keys.at("free_thresh"), "0.196");
  EXPECT_EQ(keys.at("mode"), "trinary");
  EXPECT_THAT(Numbers(keys.at("floor_from_world")),
              ::testing::ElementsAre(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1));
}

TEST(WriteOccupancyGrid, TheYamlPlacesTheMapInTheWorld) {
  testing::TempDir dir;
  const core::Pose T_wf = kWorldFrames[1].second;
  WriteOccupancyGrid(MapTheRoom(OccupancyOptions{}, T_wf)->Project(T_wf.inverse()), dir / "occupancy.pgm",
                     dir / "occupancy.yaml");

  const std::map<std::string, std::string> keys = ReadKeys(dir / "occupancy.yaml");
  const double resolution = std::stod(keys.at("resolution"));
  const std::vector<double> origin = Numbers(keys.at("origin"));
  const std::vector<double> floor_from_world = Numbers(keys.at("floor_from_world"));
  ASSERT_EQ(origin.size(), 3U);
  ASSERT_EQ(floor_from_world.size(), 16U);
  const Eigen::Matrix4d T_fw = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(floor_from_world.data());
  const cv::Mat image = cv::imread((dir / keys.at("image")).string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(image.empty());

  // The pixel of a world point, as map_server places it: the image's bottom row at origin y.
  const auto pixel_at = [&](const Eigen::Vector3d& p_f) {
    const Eigen::Vector4d p = T_fw * (T_wf * p_f).homogeneous();
    const int column = static_cast<int>(std::floor((p.x() - origin[0]) / resolution));
    const int row = image.rows - 1 - static_cast<int>(std::floor((p.y() - origin[1]) / resolution));
    return static_cast<int>(image.at<std::uint8_t>(row, column));
  };
  EXPECT_EQ(pixel_at({0.75, 0.75, 0.6}), 0);  // the crate's top
  EXPECT_EQ(pixel_at({2.0, 1.5, 1.0}), 254);  // the camera's place
}

TEST(OccupancyFiles, AFileThatCannotBeWrittenIsNamedAndNothingIsLeft) {
  testing::TempDir dir;
  OccupancyGrid grid;
  grid.width = grid.height = 1;
  grid.cells = {OccupancyGrid::kOccupied};
  const std::filesystem::path missing = dir / "no-such-folder";
  const OccupancyMap map{OccupancyOptions{}};
  struct Case {
    std::function<void()> write;
    std::filesystem::path named;
  };
  for (const Case& c : {
           Case{[&] { map.WriteBinary(missing / "occupancy.bt"); }, missing / "occupancy.bt"},
           Case{[&] { WriteOccupancyGrid(grid, missing / "occupancy.pgm", dir / "occupancy.yaml"); },
                missing / "occupancy.pgm"},
           Case{[&] { WriteOccupancyGrid(grid, dir / "occupancy.pgm", missing / "occupancy.yaml"); },
                missing / "occupancy.yaml"},
           Case{[&] { WriteOccupancyGrid(OccupancyGrid{}, dir / "occupancy.pgm", dir / "occupancy.yaml"); },
                dir / "occupancy.pgm"},  // empty: nothing in the height band
       }) {
    EXPECT_THAT(testing::InputErrorOf(c.write), HasSubstr(c.named.string()));
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "a file of a failed write is left in " << dir.path();
  }
}

}  // namespace
}  // namespace hoidslam::dense
