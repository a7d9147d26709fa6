#include "hoidslam/synth/renderer.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/camera_path.h"
#include "support/temp_dir.h"

namespace hoidslam::synth {
namespace {

TextureOptions SmallTextureOptions() {
  TextureOptions options;
  options.size = 64;
  return options;
}

const TextureSet& SmallTextures() {
  static const TextureSet textures(SmallTextureOptions());
  return textures;
}

Box MakeBox(const Eigen::Vector3d& centre, const Eigen::Vector3d& half_size, double yaw_deg = 0.0, int texture = 0) {
  Box box;
  box.T_wb = core::Pose::Identity();
  box.T_wb.translate(centre);
  box.T_wb.rotate(Eigen::AngleAxisd(yaw_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()));
  box.half_size = half_size;
  box.texture = texture;
  box.texture_scale = 0.5;
  return box;
}

SceneInstance MakeInstance(int id, std::vector<Box> parts) {
  SceneInstance instance;
  instance.id = id;
  instance.label = "thing";
  instance.parts = std::move(parts);
  return instance;
}

// A camera 1.5 m up, a little turned and tilted down, looking along world +x.
core::Pose TestCamera() { return CameraPoseFromYawPitch({0.0, 0.3, 1.5}, 8.0, -12.0); }

// Boxes spread out in front of TestCamera(), none hiding another.
SceneSnapshot SpreadScene() {
  SceneSnapshot scene;
  scene.instances.push_back(MakeInstance(1, {MakeBox({3.0, 0.0, 1.0}, {0.2, 0.3, 0.25}, 30.0)}));
  scene.instances.push_back(MakeInstance(2, {MakeBox({2.5, 1.2, 0.8}, {0.15, 0.1, 0.2}, -20.0)}));
  scene.instances.push_back(MakeInstance(3, {MakeBox({4.0, -1.0, 0.6}, {0.3, 0.3, 0.3}, 45.0)}));
  scene.instances.push_back(MakeInstance(4, {MakeBox({2.2, 0.6, 1.9}, {0.1, 0.2, 0.1}, 10.0)}));
  return scene;
}

core::CameraIntrinsics Intrinsics() { return {}; }  // TUM fr3, 640 x 480

TEST(Renderer, EmptySceneIsAllZero) {
  const Renderer renderer(Intrinsics(), SmallTextures());
  const RenderOutput out = renderer.Render({}, TestCamera());
  ASSERT_EQ(out.bgr.size(), cv::Size(640, 480));
  EXPECT_EQ(out.bgr.type(), CV_8UC3);
  EXPECT_EQ(out.depth.type(), CV_32F);
  EXPECT_EQ(out.instance.type(), CV_32S);
  EXPECT_EQ(cv::countNonZero(out.bgr.reshape(1)), 0);
  EXPECT_EQ(cv::countNonZero(out.depth), 0);
  EXPECT_EQ(cv::countNonZero(out.instance), 0);
}

// Points on the visible faces of every box, reprojected with the ground-truth pose, land on pixels that show
// that box, at the surface's depth.
TEST(Renderer, StaticPointsReprojectToWhereTheyAreDrawn) {
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, SmallTextures());
  const SceneSnapshot scene = SpreadScene();
  const core::Pose T_wc = TestCamera();
  const RenderOutput out = renderer.Render(scene, T_wc);
  int checked = 0;
  for (const SceneInstance& instance : scene.instances) {
    const Box& box = instance.parts.front();
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign : {-1, 1}) {
        const Eigen::Vector3d normal_w = box.T_wb.linear() * (sign * Eigen::Vector3d::Unit(axis));
        // Face centre and four points halfway to its corners.
        for (int corner = 0; corner < 5; ++corner) {
          Eigen::Vector3d local = sign * box.half_size[axis] * Eigen::Vector3d::Unit(axis);
          if (corner > 0) {
            const int a1 = (axis + 1) % 3;
            const int a2 = (axis + 2) % 3;
            local[a1] = ((corner & 1) ? 0.5 : -0.5) * box.half_size[a1];
            local[a2] = ((corner & 2) ? 0.5 : -0.5) * box.half_size[a2];
          }
          const Eigen::Vector3d p_w = box.T_wb * local;
          const Eigen::Vector3d camera_to_point = p_w - T_wc.translation();
          const double facing = -normal_w.dot(camera_to_point) / camera_to_point.norm();  // cos of view angle
          if (facing < 0.3) continue;  // a back face, or too grazing to hit reliably with a rounded pixel
          const Eigen::Vector3d p_c = T_wc.inverse() * p_w;
          const Eigen::Vector2d pixel = k.Project(p_c);
          const int u = static_cast<int>(std::lround(pixel.x()));
          const int v = static_cast<int>(std::lround(pixel.y()));
          ASSERT_TRUE(u >= 0 && u < k.width && v >= 0 && v < k.height) << "test scene point out of view";
          EXPECT_EQ(out.instance.at<int>(v, u), instance.id) << "at pixel " << u << "," << v;
          // The rendered depth at the pixel centre, unprojected, lies on the face plane beside the point.
          const double depth = out.depth.at<float>(v, u);
          const Eigen::Vector3d drawn_w = T_wc * k.Unproject(u, v, depth);
          EXPECT_NEAR(normal_w.dot(drawn_w - p_w), 0.0, 1e-5 * depth);
          EXPECT_LT((drawn_w - p_w).norm(), 0.75 * depth / k.fx / facing);  // within the rounding's footprint
          EXPECT_NEAR(depth, p_c.z(), 1e-2 * p_c.z());
          ++checked;
        }
      }
    }
  }
  EXPECT_GE(checked, 30);
}

