#include "hoidslam/synth/renderer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "hoidslam/core/error.h"

namespace hoidslam::synth {
namespace {

// Projected vertices are snapped to 1/256 pixel, and edge functions are evaluated exactly in integers, so
// faces that share an edge leave no crack and never overlap by a pixel row.
constexpr double kSubpixel = 256.0;
// Polygons are clipped to this many pixels around the image: keeps the fixed-point arithmetic small for
// surfaces that pass right beside the camera.
constexpr double kGuardBand = 1024.0;

// An affine function of the pixel centre (u, v): a*u + b*v + c.
struct Affine {
  double a = 0.0, b = 0.0, c = 0.0;
  double At(double u, double v) const { return a * u + b * v + c; }
};

// A visible face, as the shading pass needs it.
struct Face {
  Affine inverse_depth;  // 1/z
  Affine u_over_z;       // texture u (level-0 texels) / z
  Affine v_over_z;       // texture v (level-0 texels) / z
  const std::vector<cv::Mat>* levels = nullptr;
  cv::Vec3f multiplier;  // tint x shade
  int instance = kNoInstance;
};

// A half-space p . X + q >= 0 in camera coordinates.
struct HalfSpace {
  Eigen::Vector3d p;
  double q = 0.0;
  double At(const Eigen::Vector3d& x) const { return p.dot(x) + q; }
};

// Clips a convex polygon to a half-space (Sutherland-Hodgman). The crossing point is always computed from
// the inside vertex towards the outside one, so two faces sharing an edge get bit-identical vertices.
void Clip(std::vector<Eigen::Vector3d>& polygon, const HalfSpace& plane, std::vector<Eigen::Vector3d>& scratch) {
  scratch.clear();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& current = polygon[i];
    const Eigen::Vector3d& next = polygon[(i + 1) % n];
    const double h_current = plane.At(current);
    const double h_next = plane.At(next);
    if (h_current >= 0.0) scratch.push_back(current);
    if ((h_current >= 0.0) != (h_next >= 0.0)) {
      const bool current_inside = h_current >= 0.0;
      const Eigen::Vector3d& in = current_inside ? current : next;
      const Eigen::Vector3d& out = current_inside ? next : current;
      const double h_in = current_inside ? h_current : h_next;
      const double h_out = current_inside ? h_next : h_current;
      scratch.push_back(in + (h_in / (h_in - h_out)) * (out - in));
    }
  }
  polygon.swap(scratch);
}

struct FixedPoint {
  std::int64_t x = 0, y = 0;
};

// Box faces: outward normal axis and sign, and the corner order (corners numbered as scene.h BoxCorner does).
struct FaceTopology {
  int axis;
  int sign;
  std::array<int, 4> corners;
};
constexpr std::array<FaceTopology, 6> kFaces = {{
    {0, -1, {0, 2, 6, 4}},
    {0, +1, {1, 5, 7, 3}},
    {1, -1, {0, 4, 5, 1}},
    {1, +1, {2, 3, 7, 6}},
    {2, -1, {0, 1, 3, 2}},
    {2, +1, {4, 6, 7, 5}},
}};

// Texture axes of a face seen from outside: u to the right, v down (down the world-up box z axis on side
// faces), so upright images stay upright and unmirrored.
void FaceAxes(int axis, int sign, Eigen::Vector3d& u_axis, Eigen::Vector3d& v_axis) {
  const Eigen::Vector3d normal = sign * Eigen::Vector3d::Unit(axis);
  if (axis == 2) {
    u_axis = Eigen::Vector3d::UnitX();
    v_axis = sign > 0 ? Eigen::Vector3d(-Eigen::Vector3d::UnitY()) : Eigen::Vector3d::UnitY();
  } else {
    u_axis = Eigen::Vector3d::UnitZ().cross(normal);
    v_axis = -Eigen::Vector3d::UnitZ();
  }
}

int FloorToInt(double x) {
  const int i = static_cast<int>(x);
  return x < i ? i - 1 : i;
}

// Mipmap level whose texel matches the pixel footprint: round(log2(rho)) from the exponent of rho^2.
int MipLevel(float rho_squared) {
  if (!(rho_squared > 1.0F)) return 0;
  const int exponent = static_cast<int>((std::bit_cast<std::uint32_t>(rho_squared) >> 23U) & 0xFFU) - 127;
  return (exponent + 1) >> 1;
}

cv::Vec3f SampleNearest(const cv::Mat& texture, double u, double v) {
  const int mask = texture.cols - 1;
  const cv::Vec3b& texel = texture.at<cv::Vec3b>(FloorToInt(v) & mask, FloorToInt(u) & mask);
  return {static_cast<float>(texel[0]), static_cast<float>(texel[1]), static_cast<float>(texel[2])};
}

// Bilinear between the four texels around (u, v); texel centres sit at half-integer coordinates.
cv::Vec3f SampleBilinear(const cv::Mat& texture, double u, double v) {
  const int mask = texture.cols - 1;
  const double us = u - 0.5;
  const double vs = v - 0.5;
  const int x0 = FloorToInt(us);
  const int y0 = FloorToInt(vs);
  const auto fx = static_cast<float>(us - x0);
  const auto fy = static_cast<float>(vs - y0);
  const auto* row0 = texture.ptr<cv::Vec3b>(y0 & mask);
  const auto* row1 = texture.ptr<cv::Vec3b>((y0 + 1) & mask);
  const cv::Vec3b& a = row0[x0 & mask];
  const cv::Vec3b& b = row0[(x0 + 1) & mask];
  const cv::Vec3b& c = row1[x0 & mask];
  const cv::Vec3b& d = row1[(x0 + 1) & mask];
  cv::Vec3f out;
  for (int k = 0; k < 3; ++k) {
    const float top = a[k] + (b[k] - a[k]) * fx;
    const float bottom = c[k] + (d[k] - c[k]) * fx;
    out[k] = top + (bottom - top) * fy;
  }
  return out;
}

void CheckBox(const SceneInstance& instance, const Box& box, int texture_count) {
  const auto fail = [&](const std::string& what) {
    throw core::Error(fmt::format("synthetic scene: instance {} ('{}'): {}", instance.id, instance.label, what));
  };
  if (instance.id <= kNoInstance) fail("instance ids must be > 0");
  if (!box.T_wb.matrix().allFinite() || !box.half_size.allFinite()) fail("a box has a non-finite pose or size");
  if (!(box.half_size.minCoeff() > 0.0)) fail("a box has a non-positive size");
  if (!(box.texture_scale > 0.0)) fail("a box has a non-positive texture scale");
  if (box.texture < 0 || box.texture >= texture_count) {
    fail(fmt::format("texture index {} outside the texture set (0..{})", box.texture, texture_count - 1));
  }
}

// Per-thread working memory, kept between frames: fresh multi-megabyte buffers cost more in page faults
// than drawing a simple scene.
struct Buffers {
  std::vector<float> inverse_depth;  // z-buffer of 1/z, 0 = empty (the largest value is the nearest)
  std::vector<int> face_index;       // per pixel, index into faces or -1
  std::vector<Face> faces;
  std::vector<Eigen::Vector3d> polygon, scratch;
  std::vector<FixedPoint> projected;
};

// One Render() call: its state lives in that call and its thread's Buffers, so renders run in parallel safely.
class Rasteriser {
 public:
  Rasteriser(const core::CameraIntrinsics& k, const TextureSet& textures, const RenderOptions& options,
             const core::Pose& T_wc, Buffers& buffers)
      : k_(k),
        textures_(textures),
        options_(options),
        T_cw_(T_wc.inverse()),
        light_(options.light_direction.normalized()),
        inverse_depth_(buffers.inverse_depth),
        face_index_(buffers.face_index),
        faces_(buffers.faces),
        polygon_(buffers.polygon),
        scratch_(buffers.scratch),
        projected_(buffers.projected) {
    const std::size_t pixels = static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height);
    inverse_depth_.assign(pixels, 0.0F);
    face_index_.assign(pixels, -1);
    faces_.clear();
    const double w = k.width;
    const double h = k.height;
    // Image sides through the camera centre: a pixel coordinate in [-0.5, size - 0.5] (pixel edges).
    view_ = {{
        {{0.0, 0.0, 1.0}, -options.near_plane},
        {{k.fx, 0.0, k.cx + 0.5}, 0.0},
        {{-k.fx, 0.0, w - 0.5 - k.cx}, 0.0},
        {{0.0, k.fy, k.cy + 0.5}, 0.0},
        {{0.0, -k.fy, h - 0.5 - k.cy}, 0.0},
    }};
    clip_ = view_;
    clip_[1].p.z() += kGuardBand;
    clip_[2].p.z() += kGuardBand;
    clip_[3].p.z() += kGuardBand;
    clip_[4].p.z() += kGuardBand;
  }

