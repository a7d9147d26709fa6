#include "hoidslam/synth/office.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "hoidslam/core/enum_names.h"
#include "hoidslam/core/error.h"
#include "hoidslam/synth/random.h"

namespace hoidslam::synth {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr core::EnumNames<ObjectKind, 8> kKindNames = {{
    {ObjectKind::kTv, "tv"},
    {ObjectKind::kKeyboard, "keyboard"},
    {ObjectKind::kMouse, "mouse"},
    {ObjectKind::kLaptop, "laptop"},
    {ObjectKind::kBook, "book"},
    {ObjectKind::kCup, "cup"},
    {ObjectKind::kBottle, "bottle"},
    {ObjectKind::kChair, "chair"},
}};

constexpr core::EnumNames<Wall, 4> kWallNames = {{
    {Wall::kFront, "front"},
    {Wall::kRight, "right"},
    {Wall::kBack, "back"},
    {Wall::kLeft, "left"},
}};

constexpr core::EnumNames<PanelKind, 3> kPanelNames = {{
    {PanelKind::kPoster, "poster"},
    {PanelKind::kWhiteboard, "whiteboard"},
    {PanelKind::kDoor, "door"},
}};

// The whiteboard is a bright generic texture, the door tinted wood.
const cv::Vec3f kWhiteboardTint = {1.1F, 1.1F, 1.1F};
const cv::Vec3f kDoorTint = {0.6F, 0.7F, 0.8F};
int WhiteboardTexture(const TextureSet& textures) { return textures.Index(TextureRole::kGeneric, 1); }
int DoorTexture(const TextureSet& textures) { return textures.Index(TextureRole::kDesk); }

struct KindInfo {
  ObjectKind kind;
  int coco_id;
  Vector3d half_extents;
  bool two_handed;
};

constexpr double kDeg = std::numbers::pi / 180.0;

// Indexed by ObjectKind.
const std::array<KindInfo, 8>& Kinds() {
  static const std::array<KindInfo, 8> kinds = {{
      {ObjectKind::kTv, 62, {0.12, 0.30, 0.28}, true},
      {ObjectKind::kKeyboard, 66, {0.075, 0.22, 0.012}, true},
      {ObjectKind::kMouse, 64, {0.05, 0.03, 0.018}, false},
      {ObjectKind::kLaptop, 63, {0.155, 0.165, 0.121}, true},
      {ObjectKind::kBook, 73, {0.12, 0.085, 0.02}, true},
      {ObjectKind::kCup, 41, {0.04, 0.058, 0.05}, false},
      {ObjectKind::kBottle, 39, {0.035, 0.035, 0.135}, false},
      {ObjectKind::kChair, 56, {0.235, 0.23, 0.475}, true},
  }};
  return kinds;
}

const KindInfo& Info(ObjectKind kind) { return Kinds()[static_cast<std::size_t>(kind)]; }

core::Pose PoseAt(const Vector3d& t, double yaw_rad = 0.0) {
  core::Pose pose = core::Pose::Identity();
  pose.translate(t);
  pose.rotate(Eigen::AngleAxisd(yaw_rad, Vector3d::UnitZ()));
  return pose;
}

Box MakeBox(const core::Pose& T_wb, const Vector3d& half, int texture, double scale,
            cv::Vec3f tint = {1.0F, 1.0F, 1.0F}) {
  return Box{T_wb, half, texture, scale, tint};
}

// (x, y) in the frame of a rectangle centred at `centre` and turned by `yaw_rad`.
Vector2d ToLocal(const Vector2d& xy, const Vector2d& centre, double yaw_rad) {
  const Vector2d d = xy - centre;
  return {std::cos(yaw_rad) * d.x() + std::sin(yaw_rad) * d.y(),
          -std::sin(yaw_rad) * d.x() + std::cos(yaw_rad) * d.y()};
}

// A furniture footprint: a rectangle centred at `centre`, turned by `yaw` radians, with half sides `half`.
struct Footprint {
  Vector2d centre;
  double yaw = 0.0;
  Vector2d half;

  bool Contains(const Vector2d& xy, double margin) const {
    const Vector2d local = ToLocal(xy, centre, yaw);
    return std::abs(local.x()) <= half.x() + margin && std::abs(local.y()) <= half.y() + margin;
  }

