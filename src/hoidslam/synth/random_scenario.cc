#include "hoidslam/synth/random_scenario.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <optional>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "hoidslam/core/error.h"
#include "hoidslam/synth/camera_path.h"
#include "hoidslam/synth/office.h"
#include "hoidslam/synth/plane_geometry.h"
#include "hoidslam/synth/random.h"
#include "hoidslam/synth/textures.h"
#include "hoidslam/synth/world.h"

namespace hoidslam::synth {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using nlohmann::json;

constexpr double kFps = 30.0;
// Draws that fail a check are replaced; this many failing in a row would mean a bug, not bad luck.
constexpr std::uint64_t kMaxDraws = 100;

// Purposes of the seeds of one draw: FrameSeed(seed, draw, purpose), so that each part has a stream of its own.
enum DrawPurpose : std::uint64_t { kOfficeStream = 1, kCameraStream = 2, kMomentStream = 3, kPeopleStream = 4 };

// The camera keeps this much more than kRandomCameraClearance when it is planned, for the hand-held shake and the
// smoothing between waypoints; the finished path is held to kRandomCameraClearance itself.
constexpr double kCameraMargin = 0.42;
constexpr double kCameraRouteClearance = 0.55;  // from furniture (and chairs) when the camera walks round it
constexpr double kChairRadius = 0.33;           // a chair's footprint, as the circle through its corners
constexpr double kPersonMargin = 0.35;          // from furniture and walls to where a person may be sent
constexpr double kWalkway = 0.8;                // free floor between pieces of furniture (and their chairs)
constexpr double kWalkTurnRate = 80.0;          // degrees per second: the fastest a walk turns the view
constexpr double kSampleStep = 0.3;             // seconds between the waypoints of a walk
constexpr double kSlowestWalk = 0.2;            // metres per second: the range walking speeds are drawn from
constexpr double kFastestWalk = 0.8;
constexpr double kLongestWalk = 10.0;           // seconds a walk lasts at most, unless it needs more at kFastestWalk
constexpr double kPersonCameraDistance = 0.45;  // nobody walks through whoever holds the camera


// `value` to `decimals` decimals, so that the document reads as a person would write it.
double Rounded(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

// "1 desk", "2 desks".
std::string Count(std::size_t n, std::string_view one, std::string_view many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

json Point(const Vector2d& p) { return json::array({Rounded(p.x(), 3), Rounded(p.y(), 3)}); }
json Point(const Vector3d& p) { return json::array({Rounded(p.x(), 3), Rounded(p.y(), 3), Rounded(p.z(), 3)}); }

template <typename T>
const T& Pick(Random& random, const std::vector<T>& items) {
  return items[static_cast<std::size_t>(random.UniformInt(0, static_cast<int>(items.size()) - 1))];
}

template <typename T>
void Shuffle(Random& random, std::vector<T>& items) {
  for (std::size_t i = items.size(); i > 1; --i) {
    std::swap(items[i - 1], items[static_cast<std::size_t>(random.UniformInt(0, static_cast<int>(i) - 1))]);
  }
}

// The fraction of the way covered after `t` of `duration` seconds, for a motion whose speed rises and falls as a
// half cosine over `ramp` seconds at each end (ramp <= duration / 2) and is steady between: it starts and ends at
// rest, with a continuous speed.
double Progress(double t, double duration, double ramp) {
  t = std::clamp(t, 0.0, duration);
  if (ramp <= 0.0) return t / duration;
  const double total = duration - ramp;  // the distance at unit steady speed
  // The distance covered `s` seconds into a ramp.
  const auto ramped = [ramp](double s) { return s / 2.0 - ramp / (2.0 * kPi) * std::sin(kPi * s / ramp); };
  if (t <= ramp) return ramped(t) / total;
  if (t >= duration - ramp) return 1.0 - ramped(duration - t) / total;
  return (ramp / 2.0 + (t - ramp)) / total;
}

// ---- The office ---------------------------------------------------------------------------------------------------

// An axis-aligned rectangle on the floor.
struct Rect {
  Vector2d lo, hi;

  static Rect Around(const Vector2d& centre, const Vector2d& half) { return {centre - half, centre + half}; }
  double Gap(const Rect& other) const {
    const double dx = std::max({0.0, other.lo.x() - hi.x(), lo.x() - other.hi.x()});
    const double dy = std::max({0.0, other.lo.y() - hi.y(), lo.y() - other.hi.y()});
    return std::hypot(dx, dy);
  }
  Rect Joined(const Rect& other) const { return {lo.cwiseMin(other.lo), hi.cwiseMax(other.hi)}; }
};

constexpr std::array kWalls = {Wall::kFront, Wall::kRight, Wall::kBack, Wall::kLeft};

// The rectangle of something `width` wide along the wall and `depth` deep, `gap` off the wall, centred `at`.
Rect AgainstWall(const Vector3d& room, Wall wall, double at, double width, double depth, double gap) {
  const Vector2d centre = WallPoint(room, wall, at) + InwardNormal(wall) * (gap + depth / 2.0);
  const bool along_x = wall == Wall::kFront || wall == Wall::kBack;
  return Rect::Around(centre, along_x ? Vector2d(width / 2.0, depth / 2.0) : Vector2d(depth / 2.0, width / 2.0));
}

// A stretch of a wall: [from, to] along it.
struct WallStretch {
  Wall wall = Wall::kBack;
  double from = 0.0;
  double to = 0.0;

  bool Overlaps(const WallStretch& other, double margin) const {
    return wall == other.wall && from < other.to + margin && other.from < to + margin;
  }
};

// Where the camera and people may be: the free cells of a 0.1 m grid over the floor that are reachable from the
// door.
struct FreeFloor {
  static constexpr double kCell = 0.1;
  std::vector<Vector2d> people;  // a person may stand or be sent here
  std::vector<Vector2d> camera;  // the camera may be here, with room to spare
  std::vector<char> reached;     // per cell, row by row: in `people`
  int nx = 0;
  int ny = 0;

  // True when a person may be sent to `xy`: its cell is one of `people`.
  bool Reaches(const Vector2d& xy) const {
    const int i = static_cast<int>(std::floor(xy.x() / kCell));
    const int j = static_cast<int>(std::floor(xy.y() / kCell));
    return i >= 0 && j >= 0 && i < nx && j < ny && reached[static_cast<std::size_t>(j * nx + i)] != 0;
  }
};

// The floor as the planners see it: the footprints of the desks and shelves (random ones are turned by quarter
// turns, so their boxes are exact) and the chairs where they stand. OfficeLayout::IsBlocked says the same, slower.
class FloorPlan {
 public:
  explicit FloorPlan(const OfficeLayout& layout) : room_(layout.room) {
    const auto add = [this](const Vector2d& centre, double yaw_deg, const Vector2d& half) {
      const double c = std::abs(std::cos(Radians(yaw_deg)));
      const double s = std::abs(std::sin(Radians(yaw_deg)));
      furniture_.push_back(Rect::Around(centre, {c * half.x() + s * half.y(), s * half.x() + c * half.y()}));
    };
    for (const Desk& desk : layout.desks) add(desk.position, desk.yaw_deg, desk.size / 2.0);
    for (const Shelf& shelf : layout.shelves)
      add(shelf.position, shelf.yaw_deg, {shelf.size.y() / 2.0, shelf.size.x() / 2.0});
    for (const OfficeObject& object : layout.objects) {
      if (object.kind == ObjectKind::kChair) chairs_.push_back(object.position);
    }
  }

  // True when `xy` is `margin` from the walls and from every desk and shelf, and `chair_distance` from every
  // chair's centre: a person (or, with larger margins, the camera) may be there.
  bool Clear(const Vector2d& xy, double margin, double chair_distance) const {
    if (xy.x() < margin || xy.y() < margin || xy.x() > room_.x() - margin || xy.y() > room_.y() - margin) return false;
    const auto inside = [&](const Rect& r) {
      return xy.x() >= r.lo.x() - margin && xy.x() <= r.hi.x() + margin && xy.y() >= r.lo.y() - margin &&
             xy.y() <= r.hi.y() + margin;
    };
    if (std::any_of(furniture_.begin(), furniture_.end(), inside)) return false;
    return std::all_of(chairs_.begin(), chairs_.end(),
                       [&](const Vector2d& c) { return (c - xy).norm() >= chair_distance; });
  }

 private:
  Vector3d room_;
  std::vector<Rect> furniture_;
  std::vector<Vector2d> chairs_;
};

struct OfficePlan {
  OfficeLayout layout;
  json document;                       // the office object of the scenario
  WallStretch bare;                    // kept bare for the camera to stare at
  Vector2d door_spot;                  // inside the door: where people come in and leave
  double door_inward_deg = 0.0;        // facing into the room from the door
  std::vector<Vector3d> targets;       // things worth looking at: desks, shelves, posters
  std::vector<std::string> movable;    // objects people may carry
  std::vector<std::string> chairs;     // chairs (to sit on, to push)
  std::vector<std::string> watchable;  // objects people may stand in front of: monitors, laptops, shelved things
  std::vector<std::pair<Vector2d, double>> occupied;  // (centre, radius) of what stands on desks and the floor
  FreeFloor free;
  std::optional<FloorPlan> floor;  // of the finished office
};

// The free floor reachable from the door: a flood fill over a 0.1 m grid. Nullopt when a large part of the free
// floor cannot be reached (furniture walls a corner off): such an office is drawn again.
std::optional<FreeFloor> FindFreeFloor(const OfficeLayout& layout, const Vector2d& door_spot) {
  constexpr double kCell = FreeFloor::kCell;
  const FloorPlan plan(layout);
  const int nx = static_cast<int>(layout.room.x() / kCell);
  const int ny = static_cast<int>(layout.room.y() / kCell);
  const auto centre = [&](int i, int j) { return Vector2d((i + 0.5) * kCell, (j + 0.5) * kCell); };
  std::vector<char> free(static_cast<std::size_t>(nx * ny), 0);
  int free_count = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const bool f = plan.Clear(centre(i, j), kPersonMargin, kChairRadius + 0.25);
      free[static_cast<std::size_t>(j * nx + i)] = f ? 1 : 0;
      free_count += f ? 1 : 0;
    }
  }
  const int si = std::clamp(static_cast<int>(door_spot.x() / kCell), 0, nx - 1);
  const int sj = std::clamp(static_cast<int>(door_spot.y() / kCell), 0, ny - 1);
  if (free[static_cast<std::size_t>(sj * nx + si)] == 0) return std::nullopt;
  std::vector<char> reached(free.size(), 0);
  std::deque<std::pair<int, int>> queue = {{si, sj}};
  reached[static_cast<std::size_t>(sj * nx + si)] = 1;
  FreeFloor floor;
  while (!queue.empty()) {
    const auto [i, j] = queue.front();
    queue.pop_front();
    const Vector2d xy = centre(i, j);
    floor.people.push_back(xy);
    if (plan.Clear(xy, kCameraMargin + 0.1, kChairRadius + kCameraMargin + 0.05)) floor.camera.push_back(xy);
    for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
      const int a = i + di;
      const int b = j + dj;
      if (a < 0 || b < 0 || a >= nx || b >= ny) continue;
      const auto k = static_cast<std::size_t>(b * nx + a);
      if (free[k] == 0 || reached[k] != 0) continue;
      reached[k] = 1;
      queue.emplace_back(a, b);
    }
  }
  if (static_cast<double>(floor.people.size()) < 0.85 * free_count || floor.camera.size() < 150) return std::nullopt;
  floor.reached = std::move(reached);
  floor.nx = nx;
  floor.ny = ny;
  return floor;
}

