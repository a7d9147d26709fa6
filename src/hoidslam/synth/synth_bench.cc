// Speed of the synthetic generator's parts on an office-sized scene.
//
//   build/src/hoidslam/synth/synth_bench --benchmark_filter=BM_Render --benchmark_repetitions=5

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include "hoidslam/synth/camera_path.h"
#include "hoidslam/synth/random.h"
#include "hoidslam/synth/renderer.h"
#include "hoidslam/synth/sensor_noise.h"

namespace hoidslam::synth {
namespace {

// Builds a furnished 8 x 6 x 2.8 m room of about 300 boxes: walls, desks with monitors, keyboards and clutter,
// chairs, a shelf of books, posters and two blocky people.
class BenchOffice {
 public:
  explicit BenchOffice(const TextureSet& textures) : textures_(textures) {
    Room();
    for (int d = 0; d < 4; ++d) Desk(Eigen::Vector2d(2.0 + 2.0 * (d % 2), 1.6 + 2.8 * (d / 2)), d);
    Shelf();
    for (int p = 0; p < 6; ++p) {
      Add("", {{{7.98, 0.8 + 0.9 * p, 1.6}, {0.01, 0.35, 0.45}, 0.0, TextureRole::kPoster, p, 0.7}});
    }
    for (int p = 0; p < 2; ++p) Person(Eigen::Vector2d(3.0 + 1.5 * p, 3.0 - 0.8 * p), 40.0 + 90.0 * p, p);
  }
  const SceneSnapshot& scene() const { return scene_; }
  int box_count() const {
    int count = 0;
    for (const SceneInstance& instance : scene_.instances) count += static_cast<int>(instance.parts.size());
    return count;
  }

 private:
  struct Part {
    Eigen::Vector3d centre;
    Eigen::Vector3d half;
    double yaw_deg;
    TextureRole role;
    int variant;
    double texture_scale;
  };

  void Add(const std::string& label, const std::vector<Part>& parts) {
    SceneInstance instance;
    instance.id = static_cast<int>(scene_.instances.size()) + 1;
    instance.label = label;
    for (const Part& part : parts) {
      Box box;
      box.T_wb.translate(part.centre);
      box.T_wb.rotate(Eigen::AngleAxisd(part.yaw_deg * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()));
      box.half_size = part.half;
      box.texture = textures_.Index(part.role, part.variant);
      box.texture_scale = part.texture_scale;
      instance.parts.push_back(box);
    }
    scene_.instances.push_back(std::move(instance));
  }

  void Room() {
    Add("", {{{4.0, 3.0, -0.05}, {4.1, 3.1, 0.05}, 0.0, TextureRole::kFloor, 0, 0.6},
             {{4.0, 3.0, 2.85}, {4.1, 3.1, 0.05}, 0.0, TextureRole::kCeiling, 0, 1.2},
             {{-0.05, 3.0, 1.4}, {0.05, 3.1, 1.5}, 0.0, TextureRole::kWall, 0, 0.8},
             {{8.05, 3.0, 1.4}, {0.05, 3.1, 1.5}, 0.0, TextureRole::kWall, 0, 0.8},
             {{4.0, -0.05, 1.4}, {4.1, 0.05, 1.5}, 0.0, TextureRole::kWall, 0, 0.8},
             {{4.0, 6.05, 1.4}, {4.1, 0.05, 1.5}, 0.0, TextureRole::kWall, 0, 0.8}});
  }