  // True when the segment a-b passes through the footprint grown by `margin` (slab test in its frame).
  bool Crosses(const Vector2d& a, const Vector2d& b, double margin) const {
    const Vector2d p = ToLocal(a, centre, yaw);
    const Vector2d d = ToLocal(b, centre, yaw) - p;
    double t0 = 0.0;
    double t1 = 1.0;
    for (int axis = 0; axis < 2; ++axis) {
      const double extent = half[axis] + margin;
      if (std::abs(d[axis]) < 1e-12) {
        if (std::abs(p[axis]) > extent) return false;
        continue;
      }
      double enter = (-extent - p[axis]) / d[axis];
      double leave = (extent - p[axis]) / d[axis];
      if (enter > leave) std::swap(enter, leave);
      t0 = std::max(t0, enter);
      t1 = std::min(t1, leave);
      if (t0 > t1) return false;
    }
    return true;
  }

  std::array<Vector2d, 4> Corners(double margin) const {
    std::array<Vector2d, 4> corners;
    const Eigen::Rotation2Dd rotation(yaw);
    for (int i = 0; i < 4; ++i) {
      const Vector2d local((i & 1 ? 1 : -1) * (half.x() + margin), (i & 2 ? 1 : -1) * (half.y() + margin));
      corners[static_cast<std::size_t>(i)] = centre + rotation * local;
    }
    return corners;
  }
};

std::vector<Footprint> DeskFootprints(const OfficeLayout& office) {
  std::vector<Footprint> footprints;
  for (const Desk& desk : office.desks) footprints.push_back({desk.position, desk.yaw_deg * kDeg, desk.size / 2.0});
  return footprints;
}

// Desks and shelves: where nobody walks.
std::vector<Footprint> Obstacles(const OfficeLayout& office) {
  std::vector<Footprint> footprints = DeskFootprints(office);
  for (const Shelf& shelf : office.shelves) {
    footprints.push_back({shelf.position, shelf.yaw_deg * kDeg, Vector2d(shelf.size.y() / 2.0, shelf.size.x() / 2.0)});
  }
  return footprints;
}

void AddDesk(const Desk& desk, const TextureSet& textures, std::vector<Box>& parts) {
  const double yaw = desk.yaw_deg * kDeg;
  const core::Pose T_wd = PoseAt({desk.position.x(), desk.position.y(), 0.0}, yaw);
  const double hx = desk.size.x() / 2.0;
  const double hy = desk.size.y() / 2.0;
  const double top = 0.015;
  parts.push_back(
      MakeBox(T_wd * PoseAt({0, 0, desk.height - top}), {hx, hy, top}, textures.Index(TextureRole::kDesk), 0.8));
  const int metal = textures.Index(TextureRole::kMonitorBody);
  const double leg_half = (desk.height - 2 * top) / 2.0;
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      parts.push_back(
          MakeBox(T_wd * PoseAt({sx * (hx - 0.05), sy * (hy - 0.05), leg_half}), {0.025, 0.025, leg_half}, metal, 0.5));
    }
  }
  // A modesty panel at the back gives the space under the desk some texture.
  parts.push_back(MakeBox(T_wd * PoseAt({0, hy - 0.06, desk.height - 0.3}), {hx - 0.08, 0.01, 0.25},
                          textures.Index(TextureRole::kDesk), 0.8, {0.8F, 0.85F, 0.9F}));
}

void AddShelf(const Shelf& shelf, const TextureSet& textures, std::vector<Box>& parts) {
  // Local frame: open side faces +x, width along y.
  const core::Pose T_ws = PoseAt({shelf.position.x(), shelf.position.y(), 0.0}, shelf.yaw_deg * kDeg);
  const double hw = shelf.size.x() / 2.0;
  const double hd = shelf.size.y() / 2.0;
  const double h = shelf.size.z();
  const int wood = textures.Index(TextureRole::kDesk);
  const cv::Vec3f tint = {0.75F, 0.8F, 0.85F};
  for (const double s : {-1.0, 1.0}) {
    parts.push_back(MakeBox(T_ws * PoseAt({0, s * (hw - 0.01), h / 2}), {hd, 0.01, h / 2}, wood, 0.8, tint));
  }
  parts.push_back(MakeBox(T_ws * PoseAt({-hd + 0.005, 0, h / 2}), {0.005, hw - 0.02, h / 2},
                          textures.Index(TextureRole::kGeneric, 2), 0.6));
  for (int i = 0; i < shelf.boards; ++i) {
    const double z = 0.02 + (h - 0.04) * i / (shelf.boards - 1);
    parts.push_back(MakeBox(T_ws * PoseAt({0, 0, z}), {hd, hw - 0.02, 0.02}, wood, 0.8, tint));
  }
}