class OfficeDrawer {
 public:
  explicit OfficeDrawer(Random& random) : random_(random) {}

  std::optional<OfficePlan> Draw() {
    OfficeLayout& layout = plan_.layout;
    // Rooms an RGB-D sensor can work in: from anywhere inside, most of what the camera faces lies within its
    // depth range (4.5 m). In a 10 m room a camera facing the far wall saw nothing with depth, and no RGB-D
    // tracker has anything to hold on to there.
    layout.room = {Rounded(random_.Uniform(6.0, 8.5), 2), Rounded(random_.Uniform(5.0, 7.0), 2),
                   Rounded(random_.Uniform(2.6, 3.2), 2)};
    layout.walls.emplace();
    DrawDoorAndBareStretch();
    DrawShelves();
    DrawDesks();
    if (layout.desks.size() < 2) return std::nullopt;
    DrawShelfThings();
    DrawFreeChairs();
    DrawFloorThing();
    DrawPanels();
    layout.patchwork_walls_seed = random_.Next();
    const auto free = FindFreeFloor(layout, plan_.door_spot);
    if (!free) return std::nullopt;
    plan_.free = *free;
    plan_.floor.emplace(layout);
    plan_.document = Document();
    return std::move(plan_);
  }

 private:
  const Vector3d& room() const { return plan_.layout.room; }

  // A random stretch `width` long on a random wall, `margin` from its ends; nullopt when the wall is too short.
  std::optional<WallStretch> RandomStretch(double width, double margin) {
    const Wall wall = kWalls[static_cast<std::size_t>(random_.UniformInt(0, 3))];
    const double length = WallLength(room(), wall);
    if (length < width + 2.0 * margin) return std::nullopt;
    const double from = random_.Uniform(margin, length - width - margin);
    return WallStretch{wall, from, from + width};
  }

  // True when `rect` keeps a walkway from everything placed so far and off the zones kept free.
  bool Fits(const Rect& rect, double walkway) const {
    const auto apart = [&](const Rect& other) { return rect.Gap(other) >= walkway; };
    return std::all_of(placed_.begin(), placed_.end(), apart) &&
           std::all_of(kept_free_.begin(), kept_free_.end(), [&](const Rect& zone) { return rect.Gap(zone) > 0.05; });
  }

  void DrawDoorAndBareStretch() {
    // The door: where people come in and leave; the floor in front of it stays free.
    for (;;) {
      if (const auto door = RandomStretch(0.95, 0.6)) {
        door_ = *door;
        break;
      }
    }
    const double door_at = (door_.from + door_.to) / 2.0;
    plan_.layout.walls->push_back({PanelKind::kDoor, door_.wall, Rounded(door_at, 3), 1.05, {0.95, 2.1}, 0});
    plan_.door_spot = WallPoint(room(), door_.wall, door_at) + InwardNormal(door_.wall) * 0.6;
    plan_.door_inward_deg = Degrees(std::atan2(InwardNormal(door_.wall).y(), InwardNormal(door_.wall).x()));
    kept_free_.push_back(AgainstWall(room(), door_.wall, door_at, 1.4, 1.3, 0.0));
    // A stretch of plain wall for the camera to stare at, and the floor in front of it.
    for (;;) {
      const auto bare = RandomStretch(random_.Uniform(2.3, 3.0), 0.4);
      if (bare && !bare->Overlaps(door_, 0.4)) {
        plan_.bare = *bare;
        break;
      }
    }
    const WallStretch& bare = plan_.bare;
    kept_free_.push_back(AgainstWall(room(), bare.wall, (bare.from + bare.to) / 2.0, bare.to - bare.from, 1.7, 0.0));
  }

  void DrawShelves() {
    const int count = random_.UniformInt(1, 3);
    for (int tries = 0; tries < 60 && static_cast<int>(plan_.layout.shelves.size()) < count; ++tries) {
      const double width = Rounded(random_.Uniform(0.8, 1.4), 2);
      const double depth = Rounded(random_.Uniform(0.3, 0.4), 2);
      const double height = Rounded(random_.Uniform(1.2, 2.0), 2);
      const auto stretch = RandomStretch(width, 0.3);
      if (!stretch) continue;
      const double at = (stretch->from + stretch->to) / 2.0;
      const Rect rect = AgainstWall(room(), stretch->wall, at, width, depth, 0.02);
      // The floor in front of a shelf stays free, so that people can reach it.
      const Rect access = AgainstWall(room(), stretch->wall, at, width, 0.7, depth + 0.02);
      if (!Fits(rect, kWalkway) || !Fits(access, 0.05)) continue;
      const Vector2d inward = InwardNormal(stretch->wall);
      const Vector2d centre = (rect.lo + rect.hi) / 2.0;
      Shelf shelf;
      shelf.name = fmt::format("shelf_{}", plan_.layout.shelves.size() + 1);
      shelf.position = {Rounded(centre.x(), 3), Rounded(centre.y(), 3)};
      shelf.yaw_deg = std::round(Degrees(std::atan2(inward.y(), inward.x())));
      shelf.size = {width, depth, height};
      shelf.boards = random_.UniformInt(3, 5);
      plan_.layout.shelves.push_back(shelf);
      placed_.push_back(rect);
      kept_free_.push_back(access);
      shelf_walls_.push_back(*stretch);
      plan_.targets.emplace_back(shelf.position.x(), shelf.position.y(), height * 0.6);
    }
  }

  void DrawDesks() {
    const double area = room().x() * room().y();
    const int count = std::clamp(static_cast<int>(std::lround(area / 13.0)) + random_.UniformInt(-1, 1), 2, 6);
    for (int tries = 0; tries < 120 && static_cast<int>(plan_.layout.desks.size()) < count; ++tries) {
      Desk desk;
      desk.size = {Rounded(random_.Uniform(1.2, 1.8), 2), Rounded(random_.Uniform(0.6, 0.85), 2)};
      desk.height = Rounded(random_.Uniform(0.72, 0.76), 3);
      Rect footprint;
      Vector2d front;  // where the chair stands, from the desk's centre
      if (random_.Bernoulli(0.55)) {
        // Against a wall, its back to it.
        const auto stretch = RandomStretch(desk.size.x(), 0.9);
        if (!stretch) continue;
        const Vector2d inward = InwardNormal(stretch->wall);
        footprint =
            AgainstWall(room(), stretch->wall, (stretch->from + stretch->to) / 2.0, desk.size.x(), desk.size.y(), 0.05);
        desk.yaw_deg = std::round(Degrees(std::atan2(-inward.y(), -inward.x()))) - 90.0;
        front = inward;
      } else {
        // Free in the room, turned by a quarter turn or more.
        desk.yaw_deg = 90.0 * random_.UniformInt(-1, 2);
        const bool along_x = desk.yaw_deg == 0.0 || desk.yaw_deg == 180.0;
        const Vector2d half = along_x ? Vector2d(desk.size.x() / 2.0, desk.size.y() / 2.0)
                                      : Vector2d(desk.size.y() / 2.0, desk.size.x() / 2.0);
        const double centre_y = random_.Uniform(half.y() + 1.0, room().y() - half.y() - 1.0);
        const Vector2d centre(random_.Uniform(half.x() + 1.0, room().x() - half.x() - 1.0), centre_y);
        footprint = Rect::Around(centre, half);
        const double yaw = Radians(desk.yaw_deg);
        front = Vector2d(std::sin(yaw), -std::cos(yaw));
      }
      desk.yaw_deg = std::remainder(desk.yaw_deg, 360.0);
      const Vector2d centre = (footprint.lo + footprint.hi) / 2.0;
      // The desk with the room for its chair in front.
      const Rect chair_zone = Rect::Around(centre + front * (desk.size.y() / 2.0 + 0.45), Vector2d::Constant(0.35));
      if (!Fits(footprint.Joined(chair_zone), kWalkway)) continue;
      desk.name = fmt::format("desk_{}", plan_.layout.desks.size() + 1);
      desk.position = {Rounded(centre.x(), 3), Rounded(centre.y(), 3)};
      plan_.layout.desks.push_back(desk);
      placed_.push_back(footprint.Joined(chair_zone));
      plan_.targets.emplace_back(centre.x(), centre.y(), desk.height + 0.15);
      DrawDeskThings(desk, front);
    }
  }

