// DoorCrossings: a door the recorded path went through, from the doors seen before the step; and the
// place decisions a crossing makes in PassivePlaces.
#include <gtest/gtest.h>

#include <cmath>

#include "exploration/door_crossings.h"
#include "exploration/passive_places.h"

namespace exploration {
namespace {

// A door 0.9 m wide across the x axis at x = `at` (robot frame of a robot at the origin facing +x).
DoorSighting doorAhead(double at, double y = 0.0, double width = 0.9) {
  return {at, y + 0.5 * width, at, y - 0.5 * width};
}

TEST(DoorCrossings, AStepThroughADoorSeenAheadIsACrossing) {
  DoorCrossings c;
  EXPECT_FALSE(c.update({0.0, 0.0, 0.0}, {doorAhead(2.0)}));
  EXPECT_FALSE(c.update({1.0, 0.0, 0.0}, {}));
  const auto x = c.update({2.6, 0.1, 0.0}, {});
  ASSERT_TRUE(x);
  EXPECT_NEAR(x->door_odom.x, 2.0, 1e-9);
  EXPECT_NEAR(x->door_odom.y, 0.0, 1e-9);
  EXPECT_NEAR(x->door_odom.theta, 0.0, 1e-9);  // the door's normal, the way the robot went
  EXPECT_NEAR(x->width, 0.9, 1e-9);
  EXPECT_EQ(x->sightings, 1);
}

TEST(DoorCrossings, SightingsFromSeveralScansAreOneCrossing) {
  DoorCrossings c;
  c.update({0.0, 0.0, 0.0}, {doorAhead(3.0, 0.02)});
  c.update({1.0, 0.0, 0.0}, {doorAhead(2.0, -0.02)});
  const auto x = c.update({3.5, 0.0, 0.0}, {});
  ASSERT_TRUE(x);
  EXPECT_EQ(x->sightings, 2);
  EXPECT_NEAR(x->door_odom.x, 3.0, 1e-9);
  EXPECT_NEAR(x->door_odom.y, 0.0, 1e-9);
  EXPECT_FALSE(c.update({4.5, 0.0, 0.0}, {}));  // crossed once
}

TEST(DoorCrossings, AStepPastADoorsEdgeIsNoCrossing) {
  DoorCrossings c;  // the door lies beside the path: its line is crossed 0.55 m outside its edge
  c.update({0.0, 0.0, 0.0}, {doorAhead(2.0, 1.0)});
  EXPECT_FALSE(c.update({3.0, 0.0, 0.0}, {}));
  DoorCrossings near;  // 0.15 m outside, within the edge margin (0.2 m): crossed
  near.update({0.0, 0.0, 0.0}, {doorAhead(2.0, 0.6)});
  EXPECT_TRUE(near.update({3.0, 0.0, 0.0}, {}));
}

TEST(DoorCrossings, SightingsOlderThanTheMemoryAreForgotten) {
  DoorCrossingsParams p;
  p.memory = 5.0;
  DoorCrossings c(p);
  c.update({0.0, 0.0, 0.0}, {doorAhead(7.5)});
  for (double x = 1.0; x <= 7.0; x += 1.0) EXPECT_FALSE(c.update({x, 0.0, 0.0}, {}));
  EXPECT_FALSE(c.update({8.0, 0.0, 0.0}, {}));  // seen 8 m of travel ago
}

TEST(DoorCrossings, CrossingBackNeedsTheDoorSeenAgainAndPointsBack) {
  DoorCrossings c;
  c.update({1.0, 0.0, 0.0}, {doorAhead(1.0)});
  ASSERT_TRUE(c.update({2.5, 0.0, 0.0}, {}));
  EXPECT_FALSE(c.update({1.5, 0.0, 0.0}, {}));  // back through it, not seen since
  // Turned round at x = 2.5, it sees the door 1 m ahead (robot frame) and goes through it again.
  c.update({2.5, 0.0, M_PI}, {doorAhead(1.0)});
  const auto x = c.update({0.5, 0.0, M_PI}, {});
  ASSERT_TRUE(x);
  EXPECT_NEAR(x->door_odom.x, 1.5, 1e-9);
  EXPECT_NEAR(std::abs(x->door_odom.theta), M_PI, 1e-9);
}

TEST(DoorCrossings, ASightingMovesFromTheSensorsFrameToTheRobots) {
  // A scanner 0.2 m ahead of the robot's centre, turned 90 deg to the left.
  const DoorSighting d = inRobotFrame({0.2, 0.0, M_PI / 2}, {2.0, 0.45, 2.0, -0.45});
  EXPECT_NEAR(d.left_x, -0.25, 1e-9);
  EXPECT_NEAR(d.left_y, 2.0, 1e-9);
  EXPECT_NEAR(d.right_x, 0.65, 1e-9);
  EXPECT_NEAR(d.right_y, 2.0, 1e-9);
}

TEST(DoorCrossings, BadParametersAndPosesAreRefused) {
  std::string why;
  EXPECT_TRUE(DoorCrossings::validate(DoorCrossingsParams(), &why)) << why;
  DoorCrossingsParams p;
  p.memory = 0.0;
  EXPECT_FALSE(DoorCrossings::validate(p, &why));
  p = DoorCrossingsParams();
  p.edge_margin = -0.1;
  EXPECT_FALSE(DoorCrossings::validate(p, &why));
  DoorCrossings c;
  EXPECT_FALSE(c.update({NAN, 0.0, 0.0}, {doorAhead(1.0)}));
  EXPECT_EQ(c.remembered(), 0u);
}

// --- PassivePlaces with crossings ------------------------------------------------------------------

PlaceObservation scanAt(double x, double y, double theta, ScanPlace type, double confidence = 0.9) {
  PlaceObservation o;
  o.odom = Pose2D{x, y, theta};
  o.type = type;
  o.confidence = confidence;
  return o;
}

PlaceObservation crossingAt(double x, double y, double theta, double door_x, double door_y, double door_theta,
                            ScanPlace type = ScanPlace::Room) {
  PlaceObservation o = scanAt(x, y, theta, type);
  DoorCrossing c;
  c.door_odom = Pose2D{door_x, door_y, door_theta};
  c.width = 0.9;
  c.sightings = 2;
  o.crossing = c;
  return o;
}

// From the hallway through the door at (1, 0.8) (facing +y) into `place`, and back out.
void visitRoomAtDoor(PassivePlaces* places, int place) {
  const int door = PassivePlacesParams().path_door_id_base;
  places->update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  places->update(crossingAt(1.0, 1.5, M_PI / 2, 1.0, 0.8, M_PI / 2));
  places->entered(place, door);
  places->update(crossingAt(1.0, 0.2, -M_PI / 2, 1.0, 0.8, -M_PI / 2, ScanPlace::Hallway));
  places->left();
}

TEST(PassivePlacesCrossings, ADoorCrossingEntersAtOnceWithTheDoorWhereItWasCrossed) {
  PassivePlaces places;
  places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  // Turned into a door at (1, 0.8), facing +y, and went through it to (1, 1.5).
  const PlaceAction a = places.update(crossingAt(1.0, 1.5, M_PI / 2, 1.0, 0.8, M_PI / 2));
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_FALSE(a.leave_first);
  EXPECT_EQ(a.door_node, -1);
  EXPECT_EQ(a.door_id, PassivePlacesParams().path_door_id_base);
  EXPECT_EQ(a.known_place, -1);
  EXPECT_NEAR(a.door_in_robot.x, -0.7, 1e-9);  // 0.7 m behind the robot, facing the same way
  EXPECT_NEAR(a.door_in_robot.y, 0.0, 1e-9);
  EXPECT_NEAR(a.door_in_robot.theta, 0.0, 1e-9);
  EXPECT_NEAR(a.robot_from_door.x, 0.7, 1e-9);
}

TEST(PassivePlacesCrossings, ACrossingIntoAHallwayLeavesThePlace) {
  PassivePlaces places;
  places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  ASSERT_EQ(places.update(crossingAt(1.0, 1.5, M_PI / 2, 1.0, 0.8, M_PI / 2)).kind, PlaceAction::Enter);
  places.entered(0, PassivePlacesParams().path_door_id_base);
  EXPECT_EQ(places.update(scanAt(1.0, 3.0, M_PI / 2, ScanPlace::Room)).kind, PlaceAction::None);
  const PlaceAction a = places.update(crossingAt(1.0, 0.2, -M_PI / 2, 1.0, 0.8, -M_PI / 2, ScanPlace::Hallway));
  EXPECT_EQ(a.kind, PlaceAction::Leave);
}

TEST(PassivePlacesCrossings, ACrossingFromOnePlaceIntoAnotherLeavesFirst) {
  PassivePlaces places;
  places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  places.update(crossingAt(1.0, 1.5, M_PI / 2, 1.0, 0.8, M_PI / 2));
  places.entered(0, PassivePlacesParams().path_door_id_base);
  // An inner door at (1, 4): into a suite's second room.
  const PlaceAction a = places.update(crossingAt(1.0, 4.6, M_PI / 2, 1.0, 4.0, M_PI / 2));
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_TRUE(a.leave_first);
  EXPECT_EQ(a.door_id, PassivePlacesParams().path_door_id_base + 1);
}

TEST(PassivePlacesCrossings, ACrossingAtAKnownPlacesDoorReentersIt) {
  PassivePlaces places;
  const int door = PassivePlacesParams().path_door_id_base;
  visitRoomAtDoor(&places, 4);
  places.update(scanAt(5.0, 0.0, 0.0, ScanPlace::Hallway));
  places.update(scanAt(1.5, 0.0, M_PI, ScanPlace::Hallway));
  // The same door 0.4 m off in odometry (drift), entered the same way: place 4 again.
  const PlaceAction a = places.update(crossingAt(1.3, 1.4, M_PI / 2, 1.4, 0.7, M_PI / 2 + 0.1));
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_EQ(a.known_place, 4);
  EXPECT_EQ(a.door_id, door);
  places.entered(4, door);
  places.update(crossingAt(1.3, 0.0, -M_PI / 2, 1.4, 0.7, -M_PI / 2, ScanPlace::Hallway));
  places.left();
  // A door 3 m further on is another room's.
  const PlaceAction b = places.update(crossingAt(4.0, 1.5, M_PI / 2, 4.0, 0.8, M_PI / 2));
  ASSERT_EQ(b.kind, PlaceAction::Enter);
  EXPECT_EQ(b.known_place, -1);
  EXPECT_EQ(b.door_id, door + 1);
}

TEST(PassivePlacesCrossings, AKnownDoorIsFoundInMapNotInOdometry) {
  PassivePlaces places;
  const int door = PassivePlacesParams().path_door_id_base;
  visitRoomAtDoor(&places, 2);
  // Odometry has drifted 3 m along x since; ekf_local_map's map -> odom takes it back.
  PlaceObservation o = crossingAt(4.0, 1.5, M_PI / 2, 4.0, 0.8, M_PI / 2);
  o.map_odom = Pose2D{-3.0, 0.0, 0.0};
  const PlaceAction a = places.update(o);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_EQ(a.known_place, 2);
  EXPECT_EQ(a.door_id, door);
}

TEST(PassivePlacesCrossings, OnlyTravelOutsidePlacesWidensTheReentryGate) {
  // A door 2 m off in map: beyond reentry_distance (1 m) unless enough travel outside places
  // (0.03 m per m: 34 m) lies between the crossings; travel in places (the EKF corrected it) does not count.
  for (const bool outside : {false, true}) {
    PassivePlaces places;
    const int door = PassivePlacesParams().path_door_id_base;
    places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
    places.update(crossingAt(1.0, 1.5, M_PI / 2, 1.0, 0.8, M_PI / 2));
    places.entered(0, door);
    if (!outside) {
      for (int k = 1; k <= 40; ++k) places.update(scanAt(1.0 + 0.25 * (k % 2), 1.5 + 0.25 * (k % 2), 0.0, ScanPlace::Room));
    }
    places.update(crossingAt(1.0, 0.2, -M_PI / 2, 1.0, 0.8, -M_PI / 2, ScanPlace::Hallway));
    places.left();
    if (outside) {
      for (int k = 1; k <= 40; ++k) places.update(scanAt(1.0 + (k % 2), 0.0, 0.0, ScanPlace::Hallway));
    }
    places.update(scanAt(3.0, 0.0, M_PI / 2, ScanPlace::Hallway));
    const PlaceAction a = places.update(crossingAt(3.0, 1.5, M_PI / 2, 3.0, 0.8, M_PI / 2));
    ASSERT_EQ(a.kind, PlaceAction::Enter);
    EXPECT_EQ(a.known_place, outside ? 0 : -1) << (outside ? "40 m outside places" : "40 m inside a place");
  }
}

TEST(PassivePlacesCrossings, ARefusedReentryIsANewPlaceBehindTheSameDoor) {
  PassivePlaces places;
  const int door = PassivePlacesParams().path_door_id_base;
  places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  places.update(crossingAt(1.0, 1.5, M_PI / 2, 1.0, 0.8, M_PI / 2));
  EXPECT_EQ(places.reentryRefused({1.0, 1.5, M_PI / 2}).kind, PlaceAction::None);  // a new place: nothing to refuse
  places.entered(3, door);
  places.update(crossingAt(1.0, 0.2, -M_PI / 2, 1.0, 0.8, -M_PI / 2, ScanPlace::Hallway));
  places.left();
  const PlaceAction a = places.update(crossingAt(1.2, 1.5, M_PI / 2, 1.2, 0.8, M_PI / 2));
  ASSERT_EQ(a.known_place, 3);
  places.entered(3, door);
  // ekf_local_map could not relocate: the robot, now at (1.2, 2.5), is in another room behind that door.
  const PlaceAction b = places.reentryRefused({1.2, 2.5, M_PI / 2});
  ASSERT_EQ(b.kind, PlaceAction::Enter);
  EXPECT_TRUE(b.leave_first);
  EXPECT_EQ(b.known_place, -1);
  EXPECT_EQ(b.door_id, door + 1);
  EXPECT_NEAR(b.door_in_robot.x, -1.7, 1e-9);
  EXPECT_NEAR(b.door_in_robot.y, 0.0, 1e-9);
  places.left();
  places.entered(4, b.door_id);
  EXPECT_EQ(places.reentryRefused({1.2, 2.5, M_PI / 2}).kind, PlaceAction::None);  // once only
}

TEST(PassivePlacesCrossings, AReentryFromAnotherPlaceCanBeRefusedToo) {
  // Out of place 3 through an inner door into place 5, known behind it: the caller closes place 3
  // first (leave_first), and a failed relocation in place 5 is still refused.
  PassivePlaces places;
  const int base = PassivePlacesParams().path_door_id_base;
  places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  places.update(crossingAt(1.0, 0.0, 0.0, 0.5, 0.0, 0.0));
  places.entered(5, base);
  places.update(crossingAt(0.0, 0.0, M_PI, 0.5, 0.0, M_PI, ScanPlace::Hallway));
  places.left();
  places.update(crossingAt(-1.0, 1.0, M_PI / 2, -1.0, 0.5, M_PI / 2));
  places.entered(3, base + 1);
  const PlaceAction a = places.update(crossingAt(1.0, 1.0, 0.0, 0.5, 1.0, 0.0));
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  ASSERT_TRUE(a.leave_first);
  ASSERT_EQ(a.known_place, 5);
  places.left();
  places.entered(5, a.door_id);
  EXPECT_EQ(places.reentryRefused({1.5, 1.0, 0.0}).kind, PlaceAction::Enter);
}

TEST(PassivePlacesCrossings, WithoutEnterByTypeOnlyACrossingEnters) {
  PassivePlacesParams p;
  p.enter_by_type = false;
  PassivePlaces places(p);
  for (int k = 0; k < 20; ++k) EXPECT_EQ(places.update(scanAt(0.5 * k, 0.0, 0.0, ScanPlace::Room)).kind, PlaceAction::None);
  EXPECT_EQ(places.update(crossingAt(11.0, 0.0, 0.0, 10.5, 0.0, 0.0)).kind, PlaceAction::Enter);
}

TEST(PassivePlacesCrossings, APlaceIsLeftBeyondTheLargestRoomsExtent) {
  PassivePlacesParams p;
  p.max_place_extent = 12.0;
  PassivePlaces places(p);
  places.update(scanAt(0.0, 0.0, 0.0, ScanPlace::Hallway));
  ASSERT_EQ(places.update(crossingAt(1.0, 0.0, 0.0, 0.5, 0.0, 0.0)).kind, PlaceAction::Enter);
  places.entered(0, p.path_door_id_base);
  // Unsure scans (a cluttered hallway) never make a HALLWAY row; the distance from the entry does.
  for (double x = 2.0; x <= 13.0; x += 1.0)
    EXPECT_EQ(places.update(scanAt(x, 0.0, 0.0, ScanPlace::Hallway, 0.3)).kind, PlaceAction::None) << x;
  EXPECT_EQ(places.update(scanAt(13.5, 0.0, 0.0, ScanPlace::Hallway, 0.3)).kind, PlaceAction::Leave);
}

}  // namespace
}  // namespace exploration
