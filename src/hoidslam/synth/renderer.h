#pragma once
// A software rasteriser for SceneSnapshot: textured, shaded boxes with a z-buffer.
//
// Camera convention: T_wc maps camera to world; the camera's optical frame has x right, y down, z forward
// (TUM / OpenCV). Pixel convention: the same as core::CameraIntrinsics::Project and OpenCV, i.e. pixel (u, v)
// covers [u - 0.5, u + 0.5) x [v - 0.5, v + 0.5) in projected coordinates and is sampled at its centre (u, v),
// so `intrinsics.Unproject(u, v, depth.at<float>(v, u))` is exactly the surface point drawn there.
//
// Each box face is clipped against the near plane (camera z >= near_plane), back faces are culled, and the
// nearest face per pixel is kept. Depth, instance ids and texture coordinates come from the face's exact plane
// at the pixel centre (perspective-correct), so depth is the analytic z of the surface. Colour: the texture
// (mipmapped, bilinear or nearest), times the box tint, times Lambert shading from a fixed directional light
// plus ambient, so that the faces of a box differ.
//
// Threading: Render() is single-threaded and const; one Renderer may render several frames in parallel from
// different threads (each thread keeps its own z-buffer between calls, about 2.5 MB at 640 x 480).

#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "hoidslam/core/camera.h"
#include "hoidslam/core/pose.h"
#include "hoidslam/synth/scene.h"
#include "hoidslam/synth/textures.h"

namespace hoidslam::synth {

struct RenderOptions {
  double near_plane = 0.05;                            // metres, > 0: nearer surface is clipped away
  Eigen::Vector3d light_direction = {0.35, 0.25, 1.0};  // world direction towards the light (z up), non-zero
  double ambient = 0.5;                                // shade of a face turned away from the light, in [0, 1]
  bool bilinear = true;                                // bilinear texture sampling (else nearest texel)
  bool mipmaps = true;                                 // sample the mipmap level matching the pixel footprint

  // Throws InputError naming the parameter ("render.near_plane", ...).
  void Check() const;
};

struct RenderOutput {
  cv::Mat bgr;       // CV_8UC3; black where nothing is drawn
  cv::Mat depth;     // CV_32F, metres, z along the optical axis; 0 where nothing is drawn
  cv::Mat instance;  // CV_32S, SceneInstance::id of the surface drawn, kNoInstance where nothing is drawn
};

class Renderer {
 public:
  // Throws InputError naming the parameter when the intrinsics have distortion (the renderer draws an ideal
  // pinhole image), a non-positive size or focal length, or when options.Check() fails. The texture set is
  // copied (cheaply: images are shared, not duplicated).
  Renderer(const core::CameraIntrinsics& intrinsics, const TextureSet& textures, const RenderOptions& options = {});

  // Renders `scene` seen from camera pose T_wc. Throws core::Error for a non-finite pose, an instance id
  // <= 0, or a box with a texture index outside the texture set or a non-positive size or texture scale.
  RenderOutput Render(const SceneSnapshot& scene, const core::Pose& T_wc) const;

  const core::CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const TextureSet& textures() const { return textures_; }

 private:
  core::CameraIntrinsics intrinsics_;
  TextureSet textures_;
  RenderOptions options_;
};

}  // namespace hoidslam::synth