// A thin panel on the inside of a wall: `wall` 0..3 = y = 0, x = room.x, y = room.y, x = 0 (the order of Wall);
// `along` is the distance from the wall's first corner going counter-clockwise round the room (seen from above);
// `z` is the panel centre height.
Box PanelBox(const OfficeLayout& layout, int wall, double along, double z, double width, double height, int texture,
              cv::Vec3f tint = {1.0F, 1.0F, 1.0F}) {
  const Vector3d& room = layout.room;
  const double depth = 0.01;
  // Inward normal directions and starting corners of the four walls, going round the room.
  const std::array<Vector2d, 4> corners = {Vector2d{0, 0}, Vector2d{room.x(), 0}, Vector2d{room.x(), room.y()},
                                           Vector2d{0, room.y()}};
  const std::array<double, 4> inward_yaw = {90 * kDeg, 180 * kDeg, -90 * kDeg, 0.0};
  const double yaw = inward_yaw[static_cast<std::size_t>(wall)];
  const Vector2d normal(std::cos(yaw), std::sin(yaw));
  const Vector2d along_dir(normal.y(), -normal.x());  // counter-clockwise round the room
  const Vector2d start = corners[static_cast<std::size_t>(wall)];
  const Vector2d centre = start + along_dir * along + normal * depth;
  // Panels are textured once across their width: the texture scale is the panel width.
  return MakeBox(PoseAt({centre.x(), centre.y(), z}, yaw), {depth, width / 2, height / 2}, texture,
                 std::max(width, height), tint);
}

// The box of a panel of the layout's own list.
Box PanelOnWall(const OfficeLayout& layout, const WallPanel& panel, const TextureSet& textures) {
  // PanelBox measures along the walls counter-clockwise: the back and left walls run against x and y.
  const double along =
      panel.wall == Wall::kBack || panel.wall == Wall::kLeft ? WallLength(layout.room, panel.wall) - panel.at : panel.at;
  const int wall = static_cast<int>(panel.wall);
  switch (panel.kind) {
    case PanelKind::kWhiteboard:
      return PanelBox(layout, wall, along, panel.z, panel.size.x(), panel.size.y(), WhiteboardTexture(textures),
                      kWhiteboardTint);
    case PanelKind::kDoor:
      return PanelBox(layout, wall, along, panel.z, panel.size.x(), panel.size.y(), DoorTexture(textures), kDoorTint);
    case PanelKind::kPoster:
      break;
  }
  return PanelBox(layout, wall, along, panel.z, panel.size.x(), panel.size.y(),
                  textures.Index(TextureRole::kPoster, panel.variant));
}

// Cuts [0, length) into pieces `min` to `max` long (the last one between `min` and `max` + `min`).
std::vector<double> Cuts(double length, double min, double max, Random& random) {
  std::vector<double> cuts = {0.0};
  while (length - cuts.back() >= max + min) {
    const double piece = random.Uniform(min, max);
    cuts.push_back(cuts.back() + piece);
  }
  cuts.push_back(length);
  return cuts;
}

// The four walls as a patchwork (OfficeLayout::patchwork_walls_seed): boxes `thickness` deep behind the wall
// planes, each textured once across its larger side.
std::vector<Box> PatchworkWalls(const Vector3d& room, double thickness, std::uint64_t seed,
                                const TextureSet& textures) {
  Random random(seed);
  const int photos = textures.VariantCount(TextureRole::kPoster);
  std::vector<Box> pieces;
  for (const Wall wall : {Wall::kFront, Wall::kRight, Wall::kBack, Wall::kLeft}) {
    const Vector2d normal = InwardNormal(wall);
    const double yaw = std::atan2(normal.y(), normal.x());
    const std::vector<double> columns = Cuts(WallLength(room, wall), 0.8, 1.6, random);
    std::vector<int> previous_column;  // the variants of the column to the left, bottom up
    for (std::size_t c = 0; c + 1 < columns.size(); ++c) {
      const std::vector<double> rows = Cuts(room.z(), 0.7, 1.4, random);
      const double from = columns[c];
      const double width = columns[c + 1] - from;
      std::vector<int> column;
      for (std::size_t r = 0; r + 1 < rows.size(); ++r) {
        const int left = r < previous_column.size() ? previous_column[r] : -1;
        const int below = column.empty() ? -1 : column.back();
        int variant = random.UniformInt(0, photos - 1);
        // Never the texture of a neighbour (with fewer than three textures that cannot always be kept).
        for (int step = 0; step < photos && (variant == left || variant == below); ++step) {
          variant = (variant + 1) % photos;
        }
        const double height = rows[r + 1] - rows[r];
        const Vector2d centre = WallPoint(room, wall, from + width / 2) - normal * (thickness / 2);
        const auto shade = static_cast<float>(random.Uniform(0.85, 1.05));
        pieces.push_back(MakeBox(PoseAt({centre.x(), centre.y(), rows[r] + height / 2}, yaw),
                                 {thickness / 2, width / 2, height / 2}, textures.Index(TextureRole::kPoster, variant),
                                 std::max(width, height), {shade, shade, shade}));
        column.push_back(variant);
      }
      previous_column = std::move(column);
    }
  }
  return pieces;
}