  void AddObject(ObjectKind kind, const Vector2d& xy, double yaw_deg, std::optional<double> z = std::nullopt) {
    const int index = ++kind_counts_[static_cast<std::size_t>(kind)];
    OfficeObject object;
    object.name = fmt::format("{}_{}", CocoLabel(kind), index);
    object.kind = kind;
    object.position = {Rounded(xy.x(), 3), Rounded(xy.y(), 3)};
    if (z) object.z = Rounded(*z, 3);
    object.yaw_deg = Rounded(std::remainder(yaw_deg, 360.0), 1);
    object.variant = random_.UniformInt(0, 7);
    plan_.layout.objects.push_back(object);
    if (kind == ObjectKind::kChair) {
      plan_.chairs.push_back(object.name);
    } else {
      if (kind != ObjectKind::kTv) plan_.movable.push_back(object.name);
      if (kind == ObjectKind::kTv || kind == ObjectKind::kLaptop || z) plan_.watchable.push_back(object.name);
    }
  }

  // A monitor with keyboard and mouse, things beside them, and a chair in front.
  void DrawDeskThings(const Desk& desk, const Vector2d& front) {
    const double yaw = Radians(desk.yaw_deg);
    const Eigen::Rotation2Dd rotation(yaw);
    const double hx = desk.size.x() / 2.0;
    const double hy = desk.size.y() / 2.0;
    const auto world = [&](const Vector2d& local) { return Vector2d(desk.position + rotation * local); };
    std::vector<std::pair<Vector2d, double>> taken;  // desk frame
    // Objects face the front of the desk (local -y): their own front is local +x, turned by -90 degrees.
    const double facing = desk.yaw_deg - 90.0;
    if (random_.Bernoulli(0.85)) {
      const double x = random_.Uniform(-0.25, 0.25) * hx;
      AddObject(ObjectKind::kTv, world({x, hy - 0.2}), facing);
      AddObject(ObjectKind::kKeyboard, world({x, -hy + 0.2}), facing);
      taken.push_back({{x, hy - 0.2}, 0.32});
      taken.push_back({{x, -hy + 0.2}, 0.24});
      const double mouse = x + (random_.Bernoulli(0.5) ? 0.36 : -0.36);
      if (std::abs(mouse) < hx - 0.08) {
        AddObject(ObjectKind::kMouse, world({mouse, -hy + 0.2}), facing);
        taken.push_back({{mouse, -hy + 0.2}, 0.07});
      }
    }
    const int things = random_.UniformInt(1, 3);
    for (int tries = 0, placed = 0; tries < 30 && placed < things; ++tries) {
      const double pick = random_.Uniform();
      const ObjectKind kind = pick < 0.3    ? ObjectKind::kCup
                              : pick < 0.6  ? ObjectKind::kBook
                              : pick < 0.85 ? ObjectKind::kBottle
                                            : ObjectKind::kLaptop;
      const Vector3d ext = ObjectHalfExtents(kind);
      const double radius = std::hypot(ext.x(), ext.y()) + 0.02;
      if (hx - radius <= -hx + radius || hy - radius <= -hy + radius) continue;
      const double local_y = random_.Uniform(-hy + radius, hy - radius);
      const Vector2d local(random_.Uniform(-hx + radius, hx - radius), local_y);
      const bool apart = std::all_of(taken.begin(), taken.end(), [&](const auto& other) {
        return (other.first - local).norm() > other.second + radius;
      });
      if (!apart) continue;
      const double turn = kind == ObjectKind::kLaptop ? random_.Uniform(-15.0, 15.0)
                          : kind == ObjectKind::kBook ? random_.Uniform(-30.0, 30.0)
                                                      : random_.Uniform(-180.0, 180.0);
      AddObject(kind, world(local), facing + turn);
      taken.push_back({local, radius});
      ++placed;
    }
    for (const auto& [local, radius] : taken) plan_.occupied.emplace_back(world(local), radius);
    if (random_.Bernoulli(0.85)) {
      // The chair faces the desk, 0.35 m from its front edge.
      AddObject(ObjectKind::kChair, desk.position + front * (hy + 0.35), desk.yaw_deg + 90.0);
    }
  }

  // Books, and a few cups and bottles, on the boards.
  void DrawShelfThings() {
    for (const Shelf& shelf : plan_.layout.shelves) {
      const double spacing = (shelf.size.z() - 0.04) / (shelf.boards - 1);
      const Eigen::Rotation2Dd rotation(Radians(shelf.yaw_deg));
      const double hw = shelf.size.x() / 2.0;
      const int things = random_.UniformInt(2, 5);
      std::vector<std::pair<int, double>> taken;  // (board, position across)
      for (int tries = 0, placed = 0; tries < 30 && placed < things; ++tries) {
        const double pick = random_.Uniform();
        const ObjectKind kind = pick < 0.65 ? ObjectKind::kBook : pick < 0.83 ? ObjectKind::kCup : ObjectKind::kBottle;
        const Vector3d ext = ObjectHalfExtents(kind);
        const int board = random_.UniformInt(1, shelf.boards - 1);
        const bool top = board == shelf.boards - 1;
        if (!top && spacing - 0.04 < 2.0 * ext.z() + 0.05) continue;
        const double across = random_.Uniform(-hw + 0.14, hw - 0.14);
        const bool apart = std::all_of(taken.begin(), taken.end(), [&](const auto& other) {
          return other.first != board || std::abs(other.second - across) > 0.22;
        });
        if (!apart) continue;
        const double z = 0.02 + spacing * board + 0.021;
        const double yaw =
            kind == ObjectKind::kBook ? shelf.yaw_deg + random_.Uniform(-8.0, 8.0) : random_.Uniform(-180.0, 180.0);
        AddObject(kind, shelf.position + rotation * Vector2d(0.0, across), yaw, z);
        taken.emplace_back(board, across);
        ++placed;
      }
    }
  }

  // A free chair or two, with room in front to sit down and to be pushed.
  void DrawFreeChairs() {
    const int count = random_.UniformInt(0, 2);
    for (int tries = 0, placed = 0; tries < 40 && placed < count; ++tries) {
      const double y = random_.Uniform(0.6, room().y() - 0.6);
      const Vector2d xy(random_.Uniform(0.6, room().x() - 0.6), y);
      const double yaw = random_.Uniform(-180.0, 180.0);
      const Vector2d ahead = xy + Direction(Radians(yaw)) * 0.9;
      const FloorPlan floor(plan_.layout);
      if (!floor.Clear(xy, 0.9, 1.2) || !floor.Clear(ahead, 0.5, 1.2)) continue;
      const Rect rect = Rect::Around(xy, Vector2d::Constant(kChairRadius));
      if (!Fits(rect, 0.5)) continue;
      AddObject(ObjectKind::kChair, xy, yaw);
      placed_.push_back(rect);
      ++placed;
    }
  }

  // Sometimes a bottle or a book on the floor by a wall.
  void DrawFloorThing() {
    if (!random_.Bernoulli(0.35)) return;
    for (int tries = 0; tries < 20; ++tries) {
      const auto stretch = RandomStretch(0.3, 0.5);
      if (!stretch || stretch->Overlaps(door_, 0.5) || stretch->Overlaps(plan_.bare, 0.3)) continue;
      const Vector2d xy = WallPoint(room(), stretch->wall, stretch->from + 0.15) + InwardNormal(stretch->wall) * 0.25;
      if (plan_.layout.IsBlocked(xy, 0.4) || !Fits(Rect::Around(xy, Vector2d::Constant(0.15)), 0.4)) continue;
      const double yaw_deg = random_.Uniform(-180.0, 180.0);
      AddObject(random_.Bernoulli(0.5) ? ObjectKind::kBottle : ObjectKind::kBook, xy, yaw_deg);
      plan_.occupied.emplace_back(xy, 0.2);
      placed_.push_back(Rect::Around(xy, Vector2d::Constant(0.15)));
      return;
    }
  }

  // Posters and maybe a whiteboard, none on the bare stretch, the door or behind a shelf.
  void DrawPanels() {
    std::vector<WallStretch> used = shelf_walls_;
    used.push_back(door_);
    used.push_back(plan_.bare);
    const auto place = [&](PanelKind kind, const Vector2d& size, double z, int variant) {
      for (int tries = 0; tries < 30; ++tries) {
        const auto stretch = RandomStretch(size.x(), 0.25);
        if (!stretch) continue;
        const bool apart = std::none_of(used.begin(), used.end(),
                                        [&](const WallStretch& other) { return stretch->Overlaps(other, 0.3); });
        if (!apart) continue;
        const double at = Rounded((stretch->from + stretch->to) / 2.0, 3);
        plan_.layout.walls->push_back({kind, stretch->wall, at, Rounded(z, 3), size, variant});
        used.push_back(*stretch);
        const Vector2d xy = WallPoint(room(), stretch->wall, at);
        plan_.targets.emplace_back(xy.x(), xy.y(), z);
        return;
      }
    };
    if (random_.Bernoulli(0.6)) {
      place(PanelKind::kWhiteboard, {Rounded(random_.Uniform(1.2, 1.8), 2), Rounded(random_.Uniform(0.8, 1.1), 2)},
            1.45, 0);
    }
    // About one poster for every 12 m of wall, give or take.
    const int posters = random_.UniformInt(2, 4) + static_cast<int>(2.0 * (room().x() + room().y()) / 12.0);
    for (int i = 0; i < posters; ++i) {
      const double height = Rounded(random_.Uniform(0.6, 1.0), 2);
      const Vector2d size(Rounded(random_.Uniform(0.5, 1.0), 2), height);
      place(PanelKind::kPoster, size, std::min(random_.Uniform(1.45, 1.85), room().z() - 0.2 - size.y() / 2.0), i);
    }
  }

