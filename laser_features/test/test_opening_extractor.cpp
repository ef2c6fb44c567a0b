// Openings: doors seen frontally and obliquely (width within 5 cm), junctions, no opening in a
// closed room or behind an occluding box, no duplicates.
#include "laser_features/feature_extractor.h"

#include "synthetic_scan.h"
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <random>

namespace laser_features {
namespace {

using namespace synthetic;
using testing_helpers::allFinite;

constexpr double kSigma = 0.01;

Features extractFeatures(const World& world, const Pose2D& sensor, const ScanSpec& spec, std::mt19937* rng) {
  const std::vector<float> ranges = simulateScan(world, sensor, spec, kSigma, rng);
  FeatureExtractor extractor;
  Features features;
  std::string error;
  EXPECT_TRUE(extractor.extract(makeView(spec, ranges), &features, &error)) << error;
  EXPECT_TRUE(allFinite(features));
  return features;
}

/// The openings whose centre is within `radius` of `p` (sensor frame).
std::vector<Opening> openingsNear(const Features& features, const Eigen::Vector2d& p, double radius) {
  std::vector<Opening> near;
  for (const Opening& opening : features.openings)
    if ((opening.center - p).norm() < radius) near.push_back(opening);
  return near;
}

/// Checks one opening at the world door centre with the given width and outward world direction.
void expectOpening(const Features& features, const Pose2D& sensor, const Eigen::Vector2d& world_center,
                   double width, double world_direction, OpeningKind kind) {
  const Eigen::Vector2d center = pointInSensorFrame(world_center, sensor);
  const std::vector<Opening> near = openingsNear(features, center, 0.6);
  ASSERT_EQ(near.size(), 1u) << "openings near the door: " << near.size() << " of " << features.openings.size();
  const Opening& opening = near[0];
  EXPECT_NEAR(opening.width, width, 0.05);
  EXPECT_LT((opening.center - center).norm(), 0.1);
  EXPECT_NEAR(normalizeAngle(opening.theta - (world_direction - sensor.theta)), 0.0, 0.1);
  EXPECT_EQ(opening.kind, kind);
  EXPECT_NEAR((opening.left - opening.right).norm(), opening.width, 1e-9);
  // Left is on the left when looking along theta.
  EXPECT_GT(unitVector(opening.theta + kPi / 2).dot(opening.left - opening.center), 0.0);
  EXPECT_GT(opening.confidence, 0.3);
}

TEST(OpeningExtractor, DoorSeenFrontally) {
  std::mt19937 rng(1);
  for (const double width : {0.8, 0.9, 1.0, 1.2}) {
    const World world = roomWithDoor(2.5, width);
    const Pose2D sensor{2.0, 2.2, 0.3};
    const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
    SCOPED_TRACE(width);
    expectOpening(features, sensor, {6.0, 2.5}, width, 0.0, OpeningKind::kDoor);
  }
}

TEST(OpeningExtractor, DoorSeenObliquelyFromAHallway) {
  std::mt19937 rng(2);
  for (const double sensor_x : {7.0, 8.5, 11.5}) {
    const World world = hallwayWithSideDoor(10.0, 0.9);
    const Pose2D sensor{sensor_x, 1.0, 0.2};
    const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
    SCOPED_TRACE(sensor_x);
    expectOpening(features, sensor, {10.0, 2.0}, 0.9, kPi / 2, OpeningKind::kDoor);
    EXPECT_EQ(features.place_type, PlaceType::kHallway);
  }
}

TEST(OpeningExtractor, DoorWidthAccurateOverManyTrials) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(1.0, 4.5), y(1.0, 4.0), heading(-kPi, kPi);
  const World world = roomWithDoor(2.5, 0.9);
  int found = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const Pose2D sensor{x(rng), y(rng), heading(rng)};
    const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
    const std::vector<Opening> near = openingsNear(features, pointInSensorFrame({6.0, 2.5}, sensor), 0.6);
    EXPECT_LE(near.size(), 1u);
    if (near.empty()) continue;
    ++found;
    EXPECT_NEAR(near[0].width, 0.9, 0.05);
    EXPECT_EQ(near[0].kind, OpeningKind::kDoor);
  }
  EXPECT_GE(found, 47);
}

TEST(OpeningExtractor, SideBranchIsAJunction) {
  World world;  // a hallway along x with a 2 m wide corridor branching off upwards at x in [9, 11]
  world.addWall(0, 0, 30, 0);
  world.addWall(0, 2, 9, 2);
  world.addWall(11, 2, 30, 2);
  world.addWall(9, 2, 9, 12);
  world.addWall(11, 2, 11, 12);
  world.addWall(0, 0, 0, 2);
  world.addWall(30, 0, 30, 2);
  std::mt19937 rng(4);
  const Pose2D sensor{7.0, 1.0, -0.1};
  const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
  expectOpening(features, sensor, {10.0, 2.0}, 2.0, kPi / 2, OpeningKind::kJunction);
}