OfficeObject Obj(std::string name, ObjectKind kind, Vector2d xy, double yaw_deg, int variant = 0,
                 std::optional<double> z = std::nullopt) {
  return OfficeObject{std::move(name), kind, xy, z, yaw_deg, variant};
}

}  // namespace

std::string_view CocoLabel(ObjectKind kind) { return core::EnumName(kKindNames, kind); }

ObjectKind ParseObjectKind(std::string_view label, const std::string& parameter) {
  return core::ParseEnumName(kKindNames, label, parameter, "object type");
}

std::string_view ToString(Wall wall) { return core::EnumName(kWallNames, wall); }

double WallLength(const Vector3d& room, Wall wall) {
  return wall == Wall::kFront || wall == Wall::kBack ? room.x() : room.y();
}

Vector2d WallPoint(const Vector3d& room, Wall wall, double at) {
  switch (wall) {
    case Wall::kFront:
      return {at, 0.0};
    case Wall::kRight:
      return {room.x(), at};
    case Wall::kBack:
      return {at, room.y()};
    case Wall::kLeft:
      break;
  }
  return {0.0, at};
}

Vector2d InwardNormal(Wall wall) {
  switch (wall) {
    case Wall::kFront:
      return {0.0, 1.0};
    case Wall::kRight:
      return {-1.0, 0.0};
    case Wall::kBack:
      return {0.0, -1.0};
    case Wall::kLeft:
      break;
  }
  return {1.0, 0.0};
}

Wall ParseWall(std::string_view name, const std::string& parameter) {
  return core::ParseEnumName(kWallNames, name, parameter, "wall");
}

std::string_view ToString(PanelKind kind) { return core::EnumName(kPanelNames, kind); }

PanelKind ParsePanelKind(std::string_view name, const std::string& parameter) {
  return core::ParseEnumName(kPanelNames, name, parameter, "panel type");
}

Eigen::Vector2d DefaultPanelSize(PanelKind kind) {
  switch (kind) {
    case PanelKind::kWhiteboard:
      return {1.6, 1.0};
    case PanelKind::kDoor:
      return {0.95, 2.1};
    case PanelKind::kPoster:
      break;
  }
  return {0.7, 0.9};
}

int CocoClassId(std::string_view label) {
  if (label == "person") return 0;
  for (const auto& [kind, name] : kKindNames) {
    if (name == label) return Info(kind).coco_id;
  }
  return -1;
}

Eigen::Vector3d ObjectHalfExtents(ObjectKind kind) { return Info(kind).half_extents; }
bool IsTwoHanded(ObjectKind kind) { return Info(kind).two_handed; }

double OfficeLayout::SupportHeightAt(const Vector2d& xy) const {
  for (std::size_t i = 0; const Footprint& footprint : DeskFootprints(*this)) {
    if (footprint.Contains(xy, 0.0)) return desks[i].height;
    ++i;
  }
  return 0.0;
}

bool OfficeLayout::IsBlocked(const Vector2d& xy, double margin) const {
  const std::vector<Footprint> obstacles = Obstacles(*this);
  return std::any_of(obstacles.begin(), obstacles.end(), [&](const Footprint& f) { return f.Contains(xy, margin); });
}