  void DrawBox(const SceneInstance& instance, const Box& box) {
    const core::Pose T_cb = T_cw_ * box.T_wb;
    std::array<Eigen::Vector3d, 8> corners;
    for (int i = 0; i < 8; ++i) corners[static_cast<std::size_t>(i)] = T_cb * BoxCorner(box.half_size, i);
    for (const HalfSpace& plane : view_) {
      if (std::all_of(corners.begin(), corners.end(), [&](const Eigen::Vector3d& c) { return plane.At(c) < 0.0; })) {
        return;  // wholly outside the view
      }
    }
    for (const FaceTopology& topology : kFaces) DrawFace(instance, box, T_cb, corners, topology);
  }

  RenderOutput Shade() const {
    RenderOutput out;
    out.bgr = cv::Mat::zeros(k_.height, k_.width, CV_8UC3);
    out.depth = cv::Mat::zeros(k_.height, k_.width, CV_32F);
    out.instance = cv::Mat(k_.height, k_.width, CV_32S, cv::Scalar(kNoInstance));
    for (int v = 0; v < k_.height; ++v) {
      auto* bgr = out.bgr.ptr<cv::Vec3b>(v);
      auto* depth = out.depth.ptr<float>(v);
      auto* instance = out.instance.ptr<int>(v);
      const int* face_row = &face_index_[static_cast<std::size_t>(v) * static_cast<std::size_t>(k_.width)];
      for (int u = 0; u < k_.width; ++u) {
        if (face_row[u] < 0) continue;
        const Face& face = faces_[static_cast<std::size_t>(face_row[u])];
        const double iz = face.inverse_depth.At(u, v);
        const double z = 1.0 / iz;
        const double tu = face.u_over_z.At(u, v) * z;
        const double tv = face.v_over_z.At(u, v) * z;
        int level = 0;
        if (options_.mipmaps) {
          // Texel footprint of one pixel step: derivatives of u = U/I are (U' - u I') / I.
          const auto du_du = static_cast<float>((face.u_over_z.a - tu * face.inverse_depth.a) * z);
          const auto dv_du = static_cast<float>((face.v_over_z.a - tv * face.inverse_depth.a) * z);
          const auto du_dv = static_cast<float>((face.u_over_z.b - tu * face.inverse_depth.b) * z);
          const auto dv_dv = static_cast<float>((face.v_over_z.b - tv * face.inverse_depth.b) * z);
          level = std::min(MipLevel(std::max(du_du * du_du + dv_du * dv_du, du_dv * du_dv + dv_dv * dv_dv)),
                           static_cast<int>(face.levels->size()) - 1);
        }
        const cv::Mat& texture = (*face.levels)[static_cast<std::size_t>(level)];
        const double scale = 1.0 / static_cast<double>(1 << level);
        const cv::Vec3f texel = options_.bilinear ? SampleBilinear(texture, tu * scale, tv * scale)
                                                  : SampleNearest(texture, tu * scale, tv * scale);
        for (int c = 0; c < 3; ++c) bgr[u][c] = cv::saturate_cast<uchar>(texel[c] * face.multiplier[c]);
        depth[u] = static_cast<float>(z);
        instance[u] = face.instance;
      }
    }
    return out;
  }

