#include "hoidslam/synth/static_geometry.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/test_scenarios.h"
#include "hoidslam/synth/world.h"
#include "support/geometry.h"
#include "support/input_error.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

using ::hoidslam::testing::PoseFromAxisAngle;
using ::testing::HasSubstr;

Box MakeBox(const core::Pose& T_wb, const Eigen::Vector3d& half_size) {
  Box box;
  box.T_wb = T_wb;
  box.half_size = half_size;
  return box;
}

Box AxisBox(const Eigen::Vector3d& centre, const Eigen::Vector3d& half_size) {
  return MakeBox(PoseFromAxisAngle(Eigen::Vector3d::Zero(), centre), half_size);
}

// Whether `mesh` holds the 8 corners of `box` in a row, as AppendBoxMesh puts them.
bool HoldsBox(const io::TriangleMesh& mesh, const Box& box) {
  io::TriangleMesh one;
  AppendBoxMesh(box, one);
  return std::search(mesh.vertices.begin(), mesh.vertices.end(), one.vertices.begin(), one.vertices.end()) !=
         mesh.vertices.end();
}

// Whether the cell whose centre is `centre` is among `voxels`.
bool HoldsCell(const io::VoxelCentres& voxels, const Eigen::Vector3d& centre) {
  return std::any_of(voxels.centres.begin(), voxels.centres.end(),
                     [&](const Eigen::Vector3f& c) { return (c.cast<double>() - centre).norm() < 1e-4; });
}

TEST(AppendBoxMesh, EnclosesTheBoxWithOutwardTriangles) {
  const Box box = MakeBox(PoseFromAxisAngle({0.3, -0.5, 0.8}, {1.0, 2.0, 0.5}), {0.4, 0.25, 0.1});
  io::TriangleMesh mesh;
  AppendBoxMesh(AxisBox({0, 0, 0}, {1, 1, 1}), mesh);  // a box before it: indices continue after its vertices
  AppendBoxMesh(box, mesh);
  ASSERT_EQ(mesh.vertices.size(), 16U);
  ASSERT_EQ(mesh.triangles.size(), 24U);
  double volume = 0.0;  // by the divergence theorem: positive, and the box's, when every triangle faces out
  for (std::size_t t = 12; t < 24; ++t) {
    const Eigen::Vector3i& triangle = mesh.triangles[t];
    EXPECT_GE(triangle.minCoeff(), 8);
    EXPECT_LT(triangle.maxCoeff(), 16);
    const Eigen::Vector3d a = mesh.vertices[static_cast<std::size_t>(triangle[0])].cast<double>();
    const Eigen::Vector3d b = mesh.vertices[static_cast<std::size_t>(triangle[1])].cast<double>();
    const Eigen::Vector3d c = mesh.vertices[static_cast<std::size_t>(triangle[2])].cast<double>();
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    // Counter-clockwise seen from outside: the normal points away from the centre, along one of the box's axes.
    EXPECT_GT(normal.dot((a + b + c) / 3.0 - box.T_wb.translation()), 0.0) << t;
    EXPECT_NEAR((box.T_wb.linear().transpose() * normal).cwiseAbs().maxCoeff(), 1.0, 1e-5) << t;
    volume += a.dot(b.cross(c)) / 6.0;
  }
  EXPECT_NEAR(volume, 8 * 0.4 * 0.25 * 0.1, 1e-6);
}

TEST(VoxelCells, HoldTheCellsWhoseCentreIsInsideABox) {
  // Faces on cell edges (multiples of 0.02 m), so no centre lies on a face: 20 x 16 x 90 cells.
  VoxelCells cells(0.02);
  cells.AddBox(AxisBox({3.0, 1.0, 0.9}, {0.2, 0.16, 0.9}));
  const io::VoxelCentres voxels = cells.Centres();
  EXPECT_EQ(voxels.voxel_size, 0.02);
  ASSERT_EQ(voxels.centres.size(), 20U * 16U * 90U);
  EXPECT_TRUE(std::is_sorted(voxels.centres.begin(), voxels.centres.end(), [](const auto& a, const auto& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  }));
  EXPECT_TRUE(voxels.centres.front().isApprox(Eigen::Vector3f(2.81F, 0.85F, 0.01F)));
  EXPECT_TRUE(voxels.centres.back().isApprox(Eigen::Vector3f(3.19F, 1.15F, 1.79F)));

  // A turned box: every centre inside it, about as many cells as its volume holds.
  const Box turned = MakeBox(PoseFromAxisAngle({0.2, 0.4, std::numbers::pi / 5}, {-1.0, 0.5, 1.2}), {0.3, 0.2, 0.1});
  VoxelCells turned_cells(0.02);
  turned_cells.AddBox(turned);
  const io::VoxelCentres inside = turned_cells.Centres();
  EXPECT_NEAR(static_cast<double>(inside.centres.size()), 8 * 0.3 * 0.2 * 0.1 / std::pow(0.02, 3), 60.0);
  for (const Eigen::Vector3f& centre : inside.centres) {
    const Eigen::Vector3d local = turned.T_wb.inverse() * centre.cast<double>();
    ASSERT_TRUE((local.cwiseAbs() - turned.half_size).maxCoeff() < 1e-6) << centre.transpose();
  }
  // Cells are kept once however often they are added.
  turned_cells.AddBox(turned);
  EXPECT_EQ(turned_cells.Centres().centres, inside.centres);
}