// A branch off the hallway is an opening up to the widest hallway (BuildingRules::widestHallway:
// hallway_max_width plus the width tolerance), its width within that tolerance (an edge is the last
// beam on its wall); a gap wider than that is no opening. Seen abeam from the mid-line of a 2.5 m
// hallway (seen from before it, the wall beyond a 4 m branch is so oblique that one beam spacing
// along it exceeds the tolerance: the branch is reported once the robot comes abeam).
TEST(OpeningExtractor, ABranchAsWideAsTheWidestHallwayIsAJunctionAWiderGapIsNoOpening) {
  const BuildingRules rules;
  const double widest = rules.widestHallway();
  for (const double branch : {3.2, 3.6, 4.0, widest + 0.6}) {
    SCOPED_TRACE(branch);
    World world;  // a 2.5 m hallway along x, a branch `branch` wide going up from x = 9
    const double x1 = 9.0 + branch;
    world.addWall(0, 0, 30, 0);
    world.addWall(0, 2.5, 9, 2.5);
    world.addWall(x1, 2.5, 30, 2.5);
    world.addWall(9, 2.5, 9, 14);
    world.addWall(x1, 2.5, x1, 14);
    world.addWall(0, 0, 0, 2.5);
    world.addWall(30, 0, 30, 2.5);
    std::mt19937 rng(11);
    const Pose2D sensor{9.0 + 0.5 * branch, 1.25, 0.0};
    const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
    const Eigen::Vector2d mouth = pointInSensorFrame({9.0 + 0.5 * branch, 2.5}, sensor);
    const std::vector<Opening> near = openingsNear(features, mouth, 0.6);
    if (branch > widest) {
      EXPECT_TRUE(near.empty());
      continue;
    }
    ASSERT_EQ(near.size(), 1u);
    EXPECT_NEAR(near[0].width, branch, rules.width_tolerance);
    EXPECT_EQ(near[0].kind, OpeningKind::kJunction);
    EXPECT_NEAR(normalizeAngle(near[0].theta - 0.5 * kPi), 0.0, 0.1);
  }
}

// An opening needs free space behind its line as deep as the robot is wide (it fits through): a
// 1 m gap in a hallway's wall into a recess shallower than the robot's diameter is no opening, a
// deeper one is; for a wider robot the same recess is not.
TEST(OpeningExtractor, ARecessShallowerThanTheRobotsDiameterIsNoOpening) {
  for (const double radius : {0.25, 0.4}) {
    for (const double depth : {0.4, 0.7}) {
      SCOPED_TRACE("robot radius " + std::to_string(radius) + " m, recess " + std::to_string(depth) + " m deep");
      World world;  // a 2 m hallway along x, a 1 m gap at x in [9, 10] into a recess `depth` deep
      world.addWall(0, 0, 20, 0);
      world.addWall(0, 2, 9, 2);
      world.addWall(10, 2, 20, 2);
      world.addWall(9, 2, 9, 2 + depth);
      world.addWall(10, 2, 10, 2 + depth);
      world.addWall(9, 2 + depth, 10, 2 + depth);
      world.addWall(0, 0, 0, 2);
      world.addWall(20, 0, 20, 2);
      std::mt19937 rng(12);
      const Pose2D sensor{9.5, 1.0, 0.0};
      const ScanSpec spec = ScanSpec::full(720);
      const std::vector<float> ranges = simulateScan(world, sensor, spec, kSigma, &rng);
      FeatureExtractor::Params params;
      params.openings.robot_radius = radius;
      FeatureExtractor extractor(params);
      Features features;
      std::string error;
      ASSERT_TRUE(extractor.extract(makeView(spec, ranges), &features, &error)) << error;
      const bool fits = depth >= 2.0 * radius;
      EXPECT_EQ(openingsNear(features, pointInSensorFrame({9.5, 2.0}, sensor), 0.6).size(), fits ? 1u : 0u);
    }
  }
}

// Width cannot tell a double door from a narrow hallway's mouth (BuildingRules); the room behind
// does: seen from along the hallway, the free space behind a door reaches past its edges.
TEST(OpeningExtractor, ADoubleDoorIntoARoomIsADoorSeenFromAlongTheHallway) {
  std::mt19937 rng(11);
  for (const double width : {1.4, 1.6, 1.8}) {
    for (const double sensor_x : {7.0, 8.0, 12.0, 13.0}) {
      const World world = hallwayWithSideDoor(10.0, width);
      const Pose2D sensor{sensor_x, 1.0, 0.3};
      const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
      SCOPED_TRACE(testing::Message() << width << " m door, sensor at x " << sensor_x);
      const std::vector<Opening> near = openingsNear(features, pointInSensorFrame({10.0, 2.0}, sensor), 0.6);
      ASSERT_EQ(near.size(), 1u);
      EXPECT_TRUE(near[0].room_behind);
      EXPECT_EQ(near[0].kind, OpeningKind::kDoor);
      EXPECT_NEAR(near[0].width, width, BuildingRules().width_tolerance);
    }
  }
}