std::optional<std::vector<Vector2d>> OfficeLayout::Route(const Vector2d& from, const Vector2d& to,
                                                         double clearance) const {
  // Footprints that an end of the route is too close to keep only a token margin, so that the route can reach
  // that end but still never cuts through the furniture.
  constexpr double kTokenMargin = 0.02;
  std::vector<std::pair<Footprint, double>> obstacles;
  for (const Footprint& f : Obstacles(*this)) {
    const bool near_end = f.Contains(from, clearance) || f.Contains(to, clearance);
    obstacles.emplace_back(f, near_end ? kTokenMargin : clearance);
  }
  auto clear = [&](const Vector2d& a, const Vector2d& b) {
    return std::none_of(obstacles.begin(), obstacles.end(),
                        [&](const auto& obstacle) { return obstacle.first.Crosses(a, b, obstacle.second); });
  };
  if (clear(from, to)) return std::vector<Vector2d>{to};
  // Shortest path over a visibility graph: node 0 = from, node 1 = to, then the free grown corners.
  std::vector<Vector2d> nodes = {from, to};
  for (const auto& [f, margin] : obstacles) {
    for (const Vector2d& corner : f.Corners(margin + 0.05)) {
      const bool inside_room =
          corner.x() > 0.2 && corner.y() > 0.2 && corner.x() < room.x() - 0.2 && corner.y() < room.y() - 0.2;
      if (inside_room && !IsBlocked(corner, kTokenMargin)) nodes.push_back(corner);
    }
  }
  const std::size_t n = nodes.size();
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<std::size_t> previous(n, n);
  std::vector<bool> done(n, false);
  distance[0] = 0.0;
  for (;;) {
    std::size_t best = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (!done[i] && distance[i] < std::numeric_limits<double>::infinity() &&
          (best == n || distance[i] < distance[best])) {
        best = i;
      }
    }
    if (best == n || best == 1) break;
    done[best] = true;
    for (std::size_t i = 0; i < n; ++i) {
      if (done[i] || !clear(nodes[best], nodes[i])) continue;
      const double d = distance[best] + (nodes[i] - nodes[best]).norm();
      if (d < distance[i]) {
        distance[i] = d;
        previous[i] = best;
      }
    }
  }
  if (previous[1] == n) return std::nullopt;
  std::vector<Vector2d> route;
  for (std::size_t i = 1; i != 0; i = previous[i]) route.push_back(nodes[i]);
  std::reverse(route.begin(), route.end());
  return route;
}

const OfficeObject* OfficeLayout::FindObject(std::string_view name) const {
  for (const OfficeObject& object : objects) {
    if (object.name == name) return &object;
  }
  return nullptr;
}

core::Pose OfficeLayout::RestPose(const OfficeObject& object) const {
  const double z = object.z.value_or(SupportHeightAt(object.position));
  return PoseAt({object.position.x(), object.position.y(), z}, object.yaw_deg * kDeg);
}

void OfficeLayout::Check(const std::string& source, const std::string& key, const OfficeLayout& base) const {
  auto fail = [&](const std::string& where, const std::string& what) {
    throw core::InputError::InFile(source, fmt::format("{}.{}: {}", key, where, what));
  };
  if ((room.array() <= 1.0).any()) fail("room", "every room side must be more than 1 m");
  auto inside = [&](const Vector2d& xy) {
    return xy.x() > 0.0 && xy.y() > 0.0 && xy.x() < room.x() && xy.y() < room.y();
  };
  // Entry i of a list: the first `base_count` come from the base layout, which is valid in its own room, so
  // they can only go wrong in a smaller room (the fault of "room"); the user's own entries are named by their
  // index in the user's array.
  auto entry_fail = [&](std::string_view list, std::size_t i, std::size_t base_count, const std::string& name,
                        std::string_view field, const std::string& what) {
    if (i < base_count) fail("room", fmt::format("{} of the base office: {}.{}: {}", name, list, field, what));
    fail(fmt::format("{}[{}].{}", list, i - base_count, field), what);
  };
  std::set<std::string> base_names;
  std::set<std::string> names;
  auto unique = [&](std::string_view list, std::size_t i, std::size_t base_count, const std::string& name) {
    if (name.empty()) entry_fail(list, i, base_count, name, "name", "must not be empty");
    if (!names.insert(name).second) {
      entry_fail(list, i, base_count, name, "name",
                 fmt::format("duplicate name '{}'{}", name, base_names.contains(name) ? " (the base office has it)" : ""));
    }
    if (i < base_count) base_names.insert(name);
  };
  for (std::size_t i = 0; i < desks.size(); ++i) {
    const Desk& desk = desks[i];
    const auto desk_fail = [&](std::string_view field, const std::string& what) {
      entry_fail("desks", i, base.desks.size(), desk.name, field, what);
    };
    unique("desks", i, base.desks.size(), desk.name);
    if (!inside(desk.position)) desk_fail("position", "outside the room");
    if ((desk.size.array() <= 0.0).any()) desk_fail("size", "must be positive");
    if (desk.height <= 0.1 || desk.height >= room.z()) desk_fail("height", "must be in (0.1, room height)");
  }
  for (std::size_t i = 0; i < shelves.size(); ++i) {
    const Shelf& shelf = shelves[i];
    const auto shelf_fail = [&](std::string_view field, const std::string& what) {
      entry_fail("shelves", i, base.shelves.size(), shelf.name, field, what);
    };
    unique("shelves", i, base.shelves.size(), shelf.name);
    if (!inside(shelf.position)) shelf_fail("position", "outside the room");
    if ((shelf.size.array() <= 0.0).any()) shelf_fail("size", "must be positive");
    if (shelf.boards < 2) shelf_fail("boards", "must be at least 2");
  }
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const OfficeObject& object = objects[i];
    const auto object_fail = [&](std::string_view field, const std::string& what) {
      entry_fail("objects", i, base.objects.size(), object.name, field, what);
    };
    unique("objects", i, base.objects.size(), object.name);
    if (!inside(object.position)) object_fail("position", "outside the room");
    if (object.z && (*object.z < 0.0 || *object.z >= room.z())) object_fail("z", "outside the room");
  }
  if (!walls) return;
  for (std::size_t i = 0; i < walls->size(); ++i) {
    const WallPanel& panel = (*walls)[i];
    const auto panel_fail = [&](std::string_view field, const std::string& what) {
      fail(fmt::format("walls[{}].{}", i, field), what);
    };
    if ((panel.size.array() <= 0.0).any()) panel_fail("size", "must be positive");
    const double length = WallLength(room, panel.wall);
    if (panel.at - panel.size.x() / 2.0 < 0.0 || panel.at + panel.size.x() / 2.0 > length) {
      panel_fail("at", fmt::format("a panel {} m wide at {} m does not fit the {} wall (0..{} m)", panel.size.x(),
                                   panel.at, ToString(panel.wall), length));
    }
    if (panel.z - panel.size.y() / 2.0 < 0.0 || panel.z + panel.size.y() / 2.0 > room.z()) {
      panel_fail("z", fmt::format("a panel {} m high at {} m does not fit between the floor and the ceiling "
                                  "(0..{} m)",
                                  panel.size.y(), panel.z, room.z()));
    }
  }
}