  json Document() const {
    const OfficeLayout& layout = plan_.layout;
    json office = {{"base", "empty"}, {"room", Point(layout.room)}};
    json& desks = office["desks"] = json::array();
    for (const Desk& d : layout.desks) {
      desks.push_back({{"name", d.name},
                       {"position", Point(d.position)},
                       {"yaw_deg", Rounded(d.yaw_deg, 1)},
                       {"size", Point(d.size)},
                       {"height", d.height}});
    }
    json& shelves = office["shelves"] = json::array();
    for (const Shelf& s : layout.shelves) {
      shelves.push_back({{"name", s.name},
                         {"position", Point(s.position)},
                         {"yaw_deg", Rounded(s.yaw_deg, 1)},
                         {"size", Point(s.size)},
                         {"boards", s.boards}});
    }
    json& objects = office["objects"] = json::array();
    for (const OfficeObject& o : layout.objects) {
      json object = {{"name", o.name},
                     {"type", CocoLabel(o.kind)},
                     {"position", Point(o.position)},
                     {"yaw_deg", o.yaw_deg},
                     {"variant", o.variant}};
      if (o.z) object["z"] = *o.z;
      objects.push_back(std::move(object));
    }
    office["patchwork_walls_seed"] = *layout.patchwork_walls_seed;
    json& walls = office["walls"] = json::array();
    for (const WallPanel& p : *layout.walls) {
      json panel = {{"type", ToString(p.kind)}, {"wall", ToString(p.wall)}, {"at", p.at}, {"size", Point(p.size)}};
      if (p.kind != PanelKind::kDoor) panel["z"] = p.z;
      if (p.kind == PanelKind::kPoster) panel["variant"] = p.variant;
      walls.push_back(std::move(panel));
    }
    return office;
  }

  Random& random_;
  OfficePlan plan_;
  WallStretch door_;
  std::vector<Rect> placed_;     // furniture with the room it needs around it
  std::vector<Rect> kept_free_;  // the floor in front of the door and of the bare stretch
  std::vector<WallStretch> shelf_walls_;
  std::array<int, 8> kind_counts_{};  // by ObjectKind, for the names
};

// ---- The camera ---------------------------------------------------------------------------------------------------

// A waypoint as planned: yaw and roll unwrapped (continuous), in degrees.
struct PlannedPose {
  double time = 0.0;
  Vector3d position = Vector3d::Zero();
  double yaw = 0.0;
  double pitch = 0.0;
  double roll = 0.0;
};

// Heading and elevation (degrees) of the view from `eye` to `target`; the elevation kept within [-45, 30].
std::pair<double, double> Look(const Vector3d& eye, const Vector3d& target) {
  const Vector3d d = target - eye;
  const double yaw = Degrees(std::atan2(d.y(), d.x()));
  const double pitch = Degrees(std::atan2(d.z(), d.head<2>().norm()));
  return {yaw, std::clamp(pitch, -45.0, 30.0)};
}

// A pose held before, to come back to.
struct Landmark {
  double time = 0.0;
  Vector3d position = Vector3d::Zero();
  Vector3d target = Vector3d::Zero();  // what it looked at: the pose looks from `position` at `target`
};

enum class SegmentKind { kWalk, kReturn, kRing, kRpy, kWall, kHold };

struct CameraSegment {
  SegmentKind kind = SegmentKind::kWalk;
  double from = 0.0;
  double to = 0.0;
  std::string note;  // for the description
};

class CameraPlanner {
 public:
  CameraPlanner(const OfficePlan& office, Random& random, double duration)
      : office_(office), random_(random), duration_(duration), routes_(office.layout) {
    // The camera walks round chairs too: for its routes they are small shelves.
    for (const OfficeObject& object : office.layout.objects) {
      if (object.kind != ObjectKind::kChair) continue;
      Shelf chair;
      chair.name = object.name;
      chair.position = object.position;
      chair.size = {2.0 * kChairRadius, 2.0 * kChairRadius, 1.0};
      routes_.shelves.push_back(chair);
    }
  }

  // The waypoints, from time 0 to the duration.
  std::vector<PlannedPose> Plan() {
    Start();
    // A ring always (a second one sometimes), fast turns and a bare-wall stare mostly, in a random order, with
    // walks (many of them back to earlier views) between them.
    using Segment = bool (CameraPlanner::*)();
    struct Special {
      Segment segment;
      bool again = false;  // tried once already
    };
    std::vector<Special> specials = {{&CameraPlanner::Ring}};
    if (random_.Bernoulli(0.25)) specials.push_back({&CameraPlanner::Ring});
    if (random_.Bernoulli(0.85)) specials.push_back({&CameraPlanner::Rpy});
    if (random_.Bernoulli(0.25)) specials.push_back({&CameraPlanner::Rpy});
    if (random_.Bernoulli(0.85)) specials.push_back({&CameraPlanner::WallStare});
    if (random_.Bernoulli(0.2)) specials.push_back({&CameraPlanner::WallStare});
    Shuffle(random_, specials);
    bool walk_next = true;  // a gentle start, for the tracker to begin on
    int failures = 0;
    while (duration_ - Now() > 3.0 && failures < 12) {
      bool done = false;
      if (walk_next || specials.empty()) {
        done = (random_.Bernoulli(0.6) && Return()) || Walk();
      } else {
        const Special special = specials.back();
        specials.pop_back();
        done = (this->*special.segment)();
        // One that does not fit here is tried once more after the others, from another place.
        if (!done && !special.again) specials.insert(specials.begin(), {special.segment, true});
      }
      failures = done ? 0 : failures + 1;
      walk_next = done ? !walk_next : walk_next;
    }
    HoldToTheEnd();
    return points_;
  }

  const std::vector<CameraSegment>& segments() const { return segments_; }

 private:
  using Piece = std::vector<PlannedPose>;

  double Now() const { return points_.back().time; }
  const PlannedPose& Last() const { return points_.back(); }

  bool CameraClear(const Vector2d& xy) const {
    return office_.floor->Clear(xy, kCameraMargin, kChairRadius + kCameraMargin);
  }

  const Vector2d& RandomCameraSpot() { return Pick(random_, office_.free.camera); }

  // Something worth looking at from `eye`, at least `nearest` metres away and, where there is such a thing, within
  // kViewReach, where the depth sensor sees it: a desk, a shelf, a poster, or a random point of a wall.
  Vector3d RandomTarget(const Vector3d& eye, double nearest) {
    static constexpr double kViewReach = 3.5;  // metres
    std::optional<Vector3d> farther;  // beyond the reach, for a room where nothing lies within it
    for (int tries = 0; tries < 40; ++tries) {
      Vector3d target;
      if (random_.Bernoulli(0.7) && !office_.targets.empty()) {
        target = Pick(random_, office_.targets);
      } else {
        const Wall wall = kWalls[static_cast<std::size_t>(random_.UniformInt(0, 3))];
        const Vector2d xy =
            WallPoint(office_.layout.room, wall, random_.Uniform(0.3, WallLength(office_.layout.room, wall) - 0.3));
        target = {xy.x(), xy.y(), random_.Uniform(1.0, 1.9)};
      }
      const double distance = (target - eye).head<2>().norm();
      if (distance < nearest) continue;
      if (distance <= kViewReach) return target;
      if (!farther) farther = target;
    }
    if (farther) return *farther;
    // Far enough in any room: the farthest corner at eye height.
    const Vector3d& room = office_.layout.room;
    return {eye.x() < room.x() / 2.0 ? room.x() : 0.0, eye.y() < room.y() / 2.0 ? room.y() : 0.0, eye.z()};
  }

  void Start() {
    const Vector2d xy = RandomCameraSpot();
    const Vector3d eye(xy.x(), xy.y(), random_.Uniform(1.3, 1.6));
    const Vector3d target = RandomTarget(eye, 1.8);
    const auto [yaw, pitch] = Look(eye, target);
    points_.push_back({0.0, eye, yaw, pitch, 0.0});
    landmarks_.push_back({0.0, eye, target});
  }