/// A hallway along x (y in [0, 2]) with a hallway `width` wide leaving its upper wall at x = 10 at
/// `angle` to it (pi/2: square); its mouth is width / sin(angle) along the wall.
World hallwayWithBranch(double width, double angle) {
  World world;
  const double mouth = width / std::sin(angle);
  const Eigen::Vector2d a(10.0 - mouth / 2, 2.0), b(10.0 + mouth / 2, 2.0), dir(std::cos(angle), std::sin(angle));
  world.addWall(0, 0, 30, 0);
  world.addWall(0, 2, a.x(), 2);
  world.addWall(b.x(), 2, 30, 2);
  world.addWall(a.x(), a.y(), a.x() + 10 * dir.x(), a.y() + 10 * dir.y());
  world.addWall(b.x(), b.y(), b.x() + 10 * dir.x(), b.y() + 10 * dir.y());
  world.addWall(0, 0, 0, 2);
  world.addWall(30, 0, 30, 2);
  return world;
}

TEST(OpeningExtractor, AHallwayAsNarrowAsADoubleDoorIsAJunctionSquareOrSlanted) {
  std::mt19937 rng(12);
  for (const double angle : {0.5 * kPi, 60.0 * kPi / 180.0, 120.0 * kPi / 180.0}) {
    for (const double width : {1.5, 1.6}) {
      for (const double sensor_x : {6.0, 7.0, 8.0, 10.0, 12.0, 13.0, 14.0}) {
        const World world = hallwayWithBranch(width, angle);
        const Pose2D sensor{sensor_x, 1.0, 0.3};
        const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
        SCOPED_TRACE(testing::Message() << width << " m hallway at " << angle * 180.0 / kPi << " deg, sensor at x "
                                        << sensor_x);
        for (const Opening& o : openingsNear(features, pointInSensorFrame({10.0, 2.0}, sensor), 0.6)) {
          EXPECT_FALSE(o.room_behind);
          EXPECT_NE(o.kind, OpeningKind::kDoor) << o.width << " m wide";
        }
      }
    }
  }
}

TEST(OpeningExtractor, TheNarrowestDoorAndTwoDoorsOnePointTwoMetresApartAreDoors) {
  std::mt19937 rng(13);
  // A hallway along x (y in [0, 2]) with a 0.7 m door at x = 10 and a 0.9 m door at x = 11.2 in its
  // upper wall, into two rooms divided at x = 10.55: the doors' centres 1.2 m apart on one wall.
  World world;
  world.addWall(0, 0, 30, 0);
  world.addWall(0, 2, 9.65, 2);
  world.addWall(10.35, 2, 10.75, 2);
  world.addWall(11.65, 2, 30, 2);
  world.addWall(10.55, 2, 10.55, 6);  // the divider between the rooms
  world.addWall(7, 2, 7, 6);
  world.addWall(14, 2, 14, 6);
  world.addWall(7, 6, 14, 6);
  world.addWall(0, 0, 0, 2);
  world.addWall(30, 0, 30, 2);
  for (const double sensor_x : {8.5, 10.6, 12.5}) {
    const Pose2D sensor{sensor_x, 1.0, 0.0};
    const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
    SCOPED_TRACE(sensor_x);
    for (const auto& [x, width] : {std::pair{10.0, 0.7}, std::pair{11.2, 0.9}}) {
      const std::vector<Opening> near = openingsNear(features, pointInSensorFrame({x, 2.0}, sensor), 0.5);
      ASSERT_EQ(near.size(), 1u) << "the door at x " << x;
      // Seen from beside the other door, the 0.4 m of wall between them makes too short a segment
      // to show that its end is a wall end: the farther door may be an occlusion gap (unknown),
      // which is tracked by its width; never a junction.
      EXPECT_NE(near[0].kind, OpeningKind::kJunction) << "the door at x " << x;
      EXPECT_TRUE(BuildingRules().doorByWidth(near[0].width)) << "the door at x " << x;
      EXPECT_NEAR(near[0].width, width, BuildingRules().width_tolerance) << "the door at x " << x;
    }
  }
}

