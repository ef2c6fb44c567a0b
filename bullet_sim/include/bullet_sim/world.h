// World description read from worlds/*.yaml (format: DESIGN.md, "World files").
// ROS-free: yaml-cpp and the standard library only.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace bullet_sim {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;  // rad
};

// A surface colour (the panoramic camera's; the laser ignores colours).
struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

// A solid box of the world, axis-aligned in its own frame (walls and furniture alike).
struct OrientedBox {
  Vec2 center;
  double half_x = 0.0;  // m, half extent along the box's own x axis
  double half_y = 0.0;  // m
  double yaw = 0.0;     // rad
  double height = 0.0;  // m above the floor (a wall: the world's wall_height)
  std::optional<Rgb> color;  // none: the camera's palette colour for this surface
};

// m, a box's height when its `height` key is absent: a desk or table top (furniture along walls,
// tables); the laser's plane (0.3 m) cuts it either way.
constexpr double kFurnitureHeight = 0.75;

struct Cylinder {
  Vec2 center;
  double radius = 0.0;  // m
  double height = 0.0;  // m above the floor (default: the world's wall_height, a pillar)
  std::optional<Rgb> color;
};

// A coloured stretch of a wall (a poster, a stripe, a door frame), on both of its faces.
struct WallStripe {
  double from = 0.0, to = 0.0;      // m along the polyline from its first point, from < to
  double bottom = 0.0, top = 0.0;   // m above the floor, bottom < top
  Rgb color;
};

struct WallPolyline {
  std::vector<Vec2> points;
  double thickness = 0.0;  // m
  std::optional<Rgb> color;
  std::vector<WallStripe> stripes;
  double length() const;  // m, along its segments
};

// Where a solid box of World::solidBoxes() comes from (the camera colours it by this).
struct SolidSource {
  enum Kind { Wall, Box, DoorLeaf } kind = Wall;
  size_t index = 0;    // into walls, boxes or doors
  size_t segment = 0;  // a wall's segment (points[segment] to points[segment + 1])
  double along = 0.0;  // m, a wall: the polyline's length before this segment
};

struct Region {
  std::string name;
  bool hallway = false;  // kind: hallway, otherwise room
  std::vector<Vec2> polygon;
};

struct Door {
  std::array<std::string, 2> between;
  Vec2 center;
  double width = 0.0;   // m
  bool closed = false;  // a closed door is a solid leaf across the opening (fault tests)
};

struct World {
  std::string name;
  std::string source;  // file the world was read from (for messages)
  double wall_thickness = 0.10;  // m
  double wall_height = 2.0;      // m
  // colors.floor, colors.ceiling, colors.wall_ends (the camera's; a wall's end faces are the jambs
  // of its doors, their frames)
  std::optional<Rgb> floor_color, ceiling_color, wall_ends_color;
  std::vector<WallPolyline> walls;
  std::vector<OrientedBox> boxes;  // furniture
  std::vector<Cylinder> cylinders;
  Pose2 start;
  // Ground truth, for evaluation only.
  std::vector<Region> regions;
  std::vector<Door> doors;

  // Every wall segment as a box (length along the segment, thickness across), then the furniture,
  // then a leaf across every closed door; `sources`, when given, receives where each comes from.
  std::vector<OrientedBox> solidBoxes(std::vector<SolidSource>* sources = nullptr) const;
  // The leaf that fills a door's opening: along the boundary edge of its regions nearest the centre,
  // one wall thickness longer than the opening, half a wall thickness thick. Throws WorldError when
  // no region edge passes within 0.3 m of the door's centre (the leaf's direction is then unknown).
  OrientedBox doorLeaf(const Door& door) const;
  // Closes doors by name: "a/b" (or "b/a") is the door between regions a and b, a region name alone
  // closes every door of that region. Throws WorldError for a name that matches no door.
  void closeDoors(const std::vector<std::string>& names);
  // Axis-aligned bounds of all obstacles (m).
  void bounds(Vec2* min, Vec2* max) const;
  // Index of the region whose polygon contains p, -1 if none.
  int regionAt(const Vec2& p) const;
};

// Thrown for any invalid world; what() reads "<file>:<line>: <key>: <problem>".
class WorldError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads and validates a world file. Throws WorldError.
World loadWorldFile(const std::string& path);
// Parses a world from YAML text; `source` names it in errors. Throws WorldError.
World parseWorld(const std::string& yaml_text, const std::string& source);

// Signed distance from p to the closest obstacle surface (negative inside), m.
double distanceToObstacles(const World& world, const Vec2& p);

}  // namespace bullet_sim