  static Vector3d Forward(double yaw_deg, double pitch_deg) {
    const double yaw = Radians(yaw_deg);
    const double pitch = Radians(pitch_deg);
    return {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch)};
  }

  void Commit(const Piece& piece, SegmentKind kind, std::string note) {
    segments_.push_back({kind, Now(), piece.back().time, std::move(note)});
    points_.insert(points_.end(), piece.begin(), piece.end());
  }

  // A hand-held walk from `from` to `goal` round the furniture, looking at `target` (turning to it at first),
  // at `speed` (faster on a long way, so that no walk lasts much more than kLongestWalk): the waypoints after
  // `from`, and the speed. Nullopt when there is no way, or the view would swing too fast, or the target comes
  // nearer than `nearest`.
  struct Walked {
    Piece piece;
    double speed = 0.0;
  };
  std::optional<Walked> PlanWalk(const PlannedPose& from, const Vector3d& goal, const Vector3d& target, double speed,
                                 double nearest) const {
    const auto route = routes_.Route(from.position.head<2>(), goal.head<2>(), kCameraRouteClearance);
    if (!route) return std::nullopt;
    std::vector<Vector2d> polyline = {from.position.head<2>()};
    polyline.insert(polyline.end(), route->begin(), route->end());
    std::vector<double> along = {0.0};
    for (std::size_t i = 1; i < polyline.size(); ++i)
      along.push_back(along.back() + (polyline[i] - polyline[i - 1]).norm());
    const double length = along.back();
    speed = std::clamp(length / kLongestWalk, speed, kFastestWalk);
    const auto at = [&](double s) {
      const std::size_t k = static_cast<std::size_t>(
          std::max<std::ptrdiff_t>(1, std::upper_bound(along.begin(), along.end(), s) - along.begin()));
      if (k >= polyline.size()) return polyline.back();
      const double piece = along[k] - along[k - 1];
      return Vector2d(polyline[k - 1] +
                      (piece > 0.0 ? (s - along[k - 1]) / piece : 0.0) * (polyline[k] - polyline[k - 1]));
    };
    // The view turns from where it looks now to the target at most at kWalkTurnRate (the peak of an eased turn is
    // 1.5 times its mean rate).
    const auto [yaw0, pitch0] = Look(from.position, target);
    const double turn = std::max(std::abs(std::remainder(yaw0 - from.yaw, 360.0)), std::abs(pitch0 - from.pitch));
    const double turn_time = std::max(0.6, 1.5 * turn / kWalkTurnRate);
    const double ramp = std::min(1.0, length / speed);
    const double duration = std::max({length / speed + ramp, turn_time, 0.6});
    const int steps = std::max(2, static_cast<int>(std::ceil(duration / kSampleStep)));
    Piece piece;
    double target_yaw = from.yaw + std::remainder(yaw0 - from.yaw, 360.0);  // unwrapped from the yaw now
    double previous_yaw = from.yaw;
    for (int i = 1; i <= steps; ++i) {
      const double t = duration * i / steps;
      const double s = length > 0.0 ? Progress(t, duration, ramp) : 1.0;
      const Vector2d xy = at(s * length);
      const Vector3d eye(xy.x(), xy.y(), from.position.z() + s * (goal.z() - from.position.z()));
      if (!CameraClear(xy)) return std::nullopt;
      if ((target - eye).head<2>().norm() < nearest) return std::nullopt;
      const auto [yaw, pitch] = Look(eye, target);
      target_yaw += std::remainder(yaw - target_yaw, 360.0);
      const double w = Smoothstep(std::min(1.0, t / turn_time));
      PlannedPose pose{from.time + t, eye, from.yaw + w * (target_yaw - from.yaw),
                       from.pitch + w * (pitch - from.pitch), (1.0 - w) * from.roll};
      if (std::abs(pose.yaw - previous_yaw) / (duration / steps) > 1.2 * kWalkTurnRate) return std::nullopt;
      previous_yaw = pose.yaw;
      piece.push_back(pose);
    }
    return Walked{std::move(piece), speed};
  }

  bool Fits(const Piece& piece) const { return piece.back().time <= duration_ - 0.5; }

  // A walk to a random free spot, looking at something.
  bool Walk() {
    for (int tries = 0; tries < 8; ++tries) {
      const Vector2d xy = RandomCameraSpot();
      const double distance = (xy - Last().position.head<2>()).norm();
      if (distance < 1.2 || distance > 5.0) continue;
      const Vector3d goal(xy.x(), xy.y(), random_.Uniform(1.2, 1.65));
      const Vector3d target = RandomTarget(goal, 1.6);
      const auto walk = PlanWalk(Last(), goal, target, random_.Uniform(kSlowestWalk, kFastestWalk), 1.0);
      if (!walk || !Fits(walk->piece)) continue;
      Commit(walk->piece, SegmentKind::kWalk, fmt::format("at {:.2f} m/s", walk->speed));
      landmarks_.push_back({Now(), goal, target});
      return true;
    }
    return false;
  }

  // A walk back to a pose held at least 12 s ago, arriving with its view, and a moment there.
  bool Return() {
    std::vector<Landmark> earlier;
    for (const Landmark& landmark : landmarks_) {
      if (landmark.time <= Now() - 12.0 && (landmark.position - Last().position).norm() > 1.0) {
        earlier.push_back(landmark);
      }
    }
    if (earlier.empty()) return false;
    for (int tries = 0; tries < 4; ++tries) {
      const Landmark& landmark = Pick(random_, earlier);
      auto walk =
          PlanWalk(Last(), landmark.position, landmark.target, random_.Uniform(kSlowestWalk, kFastestWalk), 0.8);
      if (!walk) continue;
      PlannedPose stay = walk->piece.back();
      stay.time += random_.Uniform(0.5, 1.5);
      walk->piece.push_back(stay);
      if (!Fits(walk->piece)) continue;
      Commit(walk->piece, SegmentKind::kReturn,
             fmt::format("at {:.2f} m/s back to the view of {:.1f} s", walk->speed, landmark.time));
      return true;
    }
    return false;
  }

  // Round a circle about a free centre, facing outwards, more than once: every later turn sees again what the first
  // saw, from nearly the same poses.
  bool Ring() {
    for (int tries = 0; tries < 12; ++tries) {
      // Smaller circles fit where larger ones do not.
      const double radius = random_.Uniform(0.3, 1.5 - 0.08 * tries);
      const Vector2d centre = RandomCameraSpot();
      // Clear of the furniture all round, and 0.9 m or more from the walls, so that looking outwards it sees more
      // than a patch of wall.
      const Vector3d& room = office_.layout.room;
      const bool roomy = centre.x() - radius > 0.9 && centre.y() - radius > 0.9 &&
                         centre.x() + radius < room.x() - 0.9 && centre.y() + radius < room.y() - 0.9;
      bool clear = roomy;
      for (int k = 0; k < 64 && clear; ++k) clear = CameraClear(centre + radius * Direction(2.0 * kPi * k / 64));
      if (!clear) continue;
      // At most 0.5 m/s along the circle and 45 degrees a second round it.
      const double turn_rate_deg = random_.Uniform(30.0, 45.0);
      const double period = std::max(2.0 * kPi * radius / random_.Uniform(0.3, 0.5), 360.0 / turn_rate_deg);
      const double start = random_.Uniform(-180.0, 180.0);
      const double sense = random_.Bernoulli(0.5) ? 1.0 : -1.0;
      const double height = random_.Uniform(1.25, 1.6);
      const double pitch = random_.Uniform(-15.0, -3.0);
      const Vector2d first = centre + radius * Direction(Radians(start));
      const Vector3d eye(first.x(), first.y(), height);
      const auto walk = PlanWalk(Last(), eye, eye + 2.5 * Forward(start, pitch), random_.Uniform(0.3, 0.7), 1.0);
      if (!walk) continue;
      Piece piece = walk->piece;
      const double ramp = 1.5;
      const double room_left = std::min(duration_ - 0.5, piece.back().time + 0.45 * duration_) - piece.back().time;
      const double turns = std::min(random_.Uniform(1.15, 2.0), (room_left - ramp) / period);
      if (turns < 1.1) continue;
      const double time = turns * period + ramp;
      const PlannedPose begin = piece.back();
      const int steps = static_cast<int>(std::ceil(time / (period / 24.0)));
      for (int i = 1; i <= steps; ++i) {
        const double t = time * i / steps;
        const double angle = begin.yaw + sense * 360.0 * turns * Progress(t, time, ramp);
        const Vector2d xy = centre + radius * Direction(Radians(angle));
        piece.push_back({begin.time + t, Vector3d(xy.x(), xy.y(), height), angle, pitch, 0.0});
        // A quarter of the first turn apart, the poses a later turn comes back to.
        if (t < period && i % 6 == 0) {
          landmarks_.push_back(
              {begin.time + t, piece.back().position, piece.back().position + 2.5 * Forward(angle, pitch)});
        }
      }
      Commit(piece, SegmentKind::kRing,
             fmt::format("ring of {:.2f} m, {:.2f} turns of {:.1f} s", radius, turns, period));
      return true;
    }
    return false;
  }

  // Fast roll, pitch and yaw turns with the camera in place, one axis after another (as in TUM fr1_rpy): each a
  // whole number of cycles of a sine, eased in and out over half a cycle.
  static constexpr std::array kAxisNames = {"yaw", "pitch", "roll"};
  static double& Angle(PlannedPose& pose, int axis) {
    return axis == 0 ? pose.yaw : axis == 1 ? pose.pitch : pose.roll;
  }

  bool Rpy() {
    const double total = random_.Uniform(3.0, 8.0);
    const int axes = std::min(random_.UniformInt(1, 3), static_cast<int>(total / 1.5));
    std::vector<int> order = {0, 1, 2};  // yaw, pitch, roll
    Shuffle(random_, order);
    Piece piece;
    PlannedPose base = Last();
    const double stretch = total / axes;
    std::string note;
    for (int a = 0; a < axes; ++a) {
      // Amplitude A and frequency f with a peak rate 2 pi f A of 90-190 degrees a second and a whole number of
      // cycles in the stretch.
      double amplitude = 0.0;
      double frequency = 0.0;
      for (int tries = 0; tries < 20 && frequency == 0.0; ++tries) {
        amplitude = random_.Uniform(15.0, std::min(35.0, 190.0 * stretch / (4.0 * kPi)));
        const double lo = std::max({0.5, 90.0 / (2.0 * kPi * amplitude), 2.0 / stretch});
        const double hi = std::min(1.5, 190.0 / (2.0 * kPi * amplitude));
        const int fewest = std::max(2, static_cast<int>(std::ceil(lo * stretch)));
        const int most = static_cast<int>(std::floor(hi * stretch));
        if (fewest <= most) frequency = random_.UniformInt(fewest, most) / stretch;
      }
      if (frequency == 0.0) return false;
      const int axis = order[static_cast<std::size_t>(a)];
      const int steps = static_cast<int>(std::lround(12.0 * frequency * stretch));
      const double start = base.time + a * stretch;
      for (int i = 1; i <= steps; ++i) {
        const double t = stretch * i / steps;
        const double ease =
            Smoothstep(std::min(1.0, 2.0 * frequency * t)) * Smoothstep(std::min(1.0, 2.0 * frequency * (stretch - t)));
        const double offset = amplitude * ease * std::sin(2.0 * kPi * frequency * t);
        PlannedPose pose = base;
        pose.time = start + t;
        Angle(pose, axis) += offset;
        piece.push_back(pose);
      }
      note += fmt::format("{}{} {:.0f} deg at {:.2f} Hz", note.empty() ? "" : ", ",
                          kAxisNames[static_cast<std::size_t>(axis)], amplitude, frequency);
    }
    if (!Fits(piece)) return false;
    Commit(piece, SegmentKind::kRpy, "fast turns: " + note);
    landmarks_.push_back({Now(), base.position, base.position + 2.0 * Forward(base.yaw, base.pitch)});
    return true;
  }

  // Up to the bare stretch of wall, 0.6-1.2 m from it, and a look at it for 1-3 s.
  bool WallStare() {
    const WallStretch& bare = office_.bare;
    const Vector3d& room = office_.layout.room;
    for (int tries = 0; tries < 6; ++tries) {
      const double at = random_.Uniform(bare.from + 0.9, bare.to - 0.9);
      const double distance = random_.Uniform(0.6, 1.2);
      const double height = random_.Uniform(1.3, 1.6);
      const double pitch = random_.Uniform(-6.0, 4.0);
      const Vector2d on_wall = WallPoint(room, bare.wall, at);
      const Vector2d xy = on_wall + InwardNormal(bare.wall) * distance;
      const Vector3d eye(xy.x(), xy.y(), height);
      const Vector3d target(on_wall.x(), on_wall.y(), height + distance * std::tan(Radians(pitch)));
      auto walk = PlanWalk(Last(), eye, target, random_.Uniform(kSlowestWalk, 0.6), 0.55);
      if (!walk) continue;
      const double look = random_.Uniform(1.0, 3.0);
      PlannedPose stay = walk->piece.back();
      stay.time += look;
      stay.yaw += random_.Uniform(-2.0, 2.0);
      walk->piece.push_back(stay);
      if (!Fits(walk->piece)) continue;
      Commit(walk->piece, SegmentKind::kWall,
             fmt::format("bare {} wall from {:.2f} m for {:.1f} s", ToString(bare.wall), distance, look));
      return true;
    }
    return false;
  }

  // Standing until the end, the view panning slowly.
  void HoldToTheEnd() {
    const double time = duration_ - Now();
    PlannedPose pose = Last();
    pose.time = duration_;
    pose.yaw += std::clamp(random_.Uniform(-20.0, 20.0), -12.0 * time, 12.0 * time);
    Commit({pose}, SegmentKind::kHold, "standing");
  }

  const OfficePlan& office_;
  Random& random_;
  double duration_;
  OfficeLayout routes_;  // the office with the chairs as obstacles
  std::vector<PlannedPose> points_;
  std::vector<Landmark> landmarks_;
  std::vector<CameraSegment> segments_;
};