 private:
  void DrawFace(const SceneInstance& instance, const Box& box, const core::Pose& T_cb,
                const std::array<Eigen::Vector3d, 8>& corners, const FaceTopology& topology) {
    const Eigen::Vector3d normal_b = topology.sign * Eigen::Vector3d::Unit(topology.axis);
    const Eigen::Vector3d normal = T_cb.linear() * normal_b;
    const Eigen::Vector3d& any_corner = corners[static_cast<std::size_t>(topology.corners[0])];
    const double d = normal.dot(any_corner);  // the face plane: normal . X = d
    if (d >= -1e-12) return;                  // seen from behind or edge-on

    polygon_.clear();
    for (const int corner : topology.corners) polygon_.push_back(corners[static_cast<std::size_t>(corner)]);
    for (const HalfSpace& plane : clip_) {
      if (std::any_of(polygon_.begin(), polygon_.end(), [&](const Eigen::Vector3d& p) { return plane.At(p) < 0.0; })) {
        Clip(polygon_, plane, scratch_);
        if (polygon_.size() < 3) return;
      }
    }

    const int face_id = static_cast<int>(faces_.size());
    faces_.push_back(MakeFace(instance, box, T_cb, topology, normal, d));
    projected_.clear();
    for (const Eigen::Vector3d& p : polygon_) {
      projected_.push_back({std::llround((k_.fx * p.x() / p.z() + k_.cx) * kSubpixel),
                            std::llround((k_.fy * p.y() / p.z() + k_.cy) * kSubpixel)});
    }
    for (std::size_t i = 1; i + 1 < projected_.size(); ++i) {
      DrawTriangle(projected_[0], projected_[i], projected_[i + 1], face_id);
    }
  }