// A point whose projection is exactly a pixel centre has exactly its z as the rendered depth.
TEST(Renderer, DepthAtPixelCentresIsTheSurfaceZ) {
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, SmallTextures());
  const SceneSnapshot scene = SpreadScene();
  const core::Pose T_wc = TestCamera();
  const RenderOutput out = renderer.Render(scene, T_wc);
  int checked = 0;
  for (int v = 0; v < k.height; v += 7) {
    for (int u = 0; u < k.width; u += 7) {
      const int id = out.instance.at<int>(v, u);
      if (id == kNoInstance) continue;
      // Intersect the pixel's ray with the drawn box: the nearest entry over its six face planes.
      const Box& box = scene.instances[static_cast<std::size_t>(id - 1)].parts.front();
      const core::Pose T_bc = box.T_wb.inverse() * T_wc;
      const Eigen::Vector3d ray_c = k.Unproject(u, v, 1.0);
      const Eigen::Vector3d origin_b = T_bc.translation();
      const Eigen::Vector3d ray_b = T_bc.linear() * ray_c;
      double entry = 0.0;
      for (int axis = 0; axis < 3; ++axis) {
        const double t1 = (-box.half_size[axis] - origin_b[axis]) / ray_b[axis];
        const double t2 = (box.half_size[axis] - origin_b[axis]) / ray_b[axis];
        entry = std::max(entry, std::min(t1, t2));
      }
      // On a silhouette edge pixel the ray may miss by a hair; the entry distance is still the face's.
      EXPECT_NEAR(out.depth.at<float>(v, u), entry, 1e-5 * entry) << "at pixel " << u << "," << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(Renderer, TiltedPlaneHasAnalyticDepthEverywhere) {
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, SmallTextures());
  // A huge thin slab 3 m ahead of a camera at the origin, turned 35 degrees about the vertical.
  const core::Pose T_wc = CameraPoseFromYawPitch({0.0, 0.0, 0.0}, 0.0, 0.0);
  SceneSnapshot scene;
  Box slab = MakeBox({3.0, 0.0, 0.0}, {0.01, 20.0, 20.0}, 35.0);
  scene.instances.push_back(MakeInstance(7, {slab}));
  const RenderOutput out = renderer.Render(scene, T_wc);
  // The front face: normal n (world), passing through the slab centre minus its half thickness.
  const Eigen::Vector3d n_w = slab.T_wb.linear() * -Eigen::Vector3d::UnitX();
  const Eigen::Vector3d on_face_w = slab.T_wb * Eigen::Vector3d(-0.01, 0.0, 0.0);
  const Eigen::Vector3d n_c = T_wc.linear().transpose() * n_w;
  const double d = n_c.dot(T_wc.inverse() * on_face_w);
  double worst = 0.0;
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      ASSERT_EQ(out.instance.at<int>(v, u), 7);
      const double expected = d / n_c.dot(k.Unproject(u, v, 1.0));
      worst = std::max(worst, std::abs(out.depth.at<float>(v, u) - expected) / expected);
    }
  }
  EXPECT_LT(worst, 1e-6);
}