// ---- People ------------------------------------------------------------------------------------------------------

// The textures the plans are made with: plans never look at them, so the smallest set does.
const TextureSet& PlanningTextures() {
  static const TextureSet textures = [] {
    TextureOptions options;
    options.size = 16;
    options.variants = 1;
    return TextureSet(options);
  }();
  return textures;
}

// A scenario document of `office` and `people`, with a camera that does not matter (for plans alone).
json PlanDocument(const json& office, const json& people) {
  return {{"name", "plan"},
          {"camera", {{"procedural", "static"}, {"frames", 1}, {"position", {1.0, 1.0, 1.5}}, {"yaw_deg", 0.0}}},
          {"office", office},
          {"people", people}};
}

// Where the camera is along its path, sampled.
struct CameraTrack {
  static constexpr double kStep = 0.1;  // seconds
  std::vector<core::Pose> poses;        // at 0, kStep, 2 kStep, ...

  CameraTrack(const WaypointCurve& curve, double duration) {
    const auto count = static_cast<std::size_t>(std::floor(duration / kStep + 1e-9)) + 1;
    for (std::size_t i = 0; i < count; ++i) poses.push_back(curve.At(static_cast<double>(i) * kStep));
  }
  const core::Pose& At(double time) const {
    const auto i =
        static_cast<std::size_t>(std::clamp(std::lround(time / kStep), 0L, static_cast<long>(poses.size()) - 1));
    return poses[i];
  }
  Vector2d Position(double time) const { return At(time).translation().head<2>(); }
  // The view's direction on the level (unit), or zero when the camera looks straight down.
  Vector2d Heading(double time) const {
    const Vector2d forward = At(time).linear().col(2).head<2>();
    return forward.norm() > 1e-6 ? Vector2d(forward.normalized()) : Vector2d::Zero();
  }
  // True when the camera moves slowly at `time`: people can be timed to meet it there.
  bool Steady(double time) const {
    const core::Pose& a = At(time - 0.3);
    const core::Pose& b = At(time + 0.3);
    const double turn = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
    return (b.translation() - a.translation()).norm() < 0.3 && Degrees(turn) < 25.0;
  }
};

class PeoplePlanner {
 public:
  PeoplePlanner(const OfficePlan& office, const CameraTrack& camera, double duration)
      : office_(office), camera_(camera), duration_(duration) {}

  // Up to `count` people, each drawn until its plan works and it keeps clear of the camera (or left out).
  json Draw(Random& random, int count) {
    static constexpr std::array kNames = {"anna", "ben",   "carla", "dan",  "eva",
                                          "femi", "greta", "hiro",  "ines", "jonas"};
    std::vector<std::string> names(kNames.begin(), kNames.end());
    Shuffle(random, names);
    json people = json::array();
    for (int p = 0; p < count; ++p) {
      const std::uint64_t person_seed = random.Next();
      for (std::uint64_t attempt = 0; attempt < 8; ++attempt) {
        Random person_random(FrameSeed(person_seed, attempt, 0));
        Draft draft = DrawPerson(person_random, names[static_cast<std::size_t>(p)]);
        if (KeepsClear(draft.person)) {
          used_.insert(draft.uses.begin(), draft.uses.end());
          put_.insert(put_.end(), draft.put.begin(), draft.put.end());
          people.push_back(std::move(draft.person));
          break;
        }
      }
    }
    return people;
  }

 private:
  // One person as drawn, with what it takes from the office (objects and chairs nobody else may touch, so that
  // everyone's plan is their own) and where it puts things.
  struct Draft {
    json person;
    std::set<std::string> uses;
    std::vector<Vector2d> put;
    Vector2d here = Vector2d::Zero();  // where the person will be after the actions so far
  };

  // The world of this person alone; nullopt when the plan is impossible.
  std::optional<World> Solo(const json& person) const {
    try {
      const Scenario scenario = ParseScenario(PlanDocument(office_.document, json::array({person})).dump(), "plan");
      return World(scenario, PlanningTextures());
    } catch (const core::InputError&) {
      return std::nullopt;
    }
  }

  // True when the person's plan works and the person never comes within kPersonCameraDistance of the camera.
  bool KeepsClear(const json& person) const {
    const auto world = Solo(person);
    if (!world) return false;
    for (std::size_t i = 0; i < camera_.poses.size(); ++i) {
      const double t = static_cast<double>(i) * CameraTrack::kStep;
      const auto pose = world->PersonPose(0, t);
      if (pose && (pose->position - camera_.Position(t)).norm() < kPersonCameraDistance) return false;
    }
    return true;
  }

  bool Unused(const std::string& name, const Draft& draft) const {
    return !used_.contains(name) && !draft.uses.contains(name);
  }

  // A random item of `names` nobody uses yet, or nullptr.
  const std::string* Free(Random& random, const std::vector<std::string>& names, const Draft& draft) const {
    std::vector<const std::string*> free;
    for (const std::string& name : names) {
      if (Unused(name, draft)) free.push_back(&name);
    }
    return free.empty() ? nullptr : Pick(random, free);
  }

  // True when `xy` is `distance` from what stands on the desks and the floor, and from where things are put.
  bool FarFromThings(const Vector2d& xy, double distance, const Draft& draft) const {
    const auto far = [&](const Vector2d& p) { return (p - xy).norm() > distance; };
    return std::all_of(office_.occupied.begin(), office_.occupied.end(),
                       [&](const auto& o) { return (o.first - xy).norm() > o.second + distance; }) &&
           std::all_of(put_.begin(), put_.end(), far) && std::all_of(draft.put.begin(), draft.put.end(), far);
  }

  // A free place for a carried thing: on a desk, or on the floor.
  std::optional<Vector2d> PutSpot(Random& random, const Draft& draft) const {
    for (int tries = 0; tries < 20; ++tries) {
      Vector2d xy;
      if (random.Bernoulli(0.75)) {
        const Desk& desk = Pick(random, office_.layout.desks);
        const double local_y = random.Uniform(-desk.size.y() / 2.0 + 0.15, desk.size.y() / 2.0 - 0.15);
        const Vector2d local(random.Uniform(-desk.size.x() / 2.0 + 0.2, desk.size.x() / 2.0 - 0.2), local_y);
        xy = desk.position + Eigen::Rotation2Dd(Radians(desk.yaw_deg)) * local;
        if (!FarFromThings(xy, 0.18, draft)) continue;
      } else {
        xy = Pick(random, office_.free.people);
        if (!FarFromThings(xy, 0.5, draft) || (xy - office_.door_spot).norm() < 1.0) continue;
      }
      return xy;
    }
    return std::nullopt;
  }

