#pragma once
// The synthetic office: a room with desks, shelves, posters and the everyday objects people handle.
//
// World frame: the room spans x in [0, room.x], y in [0, room.y], z in [0, room.z] (z up, floor at 0).
// Objects have a local frame with its origin at the centre of their base, z up and their front (a monitor's
// screen, the side of a chair one sits down from) facing local +x; `yaw_deg` turns local +x to the world
// direction (cos yaw, sin yaw).

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hoidslam/core/pose.h"
#include "hoidslam/synth/scene.h"
#include "hoidslam/synth/textures.h"

namespace hoidslam::synth {

// The things in the office that carry a COCO label (and so get detected, and may be handled by people).
enum class ObjectKind { kTv, kKeyboard, kMouse, kLaptop, kBook, kCup, kBottle, kChair };

std::string_view CocoLabel(ObjectKind kind);  // "tv", "keyboard", ..., "chair"
// Parses the COCO labels CocoLabel gives; throws InputError naming `parameter` otherwise.
ObjectKind ParseObjectKind(std::string_view label, const std::string& parameter);
// The COCO-80 class index of a label ("person" = 0, "cup" = 41, ...), or -1 for a label hoidslam never draws.
int CocoClassId(std::string_view label);
// Half extents of an object's bounding box in its local frame (the box stands on z = 0).
Eigen::Vector3d ObjectHalfExtents(ObjectKind kind);
// True when a person carries the object with both hands (books, laptops, monitors, keyboards, chairs).
bool IsTwoHanded(ObjectKind kind);

struct OfficeObject {
  std::string name;  // unique, e.g. "cup_1"; scenarios refer to objects by it
  ObjectKind kind = ObjectKind::kCup;
  Eigen::Vector2d position = {0.0, 0.0};  // base centre, world x, y
  std::optional<double> z;                // base height; absent = on whatever desk is below, else the floor
  double yaw_deg = 0.0;
  int variant = 0;  // texture variant (book cover, cup print, ...)
};

struct Desk {
  std::string name;
  Eigen::Vector2d position = {0.0, 0.0};  // centre of the top, world x, y
  double yaw_deg = 0.0;                   // direction of the desk's long side
  Eigen::Vector2d size = {1.6, 0.8};      // long side, depth; metres
  double height = 0.74;                   // height of the top surface, metres
};

struct Shelf {
  std::string name;
  Eigen::Vector2d position = {0.0, 0.0};    // centre of the footprint
  double yaw_deg = 0.0;                     // direction the open side faces
  Eigen::Vector3d size = {1.0, 0.35, 1.9};  // width, depth, height; metres
  int boards = 4;                           // shelf boards, >= 2
};

// The four walls, seen from above with the room's x axis to the right: front y = 0, right x = room.x, back
// y = room.y, left x = 0.
enum class Wall { kFront, kRight, kBack, kLeft };
std::string_view ToString(Wall wall);  // "front", "right", "back", "left"
// Parses the names ToString gives; throws InputError naming `parameter` otherwise.
Wall ParseWall(std::string_view name, const std::string& parameter);
// Length of the wall in a room of size `room` (x, y, height), metres.
double WallLength(const Eigen::Vector3d& room, Wall wall);
// The point on the floor plan `at` along the wall (as WallPanel::at measures it).
Eigen::Vector2d WallPoint(const Eigen::Vector3d& room, Wall wall, double at);
// The wall's unit normal into the room, on the floor plan.
Eigen::Vector2d InwardNormal(Wall wall);

enum class PanelKind { kPoster, kWhiteboard, kDoor };
std::string_view ToString(PanelKind kind);  // "poster", "whiteboard", "door"
// Parses the names ToString gives; throws InputError naming `parameter` otherwise.
PanelKind ParsePanelKind(std::string_view name, const std::string& parameter);
// The size a panel of that kind has unless told otherwise: width, height; metres.
Eigen::Vector2d DefaultPanelSize(PanelKind kind);

// A flat thing on a wall, drawn just inside it.
struct WallPanel {
  PanelKind kind = PanelKind::kPoster;
  Wall wall = Wall::kBack;
  double at = 1.0;                    // centre along the wall: its x on the front and back walls, its y on the others
  double z = 1.6;                     // centre height, metres
  Eigen::Vector2d size = {0.7, 0.9};  // width, height; metres
  int variant = 0;                    // posters: which poster texture (with photos: which photo, wrapping round)
};

struct OfficeLayout {
  Eigen::Vector3d room = {8.0, 6.0, 2.8};  // metres
  std::vector<Desk> desks;
  std::vector<Shelf> shelves;
  std::vector<OfficeObject> objects;
  // What is on the walls. Nullopt: the default office's posters, whiteboard and door (placed for its 8 x 6 m room)
  // and the low cabinet along the left wall; else exactly these panels, and whatever wall they leave is bare.
  std::optional<std::vector<WallPanel>> walls;
  // The walls' own surface. Nullopt: one texture tiled every 1.2 m on all four walls (the shipped offices).
  // Else a patchwork drawn from this seed: every wall cut into pieces 0.8-1.6 m wide and 0.7-1.4 m high, each
  // showing one poster texture (with photos: one photo) once, never the same as its left or lower neighbour.
  // The random offices use it: with one photo repeated every 1.2 m on every wall, places a quarter turn or a
  // few tiles apart look exactly alike, which no real room does.
  std::optional<std::uint64_t> patchwork_walls_seed;