  Face MakeFace(const SceneInstance& instance, const Box& box, const core::Pose& T_cb, const FaceTopology& topology,
                const Eigen::Vector3d& normal, double d) const {
    Eigen::Vector3d u_axis_b;
    Eigen::Vector3d v_axis_b;
    FaceAxes(topology.axis, topology.sign, u_axis_b, v_axis_b);
    // Texture origin: the face corner where u and v are smallest (the top-left corner seen from outside).
    const auto extent_along = [&](const Eigen::Vector3d& axis) { return box.half_size.dot(axis.cwiseAbs()); };
    const Eigen::Vector3d origin_b = topology.sign * box.half_size[topology.axis] * Eigen::Vector3d::Unit(topology.axis) -
                                     extent_along(u_axis_b) * u_axis_b - extent_along(v_axis_b) * v_axis_b;
    const Eigen::Vector3d origin = T_cb * origin_b;
    const double texels_per_metre = textures_.texture_size() / box.texture_scale;

    // On the face, X = z r with r = ((u - cx) / fx, (v - cy) / fy, 1), so 1/z = (normal . r) / d and
    // tex_u / z = texels_per_metre * (axis - (axis . origin / d) normal) . r: both affine in (u, v).
    const auto affine_of = [&](const Eigen::Vector3d& w) {
      return Affine{w.x() / k_.fx, w.y() / k_.fy, w.z() - w.x() * k_.cx / k_.fx - w.y() * k_.cy / k_.fy};
    };
    const auto texture_affine = [&](const Eigen::Vector3d& axis_b) {
      const Eigen::Vector3d axis = T_cb.linear() * axis_b;
      return affine_of(texels_per_metre * (axis - (axis.dot(origin) / d) * normal));
    };

    Face face;
    face.inverse_depth = affine_of(normal / d);
    face.u_over_z = texture_affine(u_axis_b);
    face.v_over_z = texture_affine(v_axis_b);
    face.levels = &textures_.Levels(box.texture);
    const Eigen::Vector3d normal_w = T_cw_.linear().transpose() * normal;
    const auto shade = static_cast<float>(options_.ambient + (1.0 - options_.ambient) * std::max(0.0, normal_w.dot(light_)));
    face.multiplier = box.tint * shade;
    face.instance = instance.id;
    return face;
  }

