#include "hoidslam/dense/display_mesh.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/input_error.h"
#include "support/temp_dir.h"
#include "support/text_file.h"

namespace hoidslam::dense {
namespace {

// The height of a gently waving floor of 1 m × 1 m, and its colour: red along x, green along y.
float Height(float x, float y) { return 0.05F * std::sin(6.0F * x) * std::cos(4.0F * y); }
cv::Vec3b ColourAt(float x, float y) {
  return {static_cast<std::uint8_t>(std::lround(255.0F * x)), static_cast<std::uint8_t>(std::lround(255.0F * y)), 128};
}

// The floor sampled every 5 mm: 40,401 vertices, 80,000 triangles, as a 1 cm TSDF mesh of it would hold.
io::TriangleMesh WavyFloor() {
  constexpr int kSteps = 200;
  io::TriangleMesh mesh;
  for (int j = 0; j <= kSteps; ++j) {
    for (int i = 0; i <= kSteps; ++i) {
      const float x = static_cast<float>(i) / kSteps, y = static_cast<float>(j) / kSteps;
      mesh.vertices.emplace_back(x, y, Height(x, y));
      mesh.rgb.push_back(ColourAt(x, y));
    }
  }
  for (int j = 0; j < kSteps; ++j) {
    for (int i = 0; i < kSteps; ++i) {
      const int a = j * (kSteps + 1) + i, b = a + 1, c = a + kSteps + 1, d = c + 1;
      mesh.triangles.emplace_back(a, b, d);
      mesh.triangles.emplace_back(a, d, c);
    }
  }
  return mesh;
}

TEST(MeshForDisplay, KeepsTheBudgetTheSurfaceAndItsColours) {
  const io::TriangleMesh floor = WavyFloor();
  for (const std::size_t budget : {20000U, 3000U}) {
    const io::TriangleMesh small = MeshForDisplay(floor, budget);
    EXPECT_LE(small.triangles.size(), budget);
    // About the finest cell that fits, not one far coarser.
    EXPECT_GT(small.triangles.size(), budget / 4) << budget;
    ASSERT_EQ(small.rgb.size(), small.vertices.size());
    for (std::size_t i = 0; i < small.vertices.size(); ++i) {
      const Eigen::Vector3f& v = small.vertices[i];
      // A cell's mean lies on the surface within what its curvature bends away over a few centimetres.
      EXPECT_NEAR(v.z(), Height(v.x(), v.y()), 0.004F) << budget << " vertex " << i;
      // Colours that change linearly over the floor average to the colour at the mean position.
      const cv::Vec3b expected = ColourAt(v.x(), v.y());
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(small.rgb[i][c], expected[c], 2) << budget << " vertex " << i;
    }
    for (const Eigen::Vector3i& t : small.triangles) {
      for (int corner = 0; corner < 3; ++corner) ASSERT_LT(static_cast<std::size_t>(t[corner]), small.vertices.size());
    }
  }
}

TEST(MeshForDisplay, AMeshWithinTheBudgetIsKeptAsItIs) {
  const io::TriangleMesh floor = WavyFloor();
  const io::TriangleMesh same = MeshForDisplay(floor, floor.triangles.size());
  EXPECT_EQ(same.vertices, floor.vertices);
  EXPECT_EQ(same.triangles, floor.triangles);
  EXPECT_EQ(same.rgb, floor.rgb);
}

TEST(MeshForDisplay, AMeshWithoutColoursStaysWithout) {
  io::TriangleMesh floor = WavyFloor();
  floor.rgb.clear();
  const io::TriangleMesh small = MeshForDisplay(floor, 1000);
  EXPECT_LE(small.triangles.size(), 1000U);
  EXPECT_GT(small.triangles.size(), 0U);
  EXPECT_TRUE(small.rgb.empty());
}

TEST(MeshForDisplay, RefusesANoughtBudgetAndColoursThatDoNotFit) {
  io::TriangleMesh floor = WavyFloor();
  EXPECT_THROW(MeshForDisplay(floor, 0), std::invalid_argument);
  floor.rgb.pop_back();
  EXPECT_THROW(MeshForDisplay(floor, 1000), std::invalid_argument);
}

TEST(ReadMeshForDisplay, ReadsAFileOrSaysThereIsNone) {
  const testing::TempDir dir;
  EXPECT_FALSE(ReadMeshForDisplay(dir / "mesh.ply", 1000).has_value());
  io::WritePlyMesh(dir / "mesh.ply", WavyFloor(), "floor");
  const std::optional<io::TriangleMesh> read = ReadMeshForDisplay(dir / "mesh.ply", 1000);
  ASSERT_TRUE(read.has_value());
  EXPECT_LE(read->triangles.size(), 1000U);
  EXPECT_EQ(read->rgb.size(), read->vertices.size());
  ::hoidslam::testing::WriteText(dir / "broken.ply", "ply\nformat ascii 1.0\n");
  EXPECT_THAT(::hoidslam::testing::InputErrorOf([&] { ReadMeshForDisplay(dir / "broken.ply", 1000); }),
              ::testing::HasSubstr("broken.ply"));
}

}  // namespace
}  // namespace hoidslam::dense