  void Desk(const Eigen::Vector2d& at, int index) {
    const double x = at.x();
    const double y = at.y();
    std::vector<Part> desk = {{{x, y, 0.72}, {0.8, 0.4, 0.02}, 0.0, TextureRole::kDesk, 0, 0.5}};
    for (int leg = 0; leg < 4; ++leg) {
      desk.push_back({{x + ((leg & 1) ? 0.75 : -0.75), y + ((leg & 2) ? 0.35 : -0.35), 0.35}, {0.025, 0.025, 0.35},
                      0.0, TextureRole::kMonitorBody, 0, 0.3});
    }
    Add("", desk);
    Add("tv", {{{x + 0.2, y, 1.05}, {0.02, 0.28, 0.17}, 0.0, TextureRole::kMonitorScreen, 0, 0.56},
               {{x + 0.23, y, 1.05}, {0.015, 0.3, 0.19}, 0.0, TextureRole::kMonitorBody, 0, 0.4},
               {{x + 0.25, y, 0.82}, {0.02, 0.03, 0.08}, 0.0, TextureRole::kMonitorBody, 0, 0.4},
               {{x + 0.25, y, 0.745}, {0.08, 0.12, 0.005}, 0.0, TextureRole::kMonitorBody, 0, 0.4}});
    Add("keyboard", {{{x - 0.15, y, 0.75}, {0.07, 0.22, 0.01}, 0.0, TextureRole::kKeyboard, 0, 0.44}});
    Add("mouse", {{{x - 0.15, y - 0.32, 0.755}, {0.05, 0.03, 0.015}, 0.0, TextureRole::kMouse, 0, 0.1}});
    Add("cup", {{{x - 0.1, y + 0.3, 0.79}, {0.04, 0.04, 0.05}, 0.0, TextureRole::kCup, index, 0.25}});
    Add("bottle", {{{x + 0.05, y - 0.35, 0.84}, {0.035, 0.035, 0.1}, 0.0, TextureRole::kBottle, index, 0.2},
                   {{x + 0.05, y - 0.35, 0.96}, {0.015, 0.015, 0.02}, 0.0, TextureRole::kBottle, index, 0.2}});
    Add("laptop", {{{x - 0.5, y - 0.1, 0.75}, {0.12, 0.17, 0.01}, 20.0, TextureRole::kKeyboard, 0, 0.34},
                   {{x - 0.38, y - 0.05, 0.86}, {0.01, 0.17, 0.11}, 20.0, TextureRole::kLaptop, 0, 0.34}});
    for (int b = 0; b < 3; ++b) {
      Add("book", {{{x - 0.6, y + 0.25, 0.76 + 0.03 * b}, {0.1, 0.14, 0.014}, 10.0 * b, TextureRole::kBookCover, b + index,
                    0.28}});
    }
    Chair(Eigen::Vector2d(x - 0.7, y + 0.1), 180.0 + 15.0 * index);
    for (int c = 0; c < 14; ++c) {  // cables, pens, papers: small clutter
      Add("", {{{x - 0.75 + 0.115 * c, y + 0.37, 0.745}, {0.03, 0.02, 0.005}, 25.0 * c, TextureRole::kGeneric, c, 0.1}});
    }
  }

  void Chair(const Eigen::Vector2d& at, double yaw_deg) {
    const double yaw = yaw_deg * std::numbers::pi / 180.0;
    const Eigen::Vector2d back = at - 0.22 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
    std::vector<Part> chair = {{{at.x(), at.y(), 0.47}, {0.23, 0.23, 0.04}, yaw_deg, TextureRole::kChair, 0, 0.3},
                               {{back.x(), back.y(), 0.8}, {0.03, 0.22, 0.28}, yaw_deg, TextureRole::kChair, 0, 0.3},
                               {{at.x(), at.y(), 0.25}, {0.03, 0.03, 0.2}, 0.0, TextureRole::kMonitorBody, 0, 0.3}};
    for (int leg = 0; leg < 5; ++leg) {
      const double a = yaw + leg * 2.0 * std::numbers::pi / 5.0;
      chair.push_back({{at.x() + 0.15 * std::cos(a), at.y() + 0.15 * std::sin(a), 0.04}, {0.15, 0.02, 0.02},
                       a * 180.0 / std::numbers::pi, TextureRole::kMonitorBody, 0, 0.3});
    }
    Add("chair", chair);
  }

  void Shelf() {
    std::vector<Part> shelf = {{{7.7, 5.0, 0.95}, {0.17, 0.5, 0.95}, 0.0, TextureRole::kDesk, 0, 0.5}};
    Add("", shelf);
    for (int board = 0; board < 4; ++board) {
      for (int b = 0; b < 24; ++b) {
        Add("book", {{{7.5, 4.55 + 0.037 * b, 0.2 + 0.45 * board}, {0.1, 0.017, 0.12 + 0.01 * (b % 3)}, 0.0,
                      TextureRole::kBookCover, b, 0.28}});
      }
    }
  }