  static json Action(const char* action) { return {{"action", action}}; }

  void Add(Draft& draft, json action) { draft.person["actions"].push_back(std::move(action)); }

  // When the person is done with the actions so far (their plan alone), or nullopt when it fails.
  std::optional<double> DoneAt(const Draft& draft) const {
    const auto world = Solo(draft.person);
    if (!world) return std::nullopt;
    return world->end_time();
  }

  double Speed(const Draft& draft) const { return draft.person.at("speed").get<double>(); }

  // The time to walk from `from` to `to` round the furniture, roughly.
  double WalkTime(const Vector2d& from, const Vector2d& to, double speed) const {
    const auto route = office_.layout.Route(from, to, 0.3);
    if (!route) return std::numeric_limits<double>::infinity();
    double length = 0.0;
    Vector2d at = from;
    for (const Vector2d& next : *route) {
      length += (next - at).norm();
      at = next;
    }
    return length / speed + 0.3 * static_cast<double>(route->size());  // turns at the corners
  }

  bool Walk(Random& random, Draft& draft) {
    const Vector2d to = Pick(random, office_.free.people);
    Add(draft, {{"action", "walk_to"}, {"to", Point(to)}});
    draft.here = to;
    return true;
  }

  // Takes something somewhere else.
  bool Carry(Random& random, Draft& draft) {
    const std::string* object = Free(random, office_.movable, draft);
    const auto spot = PutSpot(random, draft);
    if (object == nullptr || !spot) return false;
    draft.uses.insert(*object);
    draft.put.push_back(*spot);
    Add(draft, {{"action", "pick_up"}, {"object", *object}});
    if (random.Bernoulli(0.4)) Add(draft, {{"action", "carry_to"}, {"to", Point(Pick(random, office_.free.people))}});
    Add(draft, {{"action", "put_down"}, {"to", Point(*spot)}});
    draft.here = *spot;
    return true;
  }

  bool Sit(Random& random, Draft& draft) {
    const std::string* chair = Free(random, office_.chairs, draft);
    if (chair == nullptr) return false;
    draft.uses.insert(*chair);
    Add(draft, {{"action", "sit_on"},
                {"object", *chair},
                {"duration", Rounded(random.Uniform(2.0, 8.0), 1)},
                {"gesture", random.Bernoulli(0.5)}});
    draft.here = office_.layout.FindObject(*chair)->position;
    return true;
  }

  // Pushes a chair ahead to a free place, off the camera's way.
  bool Push(Random& random, Draft& draft) {
    const std::string* name = Free(random, office_.chairs, draft);
    if (name == nullptr) return false;
    const OfficeObject& chair = *office_.layout.FindObject(*name);
    const Vector2d ahead = Direction(Radians(chair.yaw_deg));
    const Vector2d side(-ahead.y(), ahead.x());
    const double sideways = random.Uniform(-0.3, 0.3);
    const Vector2d to = chair.position + ahead * random.Uniform(0.5, 1.2) + side * sideways;
    const bool free =
        office_.floor->Clear(to, 0.45, 0.0) && office_.floor->Clear(chair.position - ahead * 0.62, 0.3, 0.0);
    const bool apart =
        std::all_of(office_.layout.objects.begin(), office_.layout.objects.end(), [&](const OfficeObject& o) {
          return o.name == chair.name || o.kind != ObjectKind::kChair || (o.position - to).norm() > 0.8;
        });
    const bool off_the_way = std::all_of(camera_.poses.begin(), camera_.poses.end(), [&](const core::Pose& pose) {
      return (pose.translation().head<2>() - to).norm() > kChairRadius + kRandomCameraClearance + 0.1;
    });
    if (!free || !apart || !off_the_way || !FarFromThings(to, 0.5, draft)) return false;
    draft.uses.insert(*name);
    draft.put.push_back(to);
    Add(draft, {{"action", "push"}, {"object", *name}, {"to", Point(to)}});
    draft.here = to - ahead * 0.62;
    return true;
  }

  // Stands in front of a monitor, a laptop or a shelf, looking at it.
  bool StandAt(Random& random, Draft& draft) {
    const std::string* name = Free(random, office_.watchable, draft);
    if (name == nullptr) return false;
    const OfficeObject& object = *office_.layout.FindObject(*name);
    const Vector2d spot = object.position + Direction(Radians(object.yaw_deg)) * random.Uniform(0.8, 1.3);
    if (!office_.free.Reaches(spot)) return false;
    draft.uses.insert(*name);
    Add(draft, {{"action", "stand_at"},
                {"object", *name},
                {"duration", Rounded(random.Uniform(1.5, 4.0), 1)},
                {"position", Point(spot)}});
    draft.here = spot;
    return true;
  }

  bool Gesture(Random& random, Draft& draft) {
    Add(draft, {{"action", "gesture"}, {"duration", Rounded(random.Uniform(1.0, 3.0), 1)}});
    return true;
  }

  // Comes up to the camera, 1-1.8 m in front of it, faces it and talks to it.
  bool Talk(Random& random, Draft& draft) {
    const auto done = DoneAt(draft);
    if (!done) return false;
    double when = *done + random.Uniform(2.0, 8.0);
    for (int tries = 0; tries < 3 && when < duration_ - 3.0; ++tries) {
      const Vector2d heading = camera_.Heading(when);
      const Vector2d spot = camera_.Position(when) + heading * random.Uniform(1.0, 1.8);
      const double arrive = *done + WalkTime(draft.here, spot, Speed(draft));
      if (heading.isZero() || !office_.free.Reaches(spot) || arrive > when) {
        when = std::max(when, arrive) + 0.5;
        continue;
      }
      Add(draft, {{"action", "walk_to"}, {"to", Point(spot)}});
      Add(draft, {{"action", "face"}, {"at", Rounded(when, 2)}, {"to", Point(camera_.Position(when + 0.5))}});
      Add(draft, {{"action", "gesture"}, {"duration", Rounded(random.Uniform(1.5, 3.0), 1)}});
      draft.here = spot;
      return true;
    }
    return false;
  }

  // Walks across the view 0.8-1.4 m in front of the camera while it moves slowly, timed to pass it then.
  bool Pass(Random& random, Draft& draft) {
    const auto done = DoneAt(draft);
    if (!done) return false;
    for (int tries = 0; tries < 8; ++tries) {
      const double when = random.Uniform(*done + 4.0, std::max(*done + 4.0, std::min(duration_ - 1.0, *done + 30.0)));
      if (when > duration_ - 1.0 || !camera_.Steady(when)) continue;
      const Vector2d heading = camera_.Heading(when);
      if (heading.isZero()) continue;
      const Vector2d middle = camera_.Position(when) + heading * random.Uniform(0.8, 1.4);
      const Vector2d side = Vector2d(-heading.y(), heading.x()) * (random.Bernoulli(0.5) ? 1.4 : -1.4);
      const Vector2d from = middle - side;
      const Vector2d to = middle + side;
      if (!office_.free.Reaches(from) || !office_.free.Reaches(to) || !office_.free.Reaches(middle)) continue;
      const auto straight = office_.layout.Route(from, to, 0.3);
      if (!straight || straight->size() != 1) continue;
      const double speed = Speed(draft);
      const double start = when - side.norm() / speed - 0.6;  // the turn towards `to` first
      if (*done + WalkTime(draft.here, from, speed) > start - 0.5) continue;
      Add(draft, {{"action", "walk_to"}, {"to", Point(from)}});
      Add(draft, {{"action", "walk_to"}, {"at", Rounded(start, 2)}, {"to", Point(to)}});
      draft.here = to;
      return true;
    }
    return false;
  }

  Draft DrawPerson(Random& random, const std::string& name) {
    static constexpr std::array<std::array<double, 3>, 5> kSkins = {
        {{0.8, 0.88, 1.0}, {0.55, 0.65, 0.8}, {0.7, 0.8, 0.95}, {0.4, 0.5, 0.65}, {0.85, 0.92, 1.05}}};
    static constexpr std::array<std::array<double, 3>, 5> kHair = {
        {{0.4, 0.45, 0.5}, {0.2, 0.2, 0.25}, {0.3, 0.45, 0.6}, {0.6, 0.6, 0.62}, {0.25, 0.35, 0.5}}};
    Draft draft;
    json& person = draft.person;
    person["name"] = name;
    person["height"] = Rounded(random.Uniform(1.55, 1.95), 2);
    person["shirt"] = random.UniformInt(0, 7);
    person["trousers"] = random.UniformInt(0, 7);
    person["skin"] = kSkins[static_cast<std::size_t>(random.UniformInt(0, 4))];
    person["hair"] = kHair[static_cast<std::size_t>(random.UniformInt(0, 4))];
    person["speed"] = Rounded(random.Uniform(0.8, 1.3), 2);
    person["actions"] = json::array();
    if (random.Bernoulli(0.5)) {
      // In the room from the start, not too near the camera.
      Vector2d start = Pick(random, office_.free.people);
      for (int tries = 0; tries < 10 && (start - camera_.Position(0.0)).norm() < 1.5; ++tries) {
        start = Pick(random, office_.free.people);
      }
      person["start"] = Point(start);
      person["facing_deg"] = Rounded(random.Uniform(-180.0, 180.0), 1);
      draft.here = start;
    } else {
      // Comes in by the door later.
      person["start"] = Point(office_.door_spot);
      person["facing_deg"] = Rounded(office_.door_inward_deg, 1);
      person["enter_at"] = Rounded(random.Uniform(1.0, 0.6 * duration_), 2);
      draft.here = office_.door_spot;
    }
    using Activity = bool (PeoplePlanner::*)(Random&, Draft&);
    static constexpr std::array<std::pair<Activity, double>, 8> kActivities = {{
        {&PeoplePlanner::Walk, 1.5},
        {&PeoplePlanner::Carry, 3.0},
        {&PeoplePlanner::Sit, 1.5},
        {&PeoplePlanner::Push, 1.0},
        {&PeoplePlanner::StandAt, 1.5},
        {&PeoplePlanner::Gesture, 0.7},
        {&PeoplePlanner::Talk, 1.2},
        {&PeoplePlanner::Pass, 1.8},
    }};
    double total = 0.0;
    for (const auto& [activity, weight] : kActivities) total += weight;
    // 2-6 things done; one that finds nothing to do (no chair left, no time to meet the camera) is drawn again.
    const int count = random.UniformInt(2, 6);
    for (int done = 0, tries = 0; done < count && tries < 3 * count; ++tries) {
      double pick = random.Uniform(0.0, total);
      for (const auto& [activity, weight] : kActivities) {
        pick -= weight;
        if (pick < 0.0) {
          done += (this->*activity)(random, draft) ? 1 : 0;
          break;
        }
      }
    }
    if (random.Bernoulli(0.35)) Add(draft, {{"action", "leave"}, {"to", Point(office_.door_spot)}});
    return draft;
  }