  // Base height of a thing standing at (x, y): the top of the desk there, else the floor.
  double SupportHeightAt(const Eigen::Vector2d& xy) const;
  // True when (x, y) lies on a desk or shelf footprint grown by `margin` metres (where a person cannot stand).
  bool IsBlocked(const Eigen::Vector2d& xy, double margin) const;
  // A walking route from `from` to `to` keeping `clearance` metres from desks and shelves: the waypoints after
  // `from`, ending with `to`. Straight when nothing is in the way, else the shortest path via the corners of
  // the footprints grown by the clearance. A footprint that `from` or `to` itself is too close to keeps only a
  // token margin (people walk up to desks). Nullopt when there is no way round (`to` inside a desk, or walled
  // in): the caller names the action that asked for it.
  std::optional<std::vector<Eigen::Vector2d>> Route(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                                    double clearance) const;
  // The object named `name`, or nullptr.
  const OfficeObject* FindObject(std::string_view name) const;
  // The resting pose of `object` (its base height resolved with SupportHeightAt when not given).
  core::Pose RestPose(const OfficeObject& object) const;
  // Throws InputError "<source>: <key>.<list>[i].<field>: ..." for duplicate names, a non-positive size, or
  // anything outside the room (a wall panel off its wall); `key` is the layout's key in the scenario ("office").
  // `base` is the layout this one extends: its desks, shelves and objects come first in each list, and i counts
  // from the first entry after them, as in the scenario's own arrays (`walls` is never the base's). A base entry
  // outside a smaller room is blamed on "room".
  void Check(const std::string& source, const std::string& key, const OfficeLayout& base) const;
  // The same for a layout of its own (no base).
  void Check(const std::string& source, const std::string& key) const;
};

// The office every shipped scenario uses: 4 desks with monitors, keyboards, mice, laptops, books, cups and
// bottles, 6 chairs and a shelf of books in an 8 x 6 x 2.8 m room. Object names: docs/synthetic-benchmark.md.
OfficeLayout DefaultOfficeLayout();

// Boxes of an object in its local frame, textured from `textures`.
std::vector<Box> ObjectParts(ObjectKind kind, int variant, const TextureSet& textures);

// Builds the static structure (room, desks, shelves, posters) as instances with label "", ids counting up
// from `first_id`.
std::vector<SceneInstance> BuildStructure(const OfficeLayout& layout, const TextureSet& textures, int first_id);

}  // namespace hoidslam::synth
