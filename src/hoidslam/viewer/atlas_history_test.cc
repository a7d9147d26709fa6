#include "hoidslam/viewer/atlas_history.h"

#include <algorithm>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace hoidslam::viewer {
namespace {

slam::AtlasView Atlas(int points, int keyframes) {
  slam::AtlasView atlas;
  for (int i = 0; i < points; ++i) {
    atlas.points.push_back({static_cast<slam::MapPointId>(i), 0, Eigen::Vector3f(0.1F * i, 0.0F, 2.0F),
                            cv::Vec3b(10, 20, 30)});
  }
  for (int i = 0; i < keyframes; ++i) {
    core::Pose pose = core::Pose::Identity();
    pose.translation() = Eigen::Vector3d(0.05 * i, 0.0, 0.0);
    atlas.keyframes.push_back({static_cast<slam::KeyFrameId>(i), 0, pose});
  }
  if (keyframes > 1) atlas.covisibility.emplace_back(0, 1);
  return atlas;
}

nlohmann::json Since(const AtlasHistory& history, std::uint64_t since) {
  return nlohmann::json::parse(history.EventJsonSince(since));
}

TEST(AtlasHistory, AFirstPageGetsTheWholeMapWithItsColoursAsRgb) {
  AtlasHistory history;
  ASSERT_TRUE(history.Update(Atlas(5, 2), 0));
  const nlohmann::json event = Since(history, 0);
  EXPECT_TRUE(event["full"]);
  EXPECT_EQ(event["revision"], 1);
  EXPECT_EQ(event["points"]["ids"].size(), 5U);
  EXPECT_EQ(event["points"]["xyz"].size(), 15U);
  EXPECT_EQ(event["points"]["rgb"][0], 30);  // BGR (10, 20, 30) as r, g, b
  EXPECT_EQ(event["keyframes"].size(), 2U);
  for (const nlohmann::json& keyframe : event["keyframes"]) {
    EXPECT_EQ(keyframe["T_wc"][3], keyframe["id"] == 1 ? 0.05 : 0.0);  // x of the camera centre
  }
  EXPECT_EQ(event["covisibility"], nlohmann::json::parse("[[0,1]]"));
  EXPECT_EQ(event["maps"], nlohmann::json::parse(R"([{"id":0,"points":5,"keyframes":2}])"));
}

TEST(AtlasHistory, APageGetsOnlyWhatChangedSinceItsRevision) {
  AtlasHistory history;
  history.Update(Atlas(5, 2), 0);
  EXPECT_FALSE(history.Update(Atlas(5, 2), 0));  // nothing new: no revision
  EXPECT_EQ(history.revision(), 1U);

  slam::AtlasView moved = Atlas(5, 3);
  moved.points[2].position.z() += 1e-5F;  // a loop closing's tiniest move is still a move
  moved.points.erase(moved.points.begin() + 4);
  ASSERT_TRUE(history.Update(moved, 0));
  const nlohmann::json event = Since(history, 1);
  EXPECT_FALSE(event["full"]);
  EXPECT_EQ(event["points"]["ids"], nlohmann::json::parse("[2]"));
  EXPECT_EQ(event["removed_points"], nlohmann::json::parse("[4]"));
  ASSERT_EQ(event["keyframes"].size(), 1U);
  EXPECT_EQ(event["keyframes"][0]["id"], 2);
  EXPECT_FALSE(event.contains("covisibility"));  // the edges did not change
  EXPECT_EQ(event["maps"][0]["points"], 4);
}

TEST(AtlasHistory, APageTooFarBehindGetsTheWholeMapAgain) {
  AtlasHistory history;
  for (int n = 1; n <= static_cast<int>(AtlasHistory::kRemembered) + 5; ++n) history.Update(Atlas(n, 1), 0);
  history.Update(Atlas(3, 1), 0);  // points removed
  const nlohmann::json behind = Since(history, 2);
  EXPECT_TRUE(behind["full"]);
  EXPECT_EQ(behind["points"]["ids"].size(), 3U);
  EXPECT_TRUE(behind["removed_points"].empty());
  const nlohmann::json recent = Since(history, history.revision() - 1);
  EXPECT_FALSE(recent["full"]);
  EXPECT_EQ(recent["removed_points"].size(), AtlasHistory::kRemembered + 2);
}

TEST(AtlasHistory, TellsMapsApartAndNamesTheMainOne) {
  slam::AtlasView atlas = Atlas(4, 2);
  atlas.points[3].map = 1;
  atlas.keyframes[1].map = 1;
  AtlasHistory history;
  history.Update(atlas, 1);
  const nlohmann::json event = Since(history, 0);
  EXPECT_EQ(event["main_map"], 1);
  EXPECT_EQ(event["maps"], nlohmann::json::parse(R"([{"id":0,"points":3,"keyframes":1},{"id":1,"points":1,"keyframes":1}])"));
  EXPECT_TRUE(history.Update(atlas, 0));  // the main map alone changed
}

}  // namespace
}  // namespace hoidslam::viewer