  const OfficePlan& office_;
  const CameraTrack& camera_;
  double duration_;
  std::set<std::string> used_;  // objects and chairs someone uses
  std::vector<Vector2d> put_;   // where someone puts something
};

// ---- The scenario ------------------------------------------------------------------------------------------------

// A covered lens and a dark moment, each in some sequences, never at the same time.
void DrawMoments(Random& random, double duration, json& document, std::string& description) {
  if (duration < 15.0) return;
  std::optional<std::pair<double, double>> covered;
  if (random.Bernoulli(0.45)) {
    const double length = Rounded(random.Uniform(1.0, 3.0), 2);
    const double from = Rounded(random.Uniform(6.0, duration - length - 3.0), 2);
    covered.emplace(from, from + length);
    document["covered"] = json::array({{{"from", from}, {"for", length}}});
    description += fmt::format("; lens covered {:.1f}-{:.1f} s", from, from + length);
  }
  if (random.Bernoulli(0.45)) {
    for (int tries = 0; tries < 10; ++tries) {
      const double length = Rounded(random.Uniform(1.0, 3.0), 2);
      const double from = Rounded(random.Uniform(6.0, duration - length - 3.0), 2);
      const double level = Rounded(random.Uniform(0.05, 0.3), 2);
      if (covered && from < covered->second + 1.0 && covered->first < from + length + 1.0) continue;
      document["dark"] = json::array({{{"from", from}, {"for", length}, {"level", level}}});
      description += fmt::format("; dark {:.1f}-{:.1f} s (light {:.0f} %)", from, from + length, 100.0 * level);
      break;
    }
  }
}

std::string_view SegmentName(SegmentKind kind) {
  switch (kind) {
    case SegmentKind::kWalk:
      return "walk";
    case SegmentKind::kReturn:
      return "return";
    case SegmentKind::kRing:
      return "ring";
    case SegmentKind::kRpy:
      return "rpy";
    case SegmentKind::kWall:
      return "wall";
    case SegmentKind::kHold:
      break;
  }
  return "hold";
}

// True when the camera path keeps the bounds every random path is held to (random_scenario.h).
bool CameraKeepsItsBounds(const Scenario& scenario, const CameraPath& path) {
  const OfficeLayout& office = scenario.office;
  const FloorPlan floor(office);
  const double fps = scenario.camera.procedural.fps;
  const auto& frames = path.frames();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const Vector3d p = frames[i].T_wc.translation();
    const Vector2d xy = p.head<2>();
    if (!floor.Clear(xy, kRandomCameraClearance, kChairRadius + kRandomCameraClearance)) return false;
    if (p.z() < kRandomCameraClearance || p.z() > office.room.z() - kRandomCameraClearance) return false;
    if (i == 0) continue;
    const core::Pose& before = frames[i - 1].T_wc;
    if ((p - before.translation()).norm() * fps > kRandomCameraMaxSpeed) return false;
    const double turn = Eigen::AngleAxisd(before.linear().transpose() * frames[i].T_wc.linear()).angle();
    if (Degrees(turn) * fps > kRandomCameraMaxTurnRate) return false;
  }
  return true;
}

// True when the plans of everyone together keep them clear of the camera.
bool PeopleKeepClear(const Scenario& scenario, const World& world, const CameraPath& path) {
  const auto& frames = path.frames();
  for (std::size_t i = 0; i < frames.size(); i += 3) {
    const double t = frames[i].timestamp - frames.front().timestamp;
    for (std::size_t p = 0; p < scenario.people.size(); ++p) {
      const auto pose = world.PersonPose(p, t);
      if (pose && (pose->position - frames[i].T_wc.translation().head<2>()).norm() < kPersonCameraDistance) {
        return false;
      }
    }
  }
  return true;
}

// One draw of the scenario of `seed`; nullopt when it fails a check.
std::optional<json> Draw(std::uint64_t seed, std::uint64_t draw, const RandomScenarioOptions& options) {
  const std::string name = RandomScenarioName(seed);
  Random office_random(FrameSeed(seed, draw, kOfficeStream));
  const auto office = OfficeDrawer(office_random).Draw();
  if (!office) return std::nullopt;

  Random camera_random(FrameSeed(seed, draw, kCameraStream));
  CameraPlanner planner(*office, camera_random, options.duration);
  const std::vector<PlannedPose> points = planner.Plan();
  std::vector<CameraWaypoint> waypoints;
  json waypoint_list = json::array();
  for (const PlannedPose& p : points) {
    waypoints.push_back({p.time, p.position, p.yaw, p.pitch, p.roll});
    // Yaw and roll are written within a half turn; the reader unwraps them again (each turns the shorter way).
    waypoint_list.push_back({{"time", Rounded(p.time, 3)},
                             {"position", Point(p.position)},
                             {"yaw_deg", Rounded(std::remainder(p.yaw, 360.0), 2)},
                             {"pitch_deg", Rounded(p.pitch, 2)},
                             {"roll_deg", Rounded(std::remainder(p.roll, 360.0), 2)}});
  }
  json camera = {{"procedural", "waypoints"},
                 {"fps", kFps},
                 {"wobble", Rounded(camera_random.Uniform(0.01, 0.03), 3)},
                 {"wobble_angle_deg", Rounded(camera_random.Uniform(0.5, 1.5), 2)},
                 {"wobble_seed", camera_random.UniformInt(1, 1000000)},
                 {"waypoints", std::move(waypoint_list)}};

  const OfficeLayout& layout = office->layout;
  std::string description = fmt::format(
      "Random scenario {} (hoidslam synth --random {}): an office of {:.2f} x {:.2f} x {:.2f} m with {}, {} and {}; "
      "the camera: ",
      seed, seed, layout.room.x(), layout.room.y(), layout.room.z(), Count(layout.desks.size(), "desk", "desks"),
      Count(layout.shelves.size(), "shelf", "shelves"), Count(layout.objects.size(), "object", "objects"));
  for (std::size_t i = 0; const CameraSegment& segment : planner.segments()) {
    description += fmt::format("{}{:.1f}-{:.1f} s {} ({})", i++ == 0 ? "" : ", ", segment.from, segment.to,
                               SegmentName(segment.kind), segment.note);
  }
  json document = {{"name", name}, {"seed", seed}, {"camera", std::move(camera)}, {"office", office->document}};
  Random moment_random(FrameSeed(seed, draw, kMomentStream));
  DrawMoments(moment_random, options.duration, document, description);

  Random people_random(FrameSeed(seed, draw, kPeopleStream));
  // 0 to 4 people, 2 most often.
  const double pick = people_random.Uniform();
  const int count = pick < 0.12 ? 0 : pick < 0.32 ? 1 : pick < 0.6 ? 2 : pick < 0.84 ? 3 : 4;
  const CameraTrack track(WaypointCurve(waypoints), options.duration);
  document["people"] = PeoplePlanner(*office, track, options.duration).Draw(people_random, count);
  description += "; " + Count(document["people"].size(), "person", "people");
  document["description"] = description;

  // The checks of `--scenario`: the file parses, the people's plans work, the camera path is built; and the bounds
  // of a random camera.
  try {
    const Scenario scenario = ParseScenario(document.dump(), name);
    const World world(scenario, PlanningTextures());
    const CameraPath path = CameraPath::Procedural(scenario.camera.procedural);
    if (!CameraKeepsItsBounds(scenario, path) || !PeopleKeepClear(scenario, world, path)) return std::nullopt;
  } catch (const core::InputError&) {
    return std::nullopt;
  }
  return document;
}

}  // namespace

void RandomScenarioOptions::Check() const {
  if (!(duration >= 10.0 && duration <= 3600.0)) {
    throw core::InputError::ForParameter("--random-duration",
                                         fmt::format("must be in [10, 3600] seconds, got {}", duration));
  }
}

std::string RandomScenarioName(std::uint64_t seed) { return fmt::format("random-{}", seed); }

json RandomScenarioDocument(std::uint64_t seed, const RandomScenarioOptions& options) {
  options.Check();
  for (std::uint64_t draw = 0; draw < kMaxDraws; ++draw) {
    if (auto document = Draw(seed, draw, options)) return std::move(*document);
  }
  throw core::Error(fmt::format("random scenario {}: no draw passed its checks in {} draws", seed, kMaxDraws));
}

Scenario RandomScenario(std::uint64_t seed, const RandomScenarioOptions& options) {
  return ParseScenario(RandomScenarioDocument(seed, options).dump(), RandomScenarioName(seed));
}

}  // namespace hoidslam::synth
