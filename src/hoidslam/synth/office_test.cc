#include "hoidslam/synth/office.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <vector>

#include "hoidslam/core/error.h"

namespace hoidslam::synth {
namespace {

using ::testing::HasSubstr;

constexpr ObjectKind kAllKinds[] = {ObjectKind::kTv,   ObjectKind::kKeyboard, ObjectKind::kMouse,  ObjectKind::kLaptop,
                                    ObjectKind::kBook, ObjectKind::kCup,      ObjectKind::kBottle, ObjectKind::kChair};

TEST(Office, DefaultLayoutIsValidAndHasEveryKindOfObject) {
  const OfficeLayout office = DefaultOfficeLayout();
  EXPECT_NO_THROW(office.Check("office.json", "office"));
  EXPECT_EQ(office.desks.size(), 4U);
  std::set<ObjectKind> kinds;
  int chairs = 0;
  for (const OfficeObject& object : office.objects) {
    kinds.insert(object.kind);
    chairs += object.kind == ObjectKind::kChair ? 1 : 0;
  }
  EXPECT_EQ(kinds.size(), std::size(kAllKinds));
  EXPECT_GE(chairs, 4);
  EXPECT_LE(chairs, 6);
}

TEST(Office, ObjectsStandOnTheDeskBelowThemOrTheFloor) {
  const OfficeLayout office = DefaultOfficeLayout();
  EXPECT_DOUBLE_EQ(office.RestPose(*office.FindObject("tv_1")).translation().z(), 0.74);
  EXPECT_DOUBLE_EQ(office.RestPose(*office.FindObject("chair_1")).translation().z(), 0.0);
  EXPECT_DOUBLE_EQ(office.RestPose(*office.FindObject("book_4")).translation().z(), 0.66);  // on a shelf board
  EXPECT_DOUBLE_EQ(office.SupportHeightAt({3.2, 3.9}), 0.74);
  EXPECT_DOUBLE_EQ(office.SupportHeightAt({3.2, 2.0}), 0.0);
  EXPECT_TRUE(office.IsBlocked({3.2, 3.9}, 0.0));
  EXPECT_TRUE(office.IsBlocked({3.2, 3.4}, 0.25));
  EXPECT_FALSE(office.IsBlocked({3.2, 2.5}, 0.25));
}

TEST(Office, PartsLieWithinTheDeclaredExtents) {
  const TextureSet textures;
  for (const ObjectKind kind : kAllKinds) {
    SCOPED_TRACE(std::string(CocoLabel(kind)));
    const Eigen::Vector3d ext = ObjectHalfExtents(kind);
    const std::vector<Box> parts = ObjectParts(kind, 1, textures);
    ASSERT_FALSE(parts.empty());
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9);
    Eigen::Vector3d hi = -lo;
    for (const Box& box : parts) {
      for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d signs(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1);
        const Eigen::Vector3d p = box.T_wb * box.half_size.cwiseProduct(signs);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    // The object stands on z = 0, and the extents enclose the parts tightly (to a centimetre on the wider side).
    EXPECT_NEAR(lo.z(), 0.0, 1e-9);
    EXPECT_NEAR(hi.z(), 2.0 * ext.z(), 0.01);
    for (int axis = 0; axis < 2; ++axis) {
      EXPECT_LE(hi[axis], ext[axis] + 1e-9);
      EXPECT_LE(-lo[axis], ext[axis] + 1e-9);
      EXPECT_NEAR(std::max(hi[axis], -lo[axis]), ext[axis], 0.01);
    }
  }
}

TEST(Office, RoutesGoRoundDesksAndShelves) {
  const OfficeLayout office = DefaultOfficeLayout();
  // In the open: straight.
  const auto straight = office.Route({1.0, 2.5}, {7.0, 2.5}, 0.3);
  ASSERT_TRUE(straight.has_value());
  ASSERT_EQ(straight->size(), 1U);
  EXPECT_TRUE((*straight)[0].isApprox(Eigen::Vector2d(7.0, 2.5)));
  // From in front of the middle desks to behind them: round a corner, never over a desk or the shelf.
  const Eigen::Vector2d from(3.6, 2.6);
  const Eigen::Vector2d to(3.6, 4.95);
  const auto route = office.Route(from, to, 0.3);
  ASSERT_TRUE(route.has_value());
  ASSERT_GE(route->size(), 2U);
  EXPECT_TRUE(route->back().isApprox(to));
  Eigen::Vector2d a = from;
  double length = 0.0;
  for (const Eigen::Vector2d& b : *route) {
    for (double s = 0.0; s <= 1.0; s += 0.01) EXPECT_FALSE(office.IsBlocked(a + s * (b - a), 0.25)) << b.transpose();
    length += (b - a).norm();
    a = b;
  }
  EXPECT_LT(length, 6.0);  // round the nearer end of the desk row, not the far one
  // Into the middle of a desk there is no way: no route rather than a straight line through the desk.
  EXPECT_FALSE(office.Route({3.2, 2.6}, {3.2, 3.9}, 0.3).has_value());
}

TEST(Office, LabelsAreCocoClasses) {
  EXPECT_EQ(CocoClassId("person"), 0);
  EXPECT_EQ(CocoClassId(CocoLabel(ObjectKind::kTv)), 62);
  EXPECT_EQ(CocoClassId(CocoLabel(ObjectKind::kBook)), 73);
  EXPECT_EQ(CocoClassId("dog"), -1);
  EXPECT_EQ(ParseObjectKind("laptop", "p"), ObjectKind::kLaptop);
  EXPECT_THROW(ParseObjectKind("mug", "p"), core::InputError);
}

TEST(Office, CheckNamesTheBadEntry) {
  OfficeLayout office = DefaultOfficeLayout();
  office.objects.push_back({"tv_1", ObjectKind::kCup, {1.0, 1.0}, std::nullopt, 0.0, 0});
  try {
    office.Check("o.json", "office");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("o.json: office.objects["));
    EXPECT_THAT(e.what(), HasSubstr("duplicate name 'tv_1'"));
  }
  office = DefaultOfficeLayout();
  office.desks[1].position = {9.0, 1.0};
  EXPECT_THROW(office.Check("o.json", "office"), core::InputError);
}

std::string CheckMessage(const OfficeLayout& office, const OfficeLayout& base) {
  try {
    office.Check("o.json", "office", base);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Office, CheckNamesTheUsersOwnIndexAfterABase) {
  const OfficeLayout base = DefaultOfficeLayout();
  OfficeLayout office = base;
  office.desks.push_back({"desk_9", {3.0, 1.0}, 0.0});
  office.desks.push_back({"desk_10", {9.0, 1.0}, 0.0});
  EXPECT_THAT(CheckMessage(office, base), HasSubstr("o.json: office.desks[1].position: outside the room"));
  office = base;
  office.objects.push_back({"cup_1", ObjectKind::kCup, {1.0, 1.0}, std::nullopt, 0.0, 0});
  EXPECT_THAT(CheckMessage(office, base),
              HasSubstr("o.json: office.objects[0].name: duplicate name 'cup_1' (the base office has it)"));
  // A base entry can only go wrong in a smaller room: the room is named.
  office = base;
  office.room = {4.0, 4.0, 2.8};
  EXPECT_THAT(CheckMessage(office, base), HasSubstr("o.json: office.room: desk_2 of the base office"));
}

TEST(Office, StructureIsUnlabelledWithConsecutiveIds) {
  const TextureSet textures;
  const std::vector<SceneInstance> structure = BuildStructure(DefaultOfficeLayout(), textures, 1);
  ASSERT_GE(structure.size(), 8U);  // floor, ceiling, walls, wall panels, 4 desks, shelf, cabinet
  for (std::size_t i = 0; i < structure.size(); ++i) {
    EXPECT_EQ(structure[i].id, static_cast<int>(i) + 1);
    EXPECT_TRUE(structure[i].label.empty());
    EXPECT_FALSE(structure[i].moving);
    for (const Box& box : structure[i].parts) EXPECT_LT(box.texture, textures.size());
  }
}

TEST(Office, OwnWallPanelsReplaceTheDefaultDecorationAndStandInsideTheirWalls) {
  const TextureSet textures;
  OfficeLayout office;
  office.room = {6.0, 5.0, 2.7};
  office.desks = {Desk{"desk_1", {3.0, 2.5}, 0.0}};
  const std::size_t decorated = BuildStructure(office, textures, 1).size();
  office.walls.emplace();
  // Floor, ceiling, walls and the desk: no panels, no cabinet.
  EXPECT_EQ(BuildStructure(office, textures, 1).size(), 4U);
  EXPECT_EQ(decorated, 6U);  // and the default panels and the cabinet
  office.walls = std::vector<WallPanel>{{PanelKind::kPoster, Wall::kFront, 2.0, 1.6, {0.6, 0.8}, 1},
                                        {PanelKind::kDoor, Wall::kRight, 1.0, 1.05, {0.95, 2.1}, 0},
                                        {PanelKind::kWhiteboard, Wall::kBack, 4.0, 1.45, {1.6, 1.0}, 0},
                                        {PanelKind::kPoster, Wall::kLeft, 3.0, 1.6, {0.6, 0.8}, 2}};
  office.Check("o.json", "office");
  const std::vector<SceneInstance> structure = BuildStructure(office, textures, 1);
  ASSERT_EQ(structure.size(), 5U);
  const std::vector<Box>& panels = structure[3].parts;
  ASSERT_EQ(panels.size(), 4U);
  // Each panel's centre lies just inside its wall, at its place along it.
  const std::array<Eigen::Vector3d, 4> centres = {Eigen::Vector3d(2.0, 0.01, 1.6), Eigen::Vector3d(5.99, 1.0, 1.05),
                                                  Eigen::Vector3d(4.0, 4.99, 1.45), Eigen::Vector3d(0.01, 3.0, 1.6)};
  for (std::size_t i = 0; i < panels.size(); ++i) {
    EXPECT_LT((panels[i].T_wb.translation() - centres[i]).norm(), 1e-9) << i;
  }
  EXPECT_EQ(panels[0].texture, textures.Index(TextureRole::kPoster, 1));
  EXPECT_EQ(panels[3].texture, textures.Index(TextureRole::kPoster, 2));
  // A panel hanging off its wall is named.
  (*office.walls)[3].at = 4.8;
  EXPECT_THAT([&] { office.Check("o.json", "office"); },
              ::testing::ThrowsMessage<core::InputError>(HasSubstr("o.json: office.walls[3].at: a panel 0.6 m wide")));
}

TEST(Office, PatchworkWallsCoverEveryWallWithPiecesOfVariedPhotos) {
  const TextureSet textures;
  OfficeLayout office;
  office.room = {7.3, 5.6, 2.9};
  office.desks = {Desk{"desk_1", {3.0, 2.5}, 0.0}};
  office.patchwork_walls_seed = 17;
  const std::vector<Box> pieces = BuildStructure(office, textures, 1)[2].parts;
  const std::set<int> posters = [&] {
    std::set<int> all;
    for (int v = 0; v < textures.VariantCount(TextureRole::kPoster); ++v) {
      all.insert(textures.Index(TextureRole::kPoster, v));
    }
    return all;
  }();
  double area = 0.0;
  std::set<int> used;
  for (const Box& piece : pieces) {
    // Behind the wall plane, its inside face on it: the room's own walls stay where they were.
    const Eigen::Vector3d centre = piece.T_wb.translation();
    const Eigen::Vector3d& room = office.room;
    const double behind = std::min({centre.x(), centre.y(), room.x() - centre.x(), room.y() - centre.y()});
    EXPECT_NEAR(behind, -piece.half_size.x(), 1e-9);
    EXPECT_GE(piece.half_size.y() * 2, 0.8 - 1e-9);
    EXPECT_LE(piece.half_size.y() * 2, 2.4 + 1e-9);
    EXPECT_TRUE(posters.contains(piece.texture));
    EXPECT_DOUBLE_EQ(piece.texture_scale, 2 * std::max(piece.half_size.y(), piece.half_size.z())) << "shown once";
    area += 4 * piece.half_size.y() * piece.half_size.z();
    used.insert(piece.texture);
  }
  EXPECT_NEAR(area, 2 * (office.room.x() + office.room.y()) * office.room.z(), 1e-9) << "the walls, whole";
  EXPECT_EQ(used.size(), posters.size());
  // Two pieces one above the other never show the same photo.
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    const Box& a = pieces[i - 1];
    const Box& b = pieces[i];
    if ((a.T_wb.translation().head<2>() - b.T_wb.translation().head<2>()).norm() < 1e-9) {
      EXPECT_NE(a.texture, b.texture) << i;
    }
  }
  // The seed draws the patchwork.
  office.patchwork_walls_seed = 18;
  const std::vector<Box> other = BuildStructure(office, textures, 1)[2].parts;
  EXPECT_TRUE(other.size() != pieces.size() ||
              !std::equal(other.begin(), other.end(), pieces.begin(),
                          [](const Box& a, const Box& b) { return a.texture == b.texture; }));
}

}  // namespace
}  // namespace hoidslam::synth
