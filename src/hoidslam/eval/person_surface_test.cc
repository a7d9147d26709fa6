#include "hoidslam/eval/person_surface.h"

#include <gtest/gtest.h>

namespace hoidslam::eval {
namespace {

// A camera at the origin looking along z at a wall 3 m away; a person 1.5 m away stands in pixels 40–59 × 20–79 of a
// 100×100 image, and the detector's box is wider than the person (30–69 × 15–84), so it also shows wall.
struct Scene {
  core::CameraIntrinsics camera;
  cv::Rect person{40, 20, 20, 60};
  cv::Rect box{30, 15, 40, 70};
  Scene() {
    camera.fx = camera.fy = 100.0;
    camera.cx = camera.cy = 50.0;
    camera.width = camera.height = 100;
  }
  PersonView View() const {
    cv::Mat depth(camera.height, camera.width, CV_32FC1, cv::Scalar(3.0F));
    depth(person).setTo(1.5F);
    return {core::Pose::Identity(), box, depth(box).clone()};
  }
  // Surface samples 1 cm apart on the plane z = `depth` over the pixels of `region`.
  std::vector<Eigen::Vector3f> Plane(const cv::Rect& region, float depth) const {
    std::vector<Eigen::Vector3f> samples;
    const float x0 = static_cast<float>((region.x - camera.cx) * depth / camera.fx);
    const float x1 = static_cast<float>((region.br().x - camera.cx) * depth / camera.fx);
    const float y0 = static_cast<float>((region.y - camera.cy) * depth / camera.fy);
    const float y1 = static_cast<float>((region.br().y - camera.cy) * depth / camera.fy);
    for (float y = y0; y < y1; y += 0.01F) {
      for (float x = x0; x < x1; x += 0.01F) samples.emplace_back(x, y, depth);
    }
    return samples;
  }
};

TEST(MeasurePersonSurface, AMapOfTheWallAloneHasNoneOfThePerson) {
  const Scene scene;
  // The wall everywhere, behind the person too (seen from other views): it agrees with the depth measured beside
  // the person inside the box, but those pixels are not at the person's depth.
  const PersonSurface surface =
      MeasurePersonSurface(scene.Plane({0, 0, 100, 100}, 3.0F), 0.01, {scene.View()}, scene.camera);
  EXPECT_EQ(surface.boxes, 1U);
  EXPECT_EQ(surface.person_pixels, static_cast<std::size_t>(scene.person.area()));
  EXPECT_EQ(surface.fused_pixels, 0U);
}

TEST(MeasurePersonSurface, AMapWithThePersonFusedHasThemAll) {
  const Scene scene;
  std::vector<Eigen::Vector3f> map = scene.Plane({0, 0, 100, 100}, 3.0F);
  const std::vector<Eigen::Vector3f> person = scene.Plane(scene.person, 1.5F);
  map.insert(map.end(), person.begin(), person.end());
  const PersonSurface surface = MeasurePersonSurface(map, 0.01, {scene.View()}, scene.camera);
  EXPECT_GT(surface.Share(), 0.97);
}

TEST(MeasurePersonSurface, HalfThePersonFusedIsHalf) {
  const Scene scene;
  const cv::Rect upper(scene.person.x, scene.person.y, scene.person.width, scene.person.height / 2);
  const PersonSurface surface = MeasurePersonSurface(scene.Plane(upper, 1.5F), 0.01, {scene.View()}, scene.camera);
  EXPECT_NEAR(surface.Share(), 0.5, 0.05);
}

TEST(MeasurePersonSurface, SurfaceSeenThroughIsNotThePerson) {
  // Surface 40 cm in front of the person (a ghost of someone who stood there earlier) is not where the camera
  // measured the person, and a box without depth in its middle is not judged.
  const Scene scene;
  PersonView blind = scene.View();
  blind.depth.setTo(0.0F);
  const PersonSurface surface =
      MeasurePersonSurface(scene.Plane(scene.person, 1.1F), 0.01, {scene.View(), blind}, scene.camera);
  EXPECT_EQ(surface.boxes, 1U);
  EXPECT_EQ(surface.fused_pixels, 0U);
}

TEST(MeasurePersonSurface, TheViewsPoseTakesTheMapIntoTheCamera) {
  // The camera stands 1 m to the right of the map's origin: the person fused at x + 1 is where the view sees them.
  const Scene scene;
  PersonView view = scene.View();
  view.T_wc.translation() = Eigen::Vector3d(1.0, 0.0, 0.0);
  std::vector<Eigen::Vector3f> person = scene.Plane(scene.person, 1.5F);
  for (Eigen::Vector3f& p : person) p.x() += 1.0F;
  EXPECT_GT(MeasurePersonSurface(person, 0.01, {view}, scene.camera).Share(), 0.97);
  EXPECT_EQ(MeasurePersonSurface(scene.Plane(scene.person, 1.5F), 0.01, {view}, scene.camera).fused_pixels, 0U);
}

}  // namespace
}  // namespace hoidslam::eval
