// PassivePlaces: places entered and left from the scans' place type with hysteresis, the door node
// passed, re-entry through a known door; and config/replay_places.yaml against the code's defaults.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <string>
#include <type_traits>

#include "exploration/passive_places.h"

namespace exploration {
namespace {

// Drives along x at `step` m per scan, feeding scans of one type.
PassivePlacesParams shortRows() {
  PassivePlacesParams p;  // rows of 3 scans over 0.5 m: the arithmetic below stays simple
  p.enter_distance = 0.5;
  p.leave_distance = 0.5;
  return p;
}

struct Drive {
  PassivePlaces places{shortRows()};
  double x = 0.0;
  double step = 0.3;
  double theta = 0.0;

  PlaceAction scan(ScanPlace type, double confidence = 0.9, int door = -1) {
    PlaceObservation o;
    x += step;
    o.odom = Pose2D{x, 0.0, theta};
    o.type = type;
    o.confidence = confidence;
    o.door_node = door;
    o.heading_map = 1.0;
    return places.update(o);
  }
  // Feeds `n` scans of `type`; returns the first action that is not None (None if there is none).
  PlaceAction scans(int n, ScanPlace type, double confidence = 0.9, int door = -1) {
    for (int k = 0; k < n; ++k) {
      const PlaceAction a = scan(type, confidence, door);
      if (a.kind != PlaceAction::None) return a;
    }
    return {};
  }
};

TEST(PassivePlaces, DefaultsAreValidAndBadOnesRefused) {
  std::string why;
  EXPECT_TRUE(PassivePlaces::validate(PassivePlacesParams(), &why)) << why;
  PassivePlacesParams p;
  p.enter_scans = 0;
  EXPECT_FALSE(PassivePlaces::validate(p, &why));
  p = PassivePlacesParams();
  p.room_confidence = 1.5;
  EXPECT_FALSE(PassivePlaces::validate(p, &why));
  p = PassivePlacesParams();
  p.relocation_sigma_xy = 0.0;
  EXPECT_FALSE(PassivePlaces::validate(p, &why));
  p = PassivePlacesParams();
  p.door_memory = NAN;
  EXPECT_FALSE(PassivePlaces::validate(p, &why));
}

TEST(PassivePlaces, EntersAfterEnoughRoomScansAndDistance) {
  Drive d;
  EXPECT_EQ(d.scans(10, ScanPlace::Hallway).kind, PlaceAction::None);
  // Two room scans are not enough (enter_scans 3).
  EXPECT_EQ(d.scans(2, ScanPlace::Room).kind, PlaceAction::None);
  const PlaceAction a = d.scan(ScanPlace::Room);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_EQ(a.door_node, -1);
  EXPECT_EQ(a.known_place, -1);
  // The doorway is where the streak began: 2 steps behind the robot.
  EXPECT_NEAR(a.door_in_robot.x, -0.6, 1e-9);
  EXPECT_NEAR(a.robot_from_door.x, 0.6, 1e-9);
  EXPECT_NEAR(a.door_bearing_map, 1.0, 1e-9);
}

TEST(PassivePlaces, StandingStillDoesNotEnter) {
  Drive d;
  d.step = 0.0;  // the same pose over and over: enter_distance is not travelled
  EXPECT_EQ(d.scans(50, ScanPlace::Room).kind, PlaceAction::None);
  d.step = 0.3;
  EXPECT_EQ(d.scans(3, ScanPlace::Room).kind, PlaceAction::Enter);
}

TEST(PassivePlaces, HysteresisUnsureScansNeitherCountNorBreak) {
  Drive d;
  d.scans(2, ScanPlace::Room);
  EXPECT_EQ(d.scans(5, ScanPlace::Room, 0.3).kind, PlaceAction::None);  // unsure: not counted
  EXPECT_EQ(d.scans(5, ScanPlace::Unknown).kind, PlaceAction::None);
  EXPECT_EQ(d.scan(ScanPlace::Room).kind, PlaceAction::Enter);  // the streak held
  // A confident hallway scan breaks a room streak.
  Drive e;
  e.scans(2, ScanPlace::Room);
  e.scan(ScanPlace::Hallway);
  EXPECT_EQ(e.scans(2, ScanPlace::Room).kind, PlaceAction::None);
  EXPECT_EQ(e.scan(ScanPlace::Room).kind, PlaceAction::Enter);
}

TEST(PassivePlaces, LeavesAfterEnoughHallwayScans) {
  Drive d;
  ASSERT_EQ(d.scans(5, ScanPlace::Room).kind, PlaceAction::Enter);
  d.places.entered(7, -1);
  EXPECT_TRUE(d.places.inPlace());
  EXPECT_EQ(d.places.place(), 7);
  EXPECT_EQ(d.scans(20, ScanPlace::Room).kind, PlaceAction::None);  // in the room: nothing to do
  EXPECT_EQ(d.scans(2, ScanPlace::Hallway).kind, PlaceAction::None);
  d.scan(ScanPlace::Room);  // breaks the hallway streak
  EXPECT_EQ(d.scans(2, ScanPlace::Hallway).kind, PlaceAction::None);
  EXPECT_EQ(d.scan(ScanPlace::Hallway).kind, PlaceAction::Leave);
  d.places.left();
  EXPECT_FALSE(d.places.inPlace());
  EXPECT_EQ(d.places.placesEntered(), 1);
}

TEST(PassivePlaces, FailedEntryRestartsTheStreak) {
  Drive d;
  ASSERT_EQ(d.scans(5, ScanPlace::Room).kind, PlaceAction::Enter);
  d.places.entered(-1, -1);
  EXPECT_FALSE(d.places.inPlace());
  EXPECT_EQ(d.scans(2, ScanPlace::Room).kind, PlaceAction::None);
  EXPECT_EQ(d.scan(ScanPlace::Room).kind, PlaceAction::Enter);
}

TEST(PassivePlaces, DoorPassedShortlyBeforeIsTheRoomsDoor) {
  Drive d;
  d.scans(3, ScanPlace::Hallway, 0.9, 4);  // at door node 4
  d.scans(3, ScanPlace::Hallway);          // 0.9 m further
  const PlaceAction a = d.scans(5, ScanPlace::Room);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_EQ(a.door_node, 4);
  EXPECT_EQ(a.known_place, -1);
  // A door passed long before is not.
  Drive far;
  far.scans(3, ScanPlace::Hallway, 0.9, 4);
  far.scans(30, ScanPlace::Hallway);  // 9 m > door_memory
  EXPECT_EQ(far.scans(5, ScanPlace::Room).door_node, -1);
}

TEST(PassivePlaces, ReentryThroughAKnownDoorNamesItsPlace) {
  Drive d;
  d.scans(2, ScanPlace::Hallway, 0.9, 4);
  PlaceAction a = d.scans(5, ScanPlace::Room);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  d.places.entered(0, a.door_node);
  EXPECT_EQ(d.places.placeOfDoor(4), 0);
  ASSERT_EQ(d.scans(5, ScanPlace::Hallway).kind, PlaceAction::Leave);
  d.places.left();
  // Back in the hallway the belief sits on door 4 again: not a way into the next room...
  d.scans(2, ScanPlace::Hallway, 0.9, 4);
  a = d.scans(5, ScanPlace::Room);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_EQ(a.door_node, -1);
  d.places.entered(1, -1);
  d.scans(5, ScanPlace::Hallway);
  d.places.left();
  // ...but after the belief moved on, passing door 4 again leads into place 0.
  d.scans(10, ScanPlace::Hallway);
  d.scans(2, ScanPlace::Hallway, 0.9, 4);
  a = d.scans(5, ScanPlace::Room);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  EXPECT_EQ(a.door_node, 4);
  EXPECT_EQ(a.known_place, 0);
}

TEST(PassivePlaces, LinksFromTheMapAreUsed) {
  Drive d;
  d.places.linkDoor(9, 3);
  d.scans(2, ScanPlace::Hallway, 0.9, 9);
  const PlaceAction a = d.scans(5, ScanPlace::Room);
  EXPECT_EQ(a.known_place, 3);
}

TEST(PassivePlaces, RelocationPoseIsTheDoorsInverse) {
  Drive d;
  d.theta = 0.5;
  const PlaceAction a = d.scans(5, ScanPlace::Room);
  ASSERT_EQ(a.kind, PlaceAction::Enter);
  const Pose2D back = laser_features::compose(a.door_in_robot, a.robot_from_door);
  EXPECT_NEAR(back.x, 0.0, 1e-9);
  EXPECT_NEAR(back.y, 0.0, 1e-9);
  EXPECT_NEAR(back.theta, 0.0, 1e-9);
}

TEST(PassivePlaces, DefaultRowsNeedTheirDistance) {
  PassivePlaces places;  // enter_distance 1.5 m
  PlaceObservation o;
  o.type = ScanPlace::Room;
  o.confidence = 0.9;
  int scans = 0;
  for (; scans < 50; ++scans) {
    o.odom.x += 0.1;
    if (places.update(o).kind == PlaceAction::Enter) break;
  }
  EXPECT_EQ(scans, 15);  // the 16th scan, 1.5 m after the first
}

TEST(PassivePlaces, NonFinitePoseIsIgnored) {
  PassivePlaces places;
  PlaceObservation o;
  o.odom.x = NAN;
  o.type = ScanPlace::Room;
  o.confidence = 1.0;
  for (int k = 0; k < 10; ++k) EXPECT_EQ(places.update(o).kind, PlaceAction::None);
  EXPECT_EQ(places.travel(), 0.0);
}

// config/replay_places.yaml documents every parameter with the code's default.
TEST(PassivePlacesConfig, YamlDefaultsEqualTheCodeDefaults) {
  const YAML::Node root = YAML::LoadFile(REPLAY_PLACES_CONFIG_FILE);
  PassivePlacesParams params;
  std::set<std::string> visited;
  visitPassivePlacesParams(&params, [&](const char* name, auto* value) {
    visited.insert(name);
    const YAML::Node node = root[name];
    ASSERT_TRUE(node.IsDefined() && node.IsScalar()) << name << " is not documented in " << REPLAY_PLACES_CONFIG_FILE;
    using T = std::remove_pointer_t<decltype(value)>;
    EXPECT_NEAR(static_cast<double>(node.as<T>()), static_cast<double>(*value), 1e-12) << name;
  });
  DoorCrossingsParams crossing;
  visitDoorCrossingsParams(&crossing, [&](const char* name, double* value) {
    visited.insert(name);
    ASSERT_TRUE(root[name].IsDefined()) << name << " is not documented in " << REPLAY_PLACES_CONFIG_FILE;
    EXPECT_NEAR(root[name].as<double>(), *value, 1e-12) << name;
  });
  // The node's own parameters (replay_places_node.cpp, same defaults).
  const std::set<std::string> node_keys = {"topo_node", "local_map_node", "odom_frame", "base_frame",
                                           "mapping", "bag_end_time", "end_tolerance", "end_grace", "end_idle_timeout",
                                           "service_timeout", "summary_file"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    EXPECT_TRUE(visited.count(key) || node_keys.count(key)) << "unknown key " << key;
  }
  for (const std::string& key : node_keys) EXPECT_TRUE(root[key].IsDefined()) << key << " is not documented";
}

}  // namespace
}  // namespace exploration