void OfficeLayout::Check(const std::string& source, const std::string& key) const {
  Check(source, key, OfficeLayout{});
}

OfficeLayout DefaultOfficeLayout() {
  OfficeLayout office;
  office.desks = {
      Desk{"desk_1", {3.2, 3.9}, 0.0},
      Desk{"desk_2", {4.8, 3.9}, 0.0},
      Desk{"desk_3", {1.3, 5.5}, 0.0},
      Desk{"desk_4", {6.7, 5.5}, 0.0},
  };
  office.shelves = {Shelf{"shelf_1", {4.0, 5.78}, -90.0}};
  using K = ObjectKind;
  office.objects = {
      // desk_1, centre front row
      Obj("tv_1", K::kTv, {3.2, 4.12}, -90),
      Obj("keyboard_1", K::kKeyboard, {3.2, 3.72}, -90),
      Obj("mouse_1", K::kMouse, {3.55, 3.72}, -90),
      Obj("cup_1", K::kCup, {2.6, 3.7}, 20, 0),
      Obj("book_1", K::kBook, {2.75, 4.1}, -80, 0),
      Obj("bottle_1", K::kBottle, {3.85, 4.1}, 0, 0),
      // desk_2
      Obj("tv_2", K::kTv, {4.8, 4.12}, -90),
      Obj("keyboard_2", K::kKeyboard, {4.75, 3.72}, -90),
      Obj("mouse_2", K::kMouse, {5.1, 3.72}, -90),
      Obj("laptop_1", K::kLaptop, {5.35, 3.9}, -75),
      Obj("cup_2", K::kCup, {4.25, 3.72}, -30, 1),
      Obj("book_2", K::kBook, {4.3, 4.1}, -95, 1),
      // desk_3, back left
      Obj("tv_3", K::kTv, {1.3, 5.72}, -90),
      Obj("keyboard_3", K::kKeyboard, {1.3, 5.32}, -90),
      Obj("laptop_2", K::kLaptop, {0.75, 5.4}, -100),
      Obj("cup_3", K::kCup, {1.85, 5.3}, 45, 2),
      Obj("bottle_2", K::kBottle, {1.95, 5.7}, 0, 1),
      // desk_4, back right
      Obj("tv_4", K::kTv, {6.7, 5.72}, -90),
      Obj("keyboard_4", K::kKeyboard, {6.7, 5.32}, -90),
      Obj("mouse_3", K::kMouse, {7.05, 5.32}, -90),
      Obj("book_3", K::kBook, {6.1, 5.35}, -60, 2),
      Obj("bottle_3", K::kBottle, {7.25, 5.45}, 0, 2),
      Obj("cup_4", K::kCup, {7.2, 5.75}, 0, 3),
      // chairs: 1-4 face their desks, 5-6 stand free
      Obj("chair_1", K::kChair, {3.2, 3.15}, 90),
      Obj("chair_2", K::kChair, {4.8, 3.15}, 90),
      Obj("chair_3", K::kChair, {1.3, 4.75}, 90),
      Obj("chair_4", K::kChair, {6.7, 4.75}, 90),
      Obj("chair_5", K::kChair, {0.9, 2.6}, 10),
      Obj("chair_6", K::kChair, {7.1, 2.6}, 170),
      // books on the shelf boards (boards at 0.02, 0.63, 1.25, 1.86 m)
      Obj("book_4", K::kBook, {3.75, 5.78}, -90, 3, 0.66),
      Obj("book_5", K::kBook, {4.2, 5.78}, -85, 0, 0.66),
      Obj("book_6", K::kBook, {3.9, 5.78}, -95, 1, 1.27),
      Obj("book_7", K::kBook, {3.9, 5.78}, -80, 2, 1.31),
  };
  return office;
}