// The floor passes under and behind the camera; a box straddles the camera's plane. Nothing explodes, and
// the floor still has its analytic depth.
TEST(Renderer, ClipsSurfacesThatPassBehindTheCamera) {
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, SmallTextures());
  const double height = 1.2;
  const core::Pose T_wc = CameraPoseFromYawPitch({0.0, 0.0, height}, 0.0, 0.0);
  SceneSnapshot scene;
  scene.instances.push_back(MakeInstance(1, {MakeBox({0.0, 0.0, -0.05}, {30.0, 30.0, 0.05})}));
  scene.instances.push_back(MakeInstance(2, {MakeBox({0.0, 0.6, 1.2}, {1.0, 0.2, 0.5})}));  // beside, both ways
  const RenderOutput out = renderer.Render(scene, T_wc);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const float z = out.depth.at<float>(v, u);
      ASSERT_TRUE(std::isfinite(z));
      ASSERT_TRUE(z == 0.0F || z >= 0.05F - 1e-6F) << z;
      if (out.instance.at<int>(v, u) == 1) {
        ASSERT_GT(v, k.cy);  // the floor only below the horizon
        const double expected = height * k.fy / (v - k.cy);
        ASSERT_NEAR(z, expected, 1e-5 * expected);
      }
    }
  }
  // The side box covers the left of the image from the very edge, the floor the lower middle.
  EXPECT_EQ(out.instance.at<int>(240, 0), 2);
  EXPECT_EQ(out.instance.at<int>(470, 320), 1);
  EXPECT_EQ(out.instance.at<int>(100, 320), kNoInstance);

  // From inside a box every face is seen from behind: nothing is drawn.
  SceneSnapshot inside;
  inside.instances.push_back(MakeInstance(3, {MakeBox({0.0, 0.0, height}, {0.5, 0.5, 0.5})}));
  EXPECT_EQ(cv::countNonZero(renderer.Render(inside, T_wc).instance), 0);
}