TEST(VoxelCells, RefuseABoxBeyondTheGrid) {
  VoxelCells cells(0.02);
  EXPECT_THAT(::hoidslam::testing::InputErrorOf([&] { cells.AddBox(AxisBox({3e4, 0.0, 0.0}, {0.1, 0.1, 0.1})); }),
              HasSubstr("lies beyond the 20972 m from the origin that the moving volume's grid covers"));
}

// An office of one desk with a cup on it; a person walks by and, at frame 3, carries the cup away; another person
// stands still throughout. Faces lie on cell edges.
const Box kDesk = AxisBox({1.0, 1.0, 0.4}, {0.5, 0.3, 0.4});
const Box kCupOnDesk = AxisBox({1.2, 1.1, 0.86}, {0.04, 0.04, 0.06});

SceneSnapshot Frame(int frame) {
  const double x = 3.0 + 0.5 * frame;  // the walker's centre
  const Box cup = frame < 3 ? kCupOnDesk : AxisBox({x + 0.3, 1.0, 1.0}, {0.04, 0.04, 0.06});
  return {0.1 * frame,
          {{1, "", false, {kDesk}},
           {2, "cup", frame == 3, {cup}},
           {3, "person", true, {AxisBox({x, 1.0, 0.9}, {0.2, 0.16, 0.9})}},
           {4, "person", false, {AxisBox({6.0, 3.0, 0.9}, {0.2, 0.16, 0.9})}}}};
}

struct Geometry {
  io::TriangleMesh mesh;
  io::VoxelCentres volume;
};

// What SequenceGeometry makes of these frames, added in this order after the first of them.
Geometry GeometryOfFrames(const std::vector<int>& frames) {
  SequenceGeometry geometry(Frame(frames.front()));
  for (const int frame : frames) geometry.Add(Frame(frame));
  return {geometry.StaticMesh(), geometry.MovingVolume()};
}

TEST(SequenceGeometry, TheMeshHoldsWhatStaysAndNotPeopleOrWhatIsPickedUpLater) {
  const io::TriangleMesh mesh = GeometryOfFrames({0, 1, 2, 3, 4, 5}).mesh;
  io::TriangleMesh desk;
  AppendBoxMesh(kDesk, desk);
  EXPECT_EQ(mesh.vertices, desk.vertices);  // the desk alone: not the cup, which rests there until frame 3
  EXPECT_EQ(mesh.triangles, desk.triangles);
  // Before the cup moves it is as static as the desk.
  const io::TriangleMesh before = GeometryOfFrames({0, 1, 2}).mesh;
  EXPECT_TRUE(HoldsBox(before, kCupOnDesk));
  EXPECT_FALSE(HoldsBox(before, Frame(0).instances[2].parts[0]));
}

TEST(SequenceGeometry, TheMovingVolumeHoldsWherePeopleAndMovedThingsWereAndNothingElse) {
  const io::VoxelCentres volume = GeometryOfFrames({0, 1, 2, 3, 4, 5}).volume;
  EXPECT_EQ(volume.voxel_size, kMovingVolumeVoxelSize);
  VoxelCells expected(kMovingVolumeVoxelSize);
  for (int frame = 0; frame <= 5; ++frame) {
    const SceneSnapshot snapshot = Frame(frame);
    for (std::size_t i = 1; i < 4; ++i) expected.AddBox(snapshot.instances[i].parts[0]);
  }
  EXPECT_EQ(volume.centres, expected.Centres().centres);
  EXPECT_TRUE(HoldsCell(volume, {3.01, 1.01, 1.21}));  // the walker at frame 0
  EXPECT_TRUE(HoldsCell(volume, {5.49, 1.01, 0.01}));  // and at frame 5
  EXPECT_FALSE(HoldsCell(volume, {3.25, 1.01, 1.21}));  // between frames 0 and 1: only the frames count
  EXPECT_TRUE(HoldsCell(volume, {1.21, 1.11, 0.85}));   // where the cup rested before it was carried away
  EXPECT_TRUE(HoldsCell(volume, {6.01, 3.01, 0.91}));   // the person standing still
  for (const Eigen::Vector3f& centre : volume.centres) {  // nothing of the desk
    ASSERT_GT(((kDesk.T_wb.inverse() * centre.cast<double>()).cwiseAbs() - kDesk.half_size).maxCoeff(), 0.0);
  }
}