std::vector<Box> ObjectParts(ObjectKind kind, int variant, const TextureSet& textures) {
  const int dark = textures.Index(TextureRole::kMonitorBody);
  std::vector<Box> parts;
  switch (kind) {
    case ObjectKind::kTv:
      parts.push_back(MakeBox(PoseAt({0, 0, 0.01}), {0.12, 0.1, 0.01}, dark, 0.3));
      parts.push_back(MakeBox(PoseAt({-0.03, 0, 0.1}), {0.02, 0.03, 0.08}, dark, 0.3));
      parts.push_back(MakeBox(PoseAt({0, 0, 0.37}), {0.03, 0.3, 0.19}, dark, 0.3));
      parts.push_back(MakeBox(PoseAt({0.031, 0, 0.375}), {0.003, 0.28, 0.17},
                              textures.Index(TextureRole::kMonitorScreen, variant), 0.56));
      break;
    case ObjectKind::kKeyboard:
      parts.push_back(
          MakeBox(PoseAt({0, 0, 0.012}), {0.075, 0.22, 0.012}, textures.Index(TextureRole::kKeyboard), 0.44));
      break;
    case ObjectKind::kMouse:
      parts.push_back(MakeBox(PoseAt({0, 0, 0.018}), {0.05, 0.03, 0.018}, textures.Index(TextureRole::kMouse), 0.1));
      break;
    case ObjectKind::kLaptop: {
      const int metal = textures.Index(TextureRole::kLaptop);
      parts.push_back(MakeBox(PoseAt({0.0, 0, 0.01}), {0.115, 0.165, 0.01}, metal, 0.33));
      parts.push_back(
          MakeBox(PoseAt({0.03, 0, 0.021}), {0.06, 0.14, 0.002}, textures.Index(TextureRole::kKeyboard), 0.28));
      // The lid leans back by 15 degrees; its inner face carries the screen.
      core::Pose T_lid = PoseAt({-0.12, 0, 0.13});
      T_lid.rotate(Eigen::AngleAxisd(-15 * kDeg, Vector3d::UnitY()));
      parts.push_back(MakeBox(T_lid, {0.005, 0.165, 0.115}, metal, 0.33));
      parts.push_back(MakeBox(T_lid * PoseAt({0.006, 0, 0}), {0.002, 0.15, 0.1},
                              textures.Index(TextureRole::kMonitorScreen, variant + 1), 0.3));
      break;
    }
    case ObjectKind::kBook:
      parts.push_back(
          MakeBox(PoseAt({0, 0, 0.02}), {0.12, 0.085, 0.02}, textures.Index(TextureRole::kBookCover, variant), 0.24));
      break;
    case ObjectKind::kCup: {
      const int print = textures.Index(TextureRole::kCup, variant);
      parts.push_back(MakeBox(PoseAt({0, 0, 0.05}), {0.04, 0.04, 0.05}, print, 0.16));
      parts.push_back(MakeBox(PoseAt({0, 0.048, 0.05}), {0.008, 0.01, 0.03}, print, 0.16));
      break;
    }
    case ObjectKind::kBottle: {
      const int label = textures.Index(TextureRole::kBottle, variant);
      parts.push_back(MakeBox(PoseAt({0, 0, 0.09}), {0.035, 0.035, 0.09}, label, 0.14));
      parts.push_back(MakeBox(PoseAt({0, 0, 0.2}), {0.025, 0.025, 0.02}, label, 0.14, {0.8F, 0.9F, 0.8F}));
      parts.push_back(
          MakeBox(PoseAt({0, 0, 0.245}), {0.013, 0.013, 0.025}, textures.Index(TextureRole::kGeneric, variant), 0.1));
      break;
    }
    case ObjectKind::kChair: {
      const int fabric = textures.Index(TextureRole::kChair);
      const cv::Vec3f tint = variant % 2 == 0 ? cv::Vec3f{1.0F, 1.0F, 1.0F} : cv::Vec3f{0.7F, 0.8F, 1.0F};
      parts.push_back(MakeBox(PoseAt({0, 0, 0.46}), {0.23, 0.23, 0.03}, fabric, 0.4, tint));
      parts.push_back(MakeBox(PoseAt({-0.21, 0, 0.73}), {0.025, 0.22, 0.22}, fabric, 0.4, tint));
      for (const double sx : {-1.0, 1.0}) {
        for (const double sy : {-1.0, 1.0}) {
          parts.push_back(MakeBox(PoseAt({sx * 0.19, sy * 0.19, 0.215}), {0.018, 0.018, 0.215}, dark, 0.3));
        }
      }
      break;
    }
  }
  return parts;
}