// Cue (c): the upper hallway wall steps back by 0.3 m across a 1 m gap (a recessed side door);
// the two wall pieces are parallel to the hallway but not collinear.
TEST(OpeningExtractor, HallwayStepIsFound) {
  World world;
  world.addWall(0, 0, 30, 0);
  world.addWall(0, 2, 9, 2);
  world.addWall(10, 2.3, 30, 2.3);
  world.addWall(7, 2, 7, 6);  // the room behind the gap
  world.addWall(13, 2.3, 13, 6);
  world.addWall(7, 6, 13, 6);
  world.addWall(0, 0, 0, 2);
  world.addWall(30, 0, 30, 2.3);
  std::mt19937 rng(8);
  const Pose2D sensor{6.0, 0.6, 0.0};
  const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
  ASSERT_EQ(features.place_type, PlaceType::kHallway);
  const std::vector<Opening> near = openingsNear(features, pointInSensorFrame({9.5, 2.15}, sensor), 0.4);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near[0].source, OpeningSource::kHallwayStep);
  EXPECT_NEAR(near[0].width, std::hypot(1.0, 0.3), 0.05);
  EXPECT_EQ(near[0].kind, OpeningKind::kDoor);
  EXPECT_NEAR(normalizeAngle(near[0].theta - (kPi / 2 + std::atan(0.3))), 0.0, 0.05);  // normal of the gap
}

// A door is set in a wall: a wall piece runs on from one of its edges along it. Next to a corner
// the jamb on that side (0.3 m) is shorter than a line, so no gap between two pieces of one wall is
// seen; the wall on its other side still sets it in the wall. The gaps between a table's legs,
// door-wide, are in no wall.
TEST(OpeningExtractor, ADoorNextToACornerIsInAWallAndAGapBetweenLegsIsNot) {
  std::mt19937 rng(8);
  const World corner_door = roomWithDoor(0.75, 0.9);  // the door's lower jamb: 0.3 m to the corner
  for (const Pose2D& sensor : {Pose2D{2.0, 3.0, 0.2}, Pose2D{1.0, 1.0, -0.4}, Pose2D{3.5, 4.0, 1.0}}) {
    const Features features = extractFeatures(corner_door, sensor, ScanSpec::full(720), &rng);
    const std::vector<Opening> near = openingsNear(features, pointInSensorFrame({6.0, 0.75}, sensor), 0.6);
    ASSERT_EQ(near.size(), 1u) << sensor.x << " " << sensor.y;
    EXPECT_NE(near[0].source, OpeningSource::kCollinearGap) << sensor.x << " " << sensor.y;
    EXPECT_TRUE(near[0].in_wall) << sensor.x << " " << sensor.y;
  }
  World legs = rectangularRoom(8.0, 6.0);
  for (const double x : {3.0, 3.8})  // a table's legs, 0.8 m apart
    for (const double y : {3.0, 3.8}) legs.addBox(x, y, 0.05, 0.05);
  const Pose2D sensor{1.0, 3.4, 0.0};
  const Features features = extractFeatures(legs, sensor, ScanSpec::full(720), &rng);
  ASSERT_FALSE(openingsNear(features, pointInSensorFrame({3.4, 3.4}, sensor), 0.6).empty());  // seen door-wide
  for (const Opening& opening : features.openings) EXPECT_FALSE(opening.in_wall) << opening.center.transpose();
}

TEST(OpeningExtractor, NoOpeningInAClosedRoom) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    const World room = rectangularRoom(6.0, 4.0);
    const Pose2D sensor{1.0 + 0.2 * trial, 1.0 + 0.1 * trial, 0.3 * trial};
    const Features features = extractFeatures(room, sensor, ScanSpec::full(720), &rng);
    EXPECT_TRUE(features.openings.empty()) << "trial " << trial << ": " << features.openings.size();
  }
}

TEST(OpeningExtractor, NoDoorBehindAnOccludingBox) {
  World world = rectangularRoom(8.0, 6.0);
  world.addBox(4.0, 5.4, 1.0, 0.4);  // a cabinet 0.4 m in front of the top wall: it shadows the wall
  std::mt19937 rng(6);
  const Pose2D sensor{4.2, 2.0, 0.0};
  const Features features = extractFeatures(world, sensor, ScanSpec::full(720), &rng);
  for (const Opening& opening : features.openings)
    EXPECT_EQ(opening.kind, OpeningKind::kUnknown) << opening.center.transpose() << " width " << opening.width;
}

TEST(OpeningExtractor, HalfScanSeesTheDoorToo) {
  std::mt19937 rng(7);
  const World world = roomWithDoor(2.5, 0.9);
  const Pose2D sensor{2.5, 2.0, 0.1};
  for (const bool clockwise : {true, false}) {
    const Features features = extractFeatures(world, sensor, ScanSpec::half(361, clockwise), &rng);
    expectOpening(features, sensor, {6.0, 2.5}, 0.9, 0.0, OpeningKind::kDoor);
  }
}

}  // namespace
}  // namespace laser_features