  void DrawTriangle(FixedPoint a, FixedPoint b, FixedPoint c, int face_id) {
    const auto cross = [](FixedPoint o, FixedPoint p, FixedPoint q) {
      return (p.x - o.x) * (q.y - o.y) - (p.y - o.y) * (q.x - o.x);
    };
    std::int64_t area = cross(a, b, c);
    if (area == 0) return;
    if (area < 0) std::swap(b, c);

    constexpr auto sub = static_cast<std::int64_t>(kSubpixel);  // a constant: the lambdas need not capture it
    const auto ceil_div = [](std::int64_t value) { return value >= 0 ? (value + sub - 1) / sub : -((-value) / sub); };
    const auto floor_div = [](std::int64_t value) { return value >= 0 ? value / sub : -((-value + sub - 1) / sub); };
    const int u_min = static_cast<int>(std::max<std::int64_t>(0, ceil_div(std::min({a.x, b.x, c.x}))));
    const int u_max = static_cast<int>(std::min<std::int64_t>(k_.width - 1, floor_div(std::max({a.x, b.x, c.x}))));
    const int v_min = static_cast<int>(std::max<std::int64_t>(0, ceil_div(std::min({a.y, b.y, c.y}))));
    const int v_max = static_cast<int>(std::min<std::int64_t>(k_.height - 1, floor_div(std::max({a.y, b.y, c.y}))));
    if (u_min > u_max || v_min > v_max) return;

    // Edge function of edge p->q at pixel centre s: cross(p, q, s) >= 0 inside (counter-clockwise in y-down).
    struct Edge {
      std::int64_t step_u, step_v, start;
    };
    const FixedPoint start{u_min * sub, v_min * sub};
    const auto edge = [&](FixedPoint p, FixedPoint q) {
      return Edge{-(q.y - p.y) * sub, (q.x - p.x) * sub, cross(p, q, start)};
    };
    const std::array<Edge, 3> edges = {edge(a, b), edge(b, c), edge(c, a)};
    const Affine& iz = faces_[static_cast<std::size_t>(face_id)].inverse_depth;

    std::array<std::int64_t, 3> row = {edges[0].start, edges[1].start, edges[2].start};
    for (int v = v_min; v <= v_max; ++v) {
      std::array<std::int64_t, 3> e = row;
      const std::size_t offset = static_cast<std::size_t>(v) * static_cast<std::size_t>(k_.width);
      const double iz_row = iz.b * v + iz.c;
      for (int u = u_min; u <= u_max; ++u) {
        if ((e[0] | e[1] | e[2]) >= 0) {
          const auto value = static_cast<float>(iz.a * u + iz_row);
          float& best = inverse_depth_[offset + static_cast<std::size_t>(u)];
          if (value > best) {
            best = value;
            face_index_[offset + static_cast<std::size_t>(u)] = face_id;
          }
        }
        e[0] += edges[0].step_u;
        e[1] += edges[1].step_u;
        e[2] += edges[2].step_u;
      }
      row[0] += edges[0].step_v;
      row[1] += edges[1].step_v;
      row[2] += edges[2].step_v;
    }
  }

  const core::CameraIntrinsics& k_;
  const TextureSet& textures_;
  const RenderOptions& options_;
  core::Pose T_cw_;
  Eigen::Vector3d light_;
  std::array<HalfSpace, 5> view_;  // near plane and the image sides: what can be seen at all
  std::array<HalfSpace, 5> clip_;  // near plane and the guard band: what polygons are clipped to
  std::vector<float>& inverse_depth_;
  std::vector<int>& face_index_;
  std::vector<Face>& faces_;
  std::vector<Eigen::Vector3d>& polygon_;
  std::vector<Eigen::Vector3d>& scratch_;
  std::vector<FixedPoint>& projected_;
};

}  // namespace

void RenderOptions::Check() const {
  if (!(near_plane > 0.0)) {
    throw core::InputError::ForParameter("render.near_plane", fmt::format("must be > 0 metres, got {}", near_plane));
  }
  if (!(light_direction.norm() > 0.0) || !light_direction.allFinite()) {
    throw core::InputError::ForParameter("render.light_direction", "must be a finite non-zero vector");
  }
  if (!(ambient >= 0.0 && ambient <= 1.0)) {
    throw core::InputError::ForParameter("render.ambient", fmt::format("must be in [0, 1], got {}", ambient));
  }
}

Renderer::Renderer(const core::CameraIntrinsics& intrinsics, const TextureSet& textures, const RenderOptions& options)
    : intrinsics_(intrinsics), textures_(textures), options_(options) {
  options_.Check();
  if (intrinsics.HasDistortion()) {
    throw core::InputError::ForParameter("Camera.k1", "the synthetic renderer draws undistorted images; "
                                                      "distortion coefficients must be zero");
  }
  if (intrinsics.width <= 0 || intrinsics.height <= 0) {
    throw core::InputError::ForParameter("Camera.width",
                                         fmt::format("image size must be positive, got {}x{}", intrinsics.width,
                                                     intrinsics.height));
  }
  if (!(intrinsics.fx > 0.0) || !(intrinsics.fy > 0.0)) {
    throw core::InputError::ForParameter("Camera.fx", "focal lengths must be positive");
  }
}

RenderOutput Renderer::Render(const SceneSnapshot& scene, const core::Pose& T_wc) const {
  if (!T_wc.matrix().allFinite()) throw core::Error("synthetic scene: the camera pose is not finite");
  thread_local Buffers buffers;
  Rasteriser rasteriser(intrinsics_, textures_, options_, T_wc, buffers);
  for (const SceneInstance& instance : scene.instances) {
    for (const Box& box : instance.parts) {
      CheckBox(instance, box, textures_.size());
      rasteriser.DrawBox(instance, box);
    }
  }
  return rasteriser.Shade();
}

}  // namespace hoidslam::synth