std::vector<SceneInstance> BuildStructure(const OfficeLayout& layout, const TextureSet& textures, int first_id) {
  std::vector<SceneInstance> structure;
  int next_id = first_id;
  auto add = [&](std::vector<Box> parts) {
    structure.push_back(SceneInstance{next_id++, "", false, std::move(parts)});
  };
  const Vector3d& room = layout.room;
  const double t = 0.1;  // wall thickness, outside the room
  const Vector3d mid(room.x() / 2, room.y() / 2, room.z() / 2);
  add({MakeBox(PoseAt({mid.x(), mid.y(), -t / 2}), {mid.x() + t, mid.y() + t, t / 2},
               textures.Index(TextureRole::kCarpet), 1.0)});
  add({MakeBox(PoseAt({mid.x(), mid.y(), room.z() + t / 2}), {mid.x() + t, mid.y() + t, t / 2},
               textures.Index(TextureRole::kCeiling), 1.2)});
  if (layout.patchwork_walls_seed) {
    add(PatchworkWalls(room, t, *layout.patchwork_walls_seed, textures));
  } else {
    const int wall = textures.Index(TextureRole::kWall);
    add({MakeBox(PoseAt({mid.x(), -t / 2, mid.z()}), {mid.x() + t, t / 2, mid.z()}, wall, 1.2),
         MakeBox(PoseAt({mid.x(), room.y() + t / 2, mid.z()}), {mid.x() + t, t / 2, mid.z()}, wall, 1.2),
         MakeBox(PoseAt({-t / 2, mid.y(), mid.z()}), {t / 2, mid.y(), mid.z()}, wall, 1.2, {0.9F, 0.95F, 1.0F}),
         MakeBox(PoseAt({room.x() + t / 2, mid.y(), mid.z()}), {t / 2, mid.y(), mid.z()}, wall, 1.2,
                 {0.9F, 0.95F, 1.0F})});
  }
  std::vector<Box> panels;
  if (layout.walls) {
    for (const WallPanel& panel : *layout.walls) panels.push_back(PanelOnWall(layout, panel, textures));
  } else {
    // Posters, a whiteboard and a door on the walls (wall 0: y = 0, 1: x = max, 2: y = max, 3: x = 0).
    int poster = 0;
    auto poster_at = [&](int w, double along, double z, double width, double height) {
      panels.push_back(PanelBox(layout, w, along, z, width, height, textures.Index(TextureRole::kPoster, poster++)));
    };
    poster_at(2, 2.6, 1.75, 0.7, 0.9);
    poster_at(2, 5.6, 1.7, 0.9, 0.65);
    poster_at(2, 7.5, 1.6, 0.6, 0.8);
    poster_at(3, 1.2, 1.6, 0.8, 0.6);
    poster_at(1, 4.6, 1.65, 0.7, 0.9);
    poster_at(0, 2.0, 1.6, 0.9, 0.7);
    poster_at(0, 6.0, 1.6, 0.7, 0.9);
    poster_at(2, 0.5, 1.5, 0.5, 0.7);
    panels.push_back(PanelBox(layout, 3, 3.4, 1.45, 1.6, 1.0, WhiteboardTexture(textures), kWhiteboardTint));
    panels.push_back(PanelBox(layout, 1, 1.0, 1.05, 0.95, 2.1, DoorTexture(textures), kDoorTint));
  }
  if (!panels.empty()) add(std::move(panels));
  for (const Desk& desk : layout.desks) {
    std::vector<Box> parts;
    AddDesk(desk, textures, parts);
    add(std::move(parts));
  }
  for (const Shelf& shelf : layout.shelves) {
    std::vector<Box> parts;
    AddShelf(shelf, textures, parts);
    add(std::move(parts));
  }
  if (!layout.walls) {
    // A low cabinet along the left wall.
    add({MakeBox(PoseAt({0.3, 3.9, 0.45}), {0.25, 0.6, 0.45}, textures.Index(TextureRole::kGeneric, 3), 0.9)});
  }
  return structure;
}

}  // namespace hoidslam::synth