TEST(SequenceGeometry, FramesInAnyOrderOrTwiceGiveTheSameResult) {
  const Geometry in_order = GeometryOfFrames({0, 1, 2, 3, 4, 5});
  const Geometry shuffled = GeometryOfFrames({4, 1, 5, 5, 0, 3, 2, 0});
  EXPECT_EQ(shuffled.mesh.vertices, in_order.mesh.vertices);
  EXPECT_EQ(shuffled.volume.centres, in_order.volume.centres);
}

TEST(SequenceGeometry, AnInstanceMissingFromSomeFrameIsNotStatic) {
  SequenceGeometry geometry(Frame(0));
  SceneSnapshot without_cup = Frame(1);
  without_cup.instances.erase(without_cup.instances.begin() + 1);
  geometry.Add(without_cup);
  EXPECT_FALSE(HoldsBox(geometry.StaticMesh(), kCupOnDesk));
  EXPECT_TRUE(HoldsCell(geometry.MovingVolume(), {1.21, 1.11, 0.85}));
}

TEST(SequenceGeometry, FilesOfASimulatedOfficeReadBackAsWritten) {
  // In the default office a person picks up a cup 1.5 s in and walks off with it.
  const Scenario scenario = fixtures::SmallScenario(R"([{"name": "p", "start": [3.6, 2.6], "actions": [
      {"action": "pick_up", "object": "cup_2", "at": 1.5}, {"action": "carry_to", "to": [5.0, 2.4]}]}])");
  const World world(scenario, fixtures::DefaultTextures());
  SequenceGeometry geometry(world.Snapshot(0.0));
  for (double t = 0.0; t <= world.end_time(); t += 0.1) geometry.Add(world.Snapshot(t));
  const SceneSnapshot first = world.Snapshot(0.0);
  const auto cup = std::find_if(first.instances.begin(), first.instances.end(),
                                [&](const SceneInstance& s) { return s.id == world.InstanceId("cup_2"); });
  ASSERT_NE(cup, first.instances.end());

  testing::TempDir dir;
  io::WritePlyMesh(dir / "static_geometry.ply", geometry.StaticMesh(), "hoidslam static geometry of small");
  io::WriteVoxelCentresPly(dir / "moving_volume.ply", geometry.MovingVolume());
  const io::TriangleMesh mesh = io::ReadPlyMesh(dir / "static_geometry.ply");
  const io::VoxelCentres volume = io::ReadVoxelCentresPly(dir / "moving_volume.ply");
  EXPECT_EQ(mesh.vertices, geometry.StaticMesh().vertices);
  EXPECT_EQ(mesh.triangles, geometry.StaticMesh().triangles);
  EXPECT_EQ(volume.voxel_size, kMovingVolumeVoxelSize);
  EXPECT_EQ(volume.centres, geometry.MovingVolume().centres);

  EXPECT_FALSE(HoldsBox(mesh, cup->parts[0]));  // picked up at 1.5 s: not static from the start either
  std::size_t static_boxes = 0;
  for (const SceneInstance& instance : first.instances) {
    if (instance.label == "person" || instance.id == cup->id) continue;
    static_boxes += instance.parts.size();
    for (const Box& box : instance.parts) EXPECT_TRUE(HoldsBox(mesh, box)) << instance.label << " " << instance.id;
  }
  EXPECT_EQ(mesh.vertices.size(), 8 * static_boxes);
  const Eigen::Vector3d rest = cup->parts[0].T_wb.translation();
  const Eigen::Vector3d cell = ((rest / kMovingVolumeVoxelSize).array().floor() + 0.5) * kMovingVolumeVoxelSize;
  EXPECT_TRUE(HoldsCell(volume, cell));
}

}  // namespace
}  // namespace hoidslam::synth