  void Person(const Eigen::Vector2d& at, double yaw_deg, int variant) {
    const double yaw = yaw_deg * std::numbers::pi / 180.0;
    const Eigen::Vector2d side(-std::sin(yaw), std::cos(yaw));
    std::vector<Part> body = {
        {{at.x(), at.y(), 1.25}, {0.12, 0.2, 0.3}, yaw_deg, TextureRole::kShirt, variant, 0.4},
        {{at.x(), at.y(), 1.7}, {0.1, 0.09, 0.12}, yaw_deg, TextureRole::kSkin, 0, 0.3},
        {{at.x(), at.y(), 1.83}, {0.11, 0.1, 0.03}, yaw_deg, TextureRole::kHair, 0, 0.3}};
    for (int s = -1; s <= 1; s += 2) {
      const Eigen::Vector2d limb = at + s * 0.1 * side;
      const Eigen::Vector2d arm = at + s * 0.26 * side;
      body.push_back({{limb.x(), limb.y(), 0.72}, {0.07, 0.07, 0.25}, yaw_deg, TextureRole::kTrousers, variant, 0.4});
      body.push_back({{limb.x(), limb.y(), 0.25}, {0.06, 0.06, 0.22}, yaw_deg, TextureRole::kTrousers, variant, 0.4});
      body.push_back({{limb.x(), limb.y(), 0.03}, {0.12, 0.05, 0.03}, yaw_deg, TextureRole::kShoe, 0, 0.2});
      body.push_back({{arm.x(), arm.y(), 1.35}, {0.05, 0.05, 0.18}, yaw_deg, TextureRole::kShirt, variant, 0.4});
      body.push_back({{arm.x(), arm.y(), 1.0}, {0.04, 0.04, 0.16}, yaw_deg, TextureRole::kSkin, 0, 0.3});
    }
    Add("person", body);
  }

  const TextureSet& textures_;
  SceneSnapshot scene_;
};

const TextureSet& Textures() {
  static const TextureSet textures;
  return textures;
}

core::Pose BenchCamera(int frame) {
  // Standing by the door, sweeping slowly across the desks.
  return CameraPoseFromYawPitch({0.6, 0.8, 1.45}, 35.0 + 10.0 * std::sin(frame * 0.05), -12.0);
}

void BM_Render(benchmark::State& state) {
  const BenchOffice office(Textures());
  const Renderer renderer(core::CameraIntrinsics{}, Textures());
  int frame = 0;
  for (auto _ : state) benchmark::DoNotOptimize(renderer.Render(office.scene(), BenchCamera(frame++)));
  state.counters["boxes"] = office.box_count();
}
BENCHMARK(BM_Render)->Unit(benchmark::kMillisecond);

void BM_RgbNoise(benchmark::State& state) {
  const BenchOffice office(Textures());
  const RenderOutput out = Renderer(core::CameraIntrinsics{}, Textures()).Render(office.scene(), BenchCamera(0));
  const SensorNoiseOptions options;
  std::uint64_t frame = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ApplyRgbNoise(out.bgr, options, FrameSeed(1, frame++, 1)));
}
BENCHMARK(BM_RgbNoise)->Unit(benchmark::kMillisecond);

void BM_DepthNoise(benchmark::State& state) {
  const BenchOffice office(Textures());
  const RenderOutput out = Renderer(core::CameraIntrinsics{}, Textures()).Render(office.scene(), BenchCamera(0));
  const SensorNoiseOptions options;
  std::uint64_t frame = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ApplyDepthNoise(out.depth, options, FrameSeed(1, frame++, 2)));
}
BENCHMARK(BM_DepthNoise)->Unit(benchmark::kMillisecond);

void BM_TextureSet(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(TextureSet());
}
BENCHMARK(BM_TextureSet)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoidslam::synth
