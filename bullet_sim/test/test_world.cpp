// World files: valid ones load; every kind of bad file is refused naming the file, line and key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "bullet_sim/world.h"

using bullet_sim::World;
using bullet_sim::WorldError;

namespace {

const char* kValid = R"(name: test_room
wall_thickness: 0.1
walls:
  - points: [[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]
boxes:
  - {center: [4.0, 3.0], size: [1.0, 0.6], yaw: 0.3}
cylinders:
  - {center: [1.0, 1.0], radius: 0.1}
robot:
  start: [3.0, 2.0, 0.0]
regions:
  - {name: room, kind: room, polygon: [[0, 0], [6, 0], [6, 4], [0, 4]]}
doors: []
)";

// Parses `text` and returns the error message ("" if it parsed).
std::string errorOf(const std::string& text, const std::string& source = "bad.yaml") {
  try {
    bullet_sim::parseWorld(text, source);
  } catch (const WorldError& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST(World, ValidWorldLoads) {
  const World w = bullet_sim::parseWorld(kValid, "valid.yaml");
  EXPECT_EQ(w.name, "test_room");
  ASSERT_EQ(w.walls.size(), 1u);
  EXPECT_EQ(w.walls[0].points.size(), 5u);
  EXPECT_EQ(w.solidBoxes().size(), 4u + 1u);
  EXPECT_NEAR(w.boxes[0].half_x, 0.5, 1e-12);
  EXPECT_NEAR(w.boxes[0].yaw, 0.3, 1e-12);
  EXPECT_NEAR(w.start.x, 3.0, 1e-12);
  EXPECT_EQ(w.regionAt({3.0, 2.0}), 0);
  EXPECT_EQ(w.regionAt({7.0, 2.0}), -1);
  EXPECT_NEAR(bullet_sim::distanceToObstacles(w, {3.0, 0.8}), 0.75, 1e-9);  // to the wall at y = 0 (inner face 0.05)
}

TEST(World, UnknownKeyIsRefusedWithLineAndKey) {
  const std::string e = errorOf(replace(kValid, "cylinders:", "pillars:"));
  EXPECT_NE(e.find("bad.yaml:7:"), std::string::npos) << e;
  EXPECT_NE(e.find("pillars"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(World, UnknownNestedKeyIsRefused) {
  const std::string e = errorOf(replace(kValid, "yaw: 0.3", "heading: 0.3"));
  EXPECT_NE(e.find("boxes[0].heading"), std::string::npos) << e;
  EXPECT_NE(e.find("bad.yaml:6:"), std::string::npos) << e;
}

TEST(World, MissingRequiredKeyIsRefused) {
  const std::string e = errorOf(replace(kValid, "name: test_room\n", ""));
  EXPECT_NE(e.find("bad.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("name: missing required key"), std::string::npos) << e;
  const std::string e2 = errorOf(replace(kValid, "robot:\n  start: [3.0, 2.0, 0.0]\n", ""));
  EXPECT_NE(e2.find("robot: missing required key"), std::string::npos) << e2;
}

TEST(World, ShortPolylineIsRefused) {
  const std::string e = errorOf(replace(kValid, "[[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]", "[[0, 0]]"));
  EXPECT_NE(e.find("bad.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("walls[0].points"), std::string::npos) << e;
  EXPECT_NE(e.find("at least two points"), std::string::npos) << e;
}

TEST(World, NegativeSizeIsRefused) {
  const std::string e = errorOf(replace(kValid, "size: [1.0, 0.6]", "size: [-1.0, 0.6]"));
  EXPECT_NE(e.find("boxes[0].size"), std::string::npos) << e;
  EXPECT_NE(e.find("positive"), std::string::npos) << e;
  const std::string e2 = errorOf(replace(kValid, "radius: 0.1", "radius: -0.1"));
  EXPECT_NE(e2.find("cylinders[0].radius"), std::string::npos) << e2;
  const std::string e3 = errorOf(replace(kValid, "wall_thickness: 0.1", "wall_thickness: 0"));
  EXPECT_NE(e3.find("wall_thickness"), std::string::npos) << e3;
}

TEST(World, StartInsideObstacleIsRefused) {
  const std::string e = errorOf(replace(kValid, "start: [3.0, 2.0, 0.0]", "start: [4.0, 3.0, 0.0]"));
  EXPECT_NE(e.find("bad.yaml:10:"), std::string::npos) << e;
  EXPECT_NE(e.find("robot.start"), std::string::npos) << e;
  EXPECT_NE(e.find("inside an obstacle"), std::string::npos) << e;
}

TEST(World, WrongTypesAreRefused) {
  EXPECT_NE(errorOf(replace(kValid, "start: [3.0, 2.0, 0.0]", "start: [3.0, 2.0]")).find("robot.start"), std::string::npos);
  EXPECT_NE(errorOf(replace(kValid, "center: [1.0, 1.0]", "center: [one, 1.0]")).find("must be a number"), std::string::npos);
  EXPECT_NE(errorOf(replace(kValid, "kind: room", "kind: attic")).find("regions[0].kind"), std::string::npos);
  EXPECT_NE(errorOf(replace(kValid, "doors: []", "doors:\n  - {between: [room, nowhere], center: [0, 2], width: 1}"))
                .find("unknown region 'nowhere'"),
            std::string::npos);
}

TEST(World, NotYamlIsRefused) {
  const std::string e = errorOf("name: [unclosed\nwalls: {", "broken.yaml");
  EXPECT_NE(e.find("broken.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("not valid YAML"), std::string::npos) << e;
  const std::string e2 = errorOf("just a sentence", "text.yaml");
  EXPECT_NE(e2.find("text.yaml"), std::string::npos) << e2;
  EXPECT_NE(e2.find("not a world file"), std::string::npos) << e2;
}

TEST(World, UnreadableFileIsRefused) {
  try {
    bullet_sim::loadWorldFile("/nonexistent/world.yaml");
    FAIL() << "no error";
  } catch (const WorldError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/world.yaml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("cannot read"), std::string::npos);
  }
}

// Every shipped world loads, and its ground truth is complete: each door joins two regions and lies
// in a gap of the walls (no wall within width/2 of its centre along the opening), each room has a door.
class ShippedWorld : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedWorld, LoadsWithCompleteGroundTruth) {
  const std::string path = std::string(WORLDS_DIR) + "/" + GetParam() + ".yaml";
  const World w = bullet_sim::loadWorldFile(path);
  EXPECT_EQ(w.name, GetParam());
  EXPECT_FALSE(w.regions.empty());
  EXPECT_GE(bullet_sim::distanceToObstacles(w, {w.start.x, w.start.y}), 0.5) << "start too close to an obstacle";
  EXPECT_GE(w.regionAt({w.start.x, w.start.y}), 0) << "start outside every region";
  std::vector<int> doors_per_region(w.regions.size(), 0);
  for (const auto& d : w.doors) {
    for (const auto& name : d.between)
      for (size_t i = 0; i < w.regions.size(); ++i)
        if (w.regions[i].name == name) ++doors_per_region[i];
    // The door centre is free space with clearance of about half the width.
    EXPECT_GT(bullet_sim::distanceToObstacles(w, d.center), d.width / 2 - 0.1)
        << "door at (" << d.center.x << ", " << d.center.y << ") is not a gap in the walls";
  }
  for (size_t i = 0; i < w.regions.size(); ++i)
    EXPECT_GT(doors_per_region[i], 0) << "region " << w.regions[i].name << " has no door";
}

INSTANTIATE_TEST_SUITE_P(Worlds, ShippedWorld, ::testing::Values("small_loop", "institute", "large_floor"));

// Closed doors (fault tests): a leaf fills the opening along the regions' shared boundary.
TEST(World, ClosedDoorIsASolidLeafAcrossTheOpening) {
  World w = bullet_sim::loadWorldFile(std::string(WORLDS_DIR) + "/small_loop.yaml");
  const size_t open_boxes = w.solidBoxes().size();
  w.closeDoors({"room_east"});  // its one door, in hall_south's north wall at (12, 2)
  EXPECT_EQ(w.solidBoxes().size(), open_boxes + 1);
  EXPECT_LE(bullet_sim::distanceToObstacles(w, {12.0, 2.0}), 0.0);
  EXPECT_LE(bullet_sim::distanceToObstacles(w, {11.6, 2.0}), 0.0);  // no slit at the door's edges
  EXPECT_GT(bullet_sim::distanceToObstacles(w, {12.0, 1.7}), 0.2);  // the hallway stays free
  EXPECT_GT(bullet_sim::distanceToObstacles(w, {12.0, 2.3}), 0.2);  // and so does the room
  // "a/b" in either order names one door; the others stay open.
  World v = bullet_sim::loadWorldFile(std::string(WORLDS_DIR) + "/small_loop.yaml");
  v.closeDoors({"hall_north/room_west"});
  EXPECT_LE(bullet_sim::distanceToObstacles(v, {4.0, 10.0}), 0.0);
  EXPECT_GT(bullet_sim::distanceToObstacles(v, {12.0, 2.0}), 0.4);
}

TEST(World, ClosingAnUnknownDoorNamesTheDoorsThereAre) {
  World w = bullet_sim::loadWorldFile(std::string(WORLDS_DIR) + "/small_loop.yaml");
  try {
    w.closeDoors({"room_nowhere"});
    FAIL() << "no error";
  } catch (const WorldError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("room_nowhere"), std::string::npos) << m;
    EXPECT_NE(m.find("room_east/hall_south"), std::string::npos) << m;
  }
}

TEST(World, ClosedKeyInTheWorldFile) {
  const std::string with_door = replace(
      replace(kValid, "doors: []", "doors:\n  - {between: [room, hall], center: [6, 2], width: 1, closed: true}"),
      "regions:\n", "regions:\n  - {name: hall, kind: hallway, polygon: [[6, 0], [8, 0], [8, 4], [6, 4]]}\n");
  const World w = bullet_sim::parseWorld(with_door, "closed.yaml");
  ASSERT_EQ(w.doors.size(), 1u);
  EXPECT_TRUE(w.doors[0].closed);
  EXPECT_NEAR(std::abs(std::sin(w.doorLeaf(w.doors[0]).yaw)), 1.0, 1e-9);  // along the wall x = 6
  const std::string e = errorOf(replace(with_door, "closed: true", "closed: maybe"));
  EXPECT_NE(e.find("doors[0].closed"), std::string::npos) << e;
  const std::string far = errorOf(replace(with_door, "center: [6, 2]", "center: [3, 2]"));
  EXPECT_NE(far.find("cannot close this door"), std::string::npos) << far;
}

// The camera's keys: colours of walls, boxes and cylinders, coloured stretches of wall, the floor's
// and ceiling's; a box's height. Optional: a world without them loads as before.
TEST(World, ColoursAndStripesLoad) {
  const std::string text = replace(replace(replace(kValid, "walls:\n  - points: [[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]",
      "colors: {floor: [90, 80, 70], ceiling: [240, 240, 235]}\nwalls:\n"
      "  - points: [[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]\n    color: [200, 40, 30]\n"
      "    stripes:\n      - {from: 7.0, to: 8.0, bottom: 0.5, top: 1.5, color: [0, 0, 255]}\n"
      "      - {from: 19.0, to: 20.0, color: [255, 255, 0]}"),
      "yaw: 0.3}", "yaw: 0.3, height: 1.8, color: [10, 20, 30]}"), "radius: 0.1}",
      "radius: 0.1, height: 0.4, color: [1, 2, 3]}");
  const World w = bullet_sim::parseWorld(text, "colours.yaml");
  ASSERT_TRUE(w.floor_color && w.ceiling_color);
  EXPECT_EQ(*w.floor_color, (bullet_sim::Rgb{90, 80, 70}));
  ASSERT_TRUE(w.walls[0].color);
  EXPECT_EQ(*w.walls[0].color, (bullet_sim::Rgb{200, 40, 30}));
  ASSERT_EQ(w.walls[0].stripes.size(), 2u);
  EXPECT_NEAR(w.walls[0].stripes[0].top, 1.5, 1e-12);
  EXPECT_NEAR(w.walls[0].stripes[1].top, w.wall_height, 1e-12);  // top defaults to the wall's
  EXPECT_NEAR(w.walls[0].length(), 20.0, 1e-12);
  EXPECT_NEAR(w.boxes[0].height, 1.8, 1e-12);
  EXPECT_EQ(*w.cylinders[0].color, (bullet_sim::Rgb{1, 2, 3}));
  EXPECT_NEAR(w.cylinders[0].height, 0.4, 1e-12);
  // Each solid knows where it comes from: the wall's four segments, then the box.
  std::vector<bullet_sim::SolidSource> sources;
  const auto solids = w.solidBoxes(&sources);
  ASSERT_EQ(sources.size(), solids.size());
  EXPECT_EQ(sources[2].kind, bullet_sim::SolidSource::Wall);
  EXPECT_EQ(sources[2].segment, 2u);
  EXPECT_NEAR(sources[2].along, 10.0, 1e-12);
  EXPECT_EQ(sources[4].kind, bullet_sim::SolidSource::Box);
  EXPECT_NEAR(solids[0].height, w.wall_height, 1e-12);

  const World plain = bullet_sim::parseWorld(kValid, "valid.yaml");
  EXPECT_FALSE(plain.floor_color || plain.walls[0].color || plain.boxes[0].color);
  EXPECT_NEAR(plain.boxes[0].height, bullet_sim::kFurnitureHeight, 1e-12);
  EXPECT_NEAR(plain.cylinders[0].height, plain.wall_height, 1e-12);  // a pillar
}

TEST(World, BadColoursAndStripesAreRefusedNamingTheKey) {
  const std::string wall = "  - points: [[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]";
  auto withWall = [&](const std::string& extra) { return replace(kValid, wall, wall + "\n" + extra); };
  EXPECT_NE(errorOf(withWall("    color: [300, 0, 0]")).find("walls[0].color: colour components are whole numbers 0-255"),
            std::string::npos);
  EXPECT_NE(errorOf(withWall("    color: [1, 2]")).find("walls[0].color: must be a colour [r, g, b]"), std::string::npos);
  EXPECT_NE(errorOf(withWall("    color: [0.5, 2, 3]")).find("walls[0].color"), std::string::npos);
  EXPECT_NE(errorOf(withWall("    stripes:\n      - {from: 3.0, to: 2.0, color: [0, 0, 0]}")).find(
                "walls[0].stripes[0]: needs 0 <= from < to <= the wall's length (20"),
            std::string::npos);
  EXPECT_NE(errorOf(withWall("    stripes:\n      - {from: 19.0, to: 21.0, color: [0, 0, 0]}")).find("walls[0].stripes[0]"),
            std::string::npos);
  EXPECT_NE(errorOf(withWall("    stripes:\n      - {from: 1.0, to: 2.0, top: 2.5, color: [0, 0, 0]}")).find(
                "needs 0 <= bottom < top <= wall_height"),
            std::string::npos);
  EXPECT_NE(errorOf(withWall("    stripes:\n      - {from: 1.0, to: 2.0}")).find("walls[0].stripes[0].color: missing required key"),
            std::string::npos);
  EXPECT_NE(errorOf(withWall("    stripes:\n      - {from: 1.0, to: 2.0, colour: [0, 0, 0]}")).find("unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf(replace(kValid, "wall_thickness: 0.1", "wall_thickness: 0.1\ncolors: {walls: [1, 2, 3]}")).find(
                "colors.walls: unknown key (allowed: ceiling, floor, wall_ends)"),
            std::string::npos);
  EXPECT_NE(errorOf(replace(kValid, "yaw: 0.3}", "yaw: 0.3, height: -1}")).find("boxes[0].height: must be positive"),
            std::string::npos);
}
