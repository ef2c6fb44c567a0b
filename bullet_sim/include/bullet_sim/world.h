// World description read from worlds/*.yaml (format: DESIGN.md, "World files").
// ROS-free: yaml-cpp and the standard library only.
#pragma once

#include <array>
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

// A solid box of the world, axis-aligned in its own frame (walls and furniture alike).
struct OrientedBox {
  Vec2 center;
  double half_x = 0.0;  // m, half extent along the box's own x axis
  double half_y = 0.0;  // m
  double yaw = 0.0;     // rad
};

struct Cylinder {
  Vec2 center;
  double radius = 0.0;  // m
};

struct WallPolyline {
  std::vector<Vec2> points;
  double thickness = 0.0;  // m
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
  std::vector<WallPolyline> walls;
  std::vector<OrientedBox> boxes;  // furniture
  std::vector<Cylinder> cylinders;
  Pose2 start;
  // Ground truth, for evaluation only.
  std::vector<Region> regions;
  std::vector<Door> doors;

  // Every wall segment as a box (length along the segment, thickness across), then the furniture,
  // then a leaf across every closed door.
  std::vector<OrientedBox> solidBoxes() const;
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