TEST(Renderer, NearerBoxHidesFartherBox) {
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, SmallTextures());
  const core::Pose T_wc = CameraPoseFromYawPitch({0.0, 0.0, 1.0}, 0.0, 0.0);
  SceneSnapshot scene;
  // Drawn far first, then near, and the other way round: the result must not depend on the order.
  scene.instances.push_back(MakeInstance(1, {MakeBox({4.0, 0.0, 1.0}, {0.1, 1.0, 1.0})}));
  scene.instances.push_back(MakeInstance(2, {MakeBox({2.0, 0.0, 1.0}, {0.1, 0.2, 0.2})}));
  const RenderOutput a = renderer.Render(scene, T_wc);
  std::swap(scene.instances[0], scene.instances[1]);
  const RenderOutput b = renderer.Render(scene, T_wc);
  const cv::Point centre(320, 248);
  EXPECT_EQ(a.instance.at<int>(centre), 2);
  EXPECT_NEAR(a.depth.at<float>(centre), 1.9, 1e-5);
  EXPECT_EQ(a.instance.at<int>(150, 320), 1);
  EXPECT_EQ(cv::norm(a.instance, b.instance, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
}

// Every pixel whose centre lies inside a box's silhouette is drawn: no cracks between faces or triangles.
TEST(Renderer, SilhouetteIsWatertight) {
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, SmallTextures());
  const core::Pose T_wc = TestCamera();
  for (double yaw : {0.0, 17.0, 45.0, 73.0}) {
    SceneSnapshot scene;
    Box box = MakeBox({2.5, 0.5, 1.0}, {0.4, 0.3, 0.35}, yaw);
    box.T_wb.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
    scene.instances.push_back(MakeInstance(5, {box}));
    const RenderOutput out = renderer.Render(scene, T_wc);
    std::vector<cv::Point2f> projected;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector3d local((i & 1) ? 0.4 : -0.4, (i & 2) ? 0.3 : -0.3, (i & 4) ? 0.35 : -0.35);
      const Eigen::Vector2d p = k.Project(T_wc.inverse() * (box.T_wb * local));
      projected.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
    }
    std::vector<cv::Point2f> hull;
    cv::convexHull(projected, hull);
    int inside = 0;
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        const double distance = cv::pointPolygonTest(hull, cv::Point2f(static_cast<float>(u), static_cast<float>(v)), true);
        if (distance > 0.01) {
          ++inside;
          ASSERT_EQ(out.instance.at<int>(v, u), 5) << "hole at " << u << "," << v << " yaw " << yaw;
        } else if (distance < -0.01) {
          ASSERT_EQ(out.instance.at<int>(v, u), kNoInstance) << "spill at " << u << "," << v << " yaw " << yaw;
        }
      }
    }
    EXPECT_GT(inside, 2000);
  }
}

// Texture coordinates are perspective-correct: on a face seen at a slant, the middle of the texture is drawn
// where the middle of the face projects, not halfway across the face's image.
TEST(Renderer, TextureIsPerspectiveCorrectAndShaded) {
  testing::TempDir dir;
  cv::Mat halves(64, 64, CV_8UC3, cv::Scalar(0, 0, 0));
  halves(cv::Rect(32, 0, 32, 64)).setTo(cv::Scalar(200, 200, 200));
  ASSERT_TRUE(cv::imwrite((dir / "halves.png").string(), halves));
  TextureOptions texture_options = SmallTextureOptions();
  texture_options.photo_folder = dir.path();
  const TextureSet textures(texture_options);
  const core::CameraIntrinsics k = Intrinsics();
  RenderOptions options;
  options.mipmaps = false;
  options.bilinear = false;
  const Renderer renderer(k, textures, options);
  const core::Pose T_wc = CameraPoseFromYawPitch({0.0, 0.0, 1.0}, 0.0, 0.0);

  // A 1 m wide face, one texture repeat wide, slanted 50 degrees; seen from -x, its u axis runs along the
  // face from the camera's left (+y) to its right (-y).
  SceneSnapshot scene;
  Box face = MakeBox({3.0, 0.0, 1.0}, {0.005, 0.5, 0.2}, 50.0, textures.Index(TextureRole::kPoster));
  face.texture_scale = 1.0;
  face.tint = {1.0F, 0.5F, 1.0F};
  scene.instances.push_back(MakeInstance(1, {face}));
  const RenderOutput out = renderer.Render(scene, T_wc);

  const auto column_of = [&](const Eigen::Vector3d& local) {
    return k.Project(T_wc.inverse() * (face.T_wb * local)).x();
  };
  const double left = column_of({-0.005, 0.5, 0.0});
  const double right = column_of({-0.005, -0.5, 0.0});
  const double middle = column_of({-0.005, 0.0, 0.0});
  ASSERT_GT(std::abs(middle - 0.5 * (left + right)), 5.0) << "slant too small to tell";
  const int row = 248;
  for (int u = static_cast<int>(std::ceil(std::min(left, right))) + 1; u < static_cast<int>(std::max(left, right)) - 1;
       ++u) {
    if (std::abs(u - middle) < 1.5) continue;
    const cv::Vec3b pixel = out.bgr.at<cv::Vec3b>(row, u);
    const bool second_half = (u - middle) * (right - left) > 0;
    if (second_half) {
      EXPECT_GT(pixel[0], 50) << u;
      // Tint multiplies: green at half the blue and red.
      EXPECT_NEAR(pixel[1], pixel[0] / 2.0, 1.0) << u;
    } else {
      EXPECT_EQ(pixel[0], 0) << u;
    }
  }
}

