#include "hoidslam/viewer/viewer.h"

#include <httplib.h>

#include <fstream>
#include <map>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/report/page_json.h"
#include "support/temp_dir.h"

namespace hoidslam::viewer {
namespace {

using ::testing::HasSubstr;

// A page folder with a stand-in index.html, and a viewer on a free port serving it.
struct Served {
  testing::TempDir web;
  pipeline::Playback playback;
  std::unique_ptr<Viewer> viewer;

  explicit Served(bool controllable = true) {
    std::ofstream(web / "index.html") << "<!doctype html><title>hoidslam viewer</title>";
    ViewerOptions options;
    options.port = 0;
    options.web_dir = web.path();
    options.map_interval_s = 0.02;
    viewer = std::make_unique<Viewer>(options, ViewerHello{"walk", 30, {}}, controllable ? &playback : nullptr);
  }

  httplib::Client Client() const { return httplib::Client(viewer->url().substr(0, viewer->url().size() - 1)); }
};

FrameSnapshot Snapshot(std::size_t index) {
  FrameSnapshot snapshot;
  snapshot.index = index;
  snapshot.image = cv::Mat(48, 64, CV_8UC3, cv::Scalar(0, 128, 255));
  snapshot.keypoints = {5.0F, 6.0F, 30.0F, 20.0F};
  snapshot.keep = {1, 0};
  snapshot.T_wc = core::Pose::Identity();
  snapshot.entry = {{"frame", index}, {"state", "ok"}, {"map", 0}, {"features", {{"kept", 1}, {"dropped", 1}}}};
  return snapshot;
}

slam::AtlasView ThreePoints() {
  slam::AtlasView atlas;
  for (slam::MapPointId id = 0; id < 3; ++id) atlas.points.push_back({id, 0, Eigen::Vector3f(0, 0, 1), cv::Vec3b()});
  atlas.keyframes.push_back({0, 0, core::Pose::Identity()});
  return atlas;
}

// The events a page gets on /events until `enough` says it has what it waits for: name → data of the latest.
std::map<std::string, nlohmann::json> ReadEvents(httplib::Client& client,
                                                 const std::function<bool(const std::map<std::string, nlohmann::json>&)>& enough) {
  std::map<std::string, nlohmann::json> latest;
  std::string buffer;
  client.Get("/events", [&](const char* data, std::size_t length) {
    buffer.append(data, length);
    for (std::size_t end; (end = buffer.find("\n\n")) != std::string::npos; buffer.erase(0, end + 2)) {
      const std::string message = buffer.substr(0, end);
      if (!message.starts_with("event: ")) continue;  // a comment: nothing new
      const std::size_t newline = message.find('\n');
      latest[message.substr(7, newline - 7)] = nlohmann::json::parse(message.substr(newline + 7));  // "data: "
    }
    return !enough(latest);
  });
  return latest;
}

TEST(Viewer, ServesThePageAndSendsEachPageTheRunAsItGoes) {
  Served served;
  httplib::Client client = served.Client();
  const httplib::Result page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_THAT(page->body, HasSubstr("hoidslam viewer"));

  served.viewer->Publish(Snapshot(0));
  served.viewer->FollowMap(ThreePoints);
  const auto events = ReadEvents(client, [](const auto& latest) {
    return latest.contains("frame") && latest.contains("map") && latest.contains("status");
  });
  ASSERT_TRUE(events.contains("hello"));
  EXPECT_EQ(events.at("hello")["sequence"], "walk");
  EXPECT_EQ(events.at("hello")["total_frames"], 30);
  EXPECT_TRUE(events.at("hello")["controllable"]);
  EXPECT_EQ(events.at("map")["points"]["ids"].size(), 3U);
  EXPECT_EQ(events.at("frame")["kept"], 1);
  EXPECT_EQ(events.at("status")["state"], "running");

  slam::AtlasView final_map = ThreePoints();
  final_map.points.pop_back();
  served.viewer->FinalMap(final_map, 0);
  served.viewer->RunFinished();
  const auto after = ReadEvents(client, [](const auto& latest) {
    return latest.contains("status") && latest.at("status")["state"] == "finished";
  });
  EXPECT_EQ(after.at("map")["maps"][0]["points"], 2);  // a new page gets the final map whole
  EXPECT_GE(served.viewer->FramesSent(), 2U);
}

// A square of two triangles at depth `z`, coloured.
io::TriangleMesh Square(float z) {
  io::TriangleMesh mesh;
  mesh.vertices = {{0, 0, z}, {1, 0, z}, {0, 1, z}, {1, 1, z}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  for (const std::uint8_t grey : {10, 90, 170, 250}) mesh.rgb.emplace_back(grey, 255 - grey, 128);
  return mesh;
}

TEST(Viewer, EachPageGetsTheNewestDenseMap) {
  Served served;
  httplib::Client client = served.Client();
  const auto first = ReadEvents(client, [](const auto& latest) { return latest.contains("hello"); });
  EXPECT_FALSE(first.contains("dense")) << "no dense map before the run shows one";

  io::TriangleMesh two_squares = Square(1.0F);
  const io::TriangleMesh far = Square(2.0F);
  two_squares.vertices.insert(two_squares.vertices.end(), far.vertices.begin(), far.vertices.end());
  two_squares.rgb.insert(two_squares.rgb.end(), far.rgb.begin(), far.rgb.end());
  for (const Eigen::Vector3i& t : far.triangles) two_squares.triangles.emplace_back(t + Eigen::Vector3i::Constant(4));
  served.viewer->ShowDenseMap(Square(1.0F));
  served.viewer->ShowDenseMap(two_squares);  // the newest wins
  const auto events = ReadEvents(client, [](const auto& latest) { return latest.contains("dense"); });
  const nlohmann::json& dense = events.at("dense");
  EXPECT_EQ(dense.at("vertices"), 8);
  EXPECT_EQ(dense.at("triangles"), 4);
  EXPECT_EQ(dense.at("positions"), report::DenseMeshJson(two_squares).at("positions"));
  EXPECT_EQ(dense.at("indices").get<std::string>().size(), 4U * 4 * 3 * 4 / 3);  // base64 of 4 × 3 uint32

  // A page that connects later gets it too, without waiting for anything newer.
  httplib::Client later = served.Client();
  EXPECT_EQ(ReadEvents(later, [](const auto& latest) { return latest.contains("dense"); }).at("dense").at("triangles"), 4);
}

TEST(Viewer, ThePagesControlsPauseStepAndSpeedTheRunAndNonsenseIsRefused) {
  Served served;
  httplib::Client client = served.Client();
  const auto post = [&](const std::string& body) { return client.Post("/control", body, "application/json"); };
  httplib::Result paused = post(R"({"command": "pause"})");
  ASSERT_TRUE(paused);
  EXPECT_EQ(paused->status, 200);
  EXPECT_TRUE(nlohmann::json::parse(paused->body)["paused"]);
  EXPECT_TRUE(served.playback.state().paused);
  ASSERT_EQ(post(R"({"command": "speed", "speed": 2})")->status, 200);
  EXPECT_EQ(served.playback.state().speed, 2.0);
  ASSERT_EQ(post(R"({"command": "play"})")->status, 200);
  EXPECT_FALSE(served.playback.state().paused);

  const httplib::Result too_fast = post(R"({"command": "speed", "speed": 1000})");
  EXPECT_EQ(too_fast->status, 400);
  EXPECT_THAT(too_fast->body, HasSubstr("speed"));
  EXPECT_EQ(post(R"({"command": "rewind"})")->status, 400);
  EXPECT_EQ(post("pause")->status, 400);

  Served paced(false);
  httplib::Client paced_client = paced.Client();
  EXPECT_EQ(paced_client.Post("/control", R"({"command": "pause"})", "application/json")->status, 409);
}

TEST(Viewer, AClosedPageNeitherHoldsUpTheRunNorTheViewersEnd) {
  Served served;
  served.viewer->Publish(Snapshot(0));
  httplib::Client client = served.Client();
  ReadEvents(client, [](const auto& latest) { return latest.contains("frame"); });  // then the page goes
  httplib::Client open = served.Client();
  std::thread still_open([&] { ReadEvents(open, [](const auto&) { return false; }); });  // until the viewer ends
  for (std::size_t i = 1; i < 200; ++i) served.viewer->Publish(Snapshot(i));
  served.viewer.reset();  // with a page still connected
  still_open.join();
}

TEST(Viewer, APortInUseOrAMissingPageIsNamed) {
  Served first;
  const std::string url = first.viewer->url();
  ViewerOptions options;
  options.web_dir = first.web.path();
  options.port = std::stoi(url.substr(url.rfind(':') + 1));
  try {
    Viewer second(options, {}, nullptr);
    ADD_FAILURE() << "a second viewer listened on " << url;
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--view-port"));
  }
  testing::TempDir empty;
  options.web_dir = empty.path();
  options.port = 0;
  try {
    Viewer without_page(options, {}, nullptr);
    ADD_FAILURE() << "a viewer started without its page";
  } catch (const core::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("index.html"));
  }
}

}  // namespace
}  // namespace hoidslam::viewer