TEST(Renderer, FacesTowardsTheLightAreBrighter) {
  const TextureSet& textures = SmallTextures();
  const core::CameraIntrinsics k = Intrinsics();
  const Renderer renderer(k, textures);
  // Looking down at a cube from above and in front: top face (lit) and front face (in the light's shade).
  const core::Pose T_wc = CameraPoseLookingAt({-2.0, 0.0, 2.5}, {0.0, 0.0, 0.0});
  SceneSnapshot scene;
  scene.instances.push_back(MakeInstance(1, {MakeBox({0.0, 0.0, 0.0}, {0.3, 0.3, 0.3}, 0.0,
                                                     textures.Index(TextureRole::kWall))}));
  const RenderOutput out = renderer.Render(scene, T_wc);
  const auto mean_where = [&](const Eigen::Vector3d& point) {
    const Eigen::Vector2d p = k.Project(T_wc.inverse() * point);
    const cv::Rect patch(static_cast<int>(p.x()) - 5, static_cast<int>(p.y()) - 5, 11, 11);
    return cv::mean(out.bgr(patch));
  };
  const cv::Scalar top = mean_where({0.0, 0.0, 0.3});
  const cv::Scalar front = mean_where({-0.3, 0.0, 0.0});
  EXPECT_GT(top[0], front[0] * 1.2);
}

TEST(Renderer, IsDeterministic) {
  const Renderer renderer(Intrinsics(), SmallTextures());
  const RenderOutput a = renderer.Render(SpreadScene(), TestCamera());
  const RenderOutput b = renderer.Render(SpreadScene(), TestCamera());
  EXPECT_EQ(cv::norm(a.bgr, b.bgr, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.instance, b.instance, cv::NORM_INF), 0.0);
}

TEST(Renderer, RejectsBadBoxesAndIntrinsics) {
  const Renderer renderer(Intrinsics(), SmallTextures());
  SceneSnapshot scene = SpreadScene();
  scene.instances[1].parts[0].texture = SmallTextures().size();
  EXPECT_THROW(renderer.Render(scene, TestCamera()), core::Error);
  scene = SpreadScene();
  scene.instances[0].parts[0].half_size.y() = 0.0;
  EXPECT_THROW(renderer.Render(scene, TestCamera()), core::Error);
  scene = SpreadScene();
  scene.instances[0].parts[0].texture_scale = -1.0;
  EXPECT_THROW(renderer.Render(scene, TestCamera()), core::Error);
  scene = SpreadScene();
  scene.instances[2].id = kNoInstance;
  EXPECT_THROW(renderer.Render(scene, TestCamera()), core::Error);
  core::Pose nan_pose = TestCamera();
  nan_pose.translation().x() = std::nan("");
  EXPECT_THROW(renderer.Render(SpreadScene(), nan_pose), core::Error);

  core::CameraIntrinsics distorted;
  distorted.k1 = 0.1;
  EXPECT_THROW(Renderer(distorted, SmallTextures()), core::InputError);
  RenderOptions options;
  options.near_plane = 0.0;
  try {
    Renderer(Intrinsics(), SmallTextures(), options);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& error) {
    EXPECT_NE(std::string(error.what()).find("render.near_plane"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace hoidslam::synth
