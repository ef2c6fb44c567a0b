// The building rules live once: config/building.yaml holds every rule with the code's default, and
// no node's own YAML restates one (nor the heading bins and the building's axis, which are
// pomdp_topo's alone); the rules' door test itself.
#include "laser_features/building_rules.h"
#include "laser_features/opening_tracks.h"
#include "laser_features/robot_footprint.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <string>

namespace {

using laser_features::BuildingRules;

/// config/<file> holds every value `visit` visits in `values`, with its default there, and no other.
template <typename T, typename Visit>
void expectTheYamlHoldsTheDefaults(const std::string& file, T* values, Visit visit) {
  const YAML::Node root = YAML::LoadFile(std::string(CONFIG_DIR) + "/" + file);
  std::set<std::string> visited;
  visit(values, [&](const char* name, auto* value) {
    visited.insert(name);
    ASSERT_TRUE(root[name].IsDefined()) << name << " is not in " << file;
    EXPECT_DOUBLE_EQ(root[name].as<double>(), double(*value)) << name;
  });
  for (const auto& kv : root) EXPECT_TRUE(visited.count(kv.first.as<std::string>())) << "unknown key " << kv.first;
}

TEST(BuildingRules, TheYamlHoldsEveryRuleWithTheCodesDefault) {
  BuildingRules rules;
  expectTheYamlHoldsTheDefaults("building.yaml", &rules,
                                [](BuildingRules* r, auto&& f) { laser_features::visitBuildingRules(r, f); });
}

/// Every key (at any depth, "a/b" for nested ones) of a YAML node.
void keys(const YAML::Node& node, const std::string& prefix, std::set<std::string>* out) {
  if (!node.IsMap()) return;
  for (const auto& kv : node) {
    const std::string k = kv.first.as<std::string>();
    out->insert(k);
    keys(kv.second, prefix + k + "/", out);
  }
}

TEST(BuildingRules, NoNodesYamlRestatesThem) {
  std::set<std::string> rules;
  BuildingRules r;
  laser_features::visitBuildingRules(&r, [&](const char* name, auto*) { rules.insert(name); });
  rules.insert("min_width");  // the narrowest opening is the narrowest door
  const std::set<std::string> pomdp_topo_only = {"axis_angle", "heading_bins"};
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CONFIG_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().filename().string();
    if (name == "building.yaml") continue;
    ++files;
    std::set<std::string> found;
    keys(YAML::LoadFile(entry.path().string()), "", &found);
    for (const std::string& k : rules) EXPECT_FALSE(found.count(k)) << name << " restates the building rule " << k;
    if (name != "pomdp_topo.yaml") {
      for (const std::string& k : pomdp_topo_only) EXPECT_FALSE(found.count(k)) << name << " restates pomdp_topo's " << k;
    }
  }
  EXPECT_GE(files, 4);
}

// The robot's footprint lives once too: config/robot.yaml with the code's defaults, and no node's
// YAML holds a radius or a safety margin of its own.
TEST(RobotFootprint, TheYamlHoldsItWithTheCodesDefaultAndNoNodesYamlRestatesIt) {
  laser_features::RobotFootprint footprint;
  expectTheYamlHoldsTheDefaults("robot.yaml", &footprint, [](laser_features::RobotFootprint* r, auto&& f) {
    laser_features::visitRobotFootprint(r, f);
  });
  EXPECT_TRUE(footprint.valid());
  for (const auto& entry : std::filesystem::directory_iterator(CONFIG_DIR)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".yaml" || name == "robot.yaml") continue;
    std::set<std::string> found;
    keys(YAML::LoadFile(entry.path().string()), "", &found);
    for (const char* k : {"robot_radius", "safety_margin", "radius"})
      EXPECT_FALSE(found.count(k)) << name << " restates the robot's footprint (" << k << ")";
  }
}

// How openings are tracked lives once too: config/opening_tracks.yaml with the code's defaults, and
// no node's YAML holds a tracking value of its own (pomdp_topo's front end and the exploration's door
// tracker both read these).
TEST(OpeningTracks, TheYamlHoldsThemWithTheCodesDefaultsAndNoNodesYamlRestatesThem) {
  laser_features::OpeningTracks tracks;
  expectTheYamlHoldsTheDefaults("opening_tracks.yaml", &tracks, [](laser_features::OpeningTracks* t, auto&& f) {
    laser_features::visitOpeningTracks(t, f);
  });
  EXPECT_TRUE(tracks.valid());
  std::set<std::string> names = {"track_keep_distance", "door_side_angle", "door_min_sightings"};
  laser_features::visitOpeningTracks(&tracks, [&](const char* name, auto*) { names.insert(name); });
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(CONFIG_DIR)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".yaml" || name == "opening_tracks.yaml") continue;
    ++files;
    std::set<std::string> found;
    keys(YAML::LoadFile(entry.path().string()), "", &found);
    for (const std::string& k : names) EXPECT_FALSE(found.count(k)) << name << " restates the opening tracks' " << k;
  }
  EXPECT_GE(files, 4);
}

TEST(OpeningTracks, OutOfRangeValuesAreRefusedWithTheirNamespace) {
  laser_features::OpeningTracks t;
  t.min_sightings = 0;
  std::string why;
  EXPECT_FALSE(t.valid(&why));
  EXPECT_NE(why.find("opening_tracks/min_sightings"), std::string::npos) << why;
  t = laser_features::OpeningTracks();
  t.side_angle = 1.6;
  EXPECT_FALSE(t.valid());
  t = laser_features::OpeningTracks();
  t.keep_distance = std::nan("");
  EXPECT_FALSE(t.valid());
}

// A door is entered after it is passed: the exploration turns back to it only once pomdp_topo's
// front end has made its node (enter_lag > pass_lag), else the entry marks explored an opening of
// the node before and the door's own node, made later, stays unexplored (the room mapped twice).
TEST(OpeningTracks, ADoorIsEnteredOnlyAfterItIsPassed) {
  laser_features::OpeningTracks t;
  EXPECT_GT(t.enter_lag, t.pass_lag);
  t.enter_lag = t.pass_lag;
  std::string why;
  EXPECT_FALSE(t.valid(&why));
  EXPECT_NE(why.find("opening_tracks/enter_lag"), std::string::npos) << why;
  t.enter_lag = t.pass_lag + 0.05;
  EXPECT_TRUE(t.valid());
  t.pass_lag = -0.1;
  EXPECT_FALSE(t.valid());
}

TEST(BuildingRules, NarrowerThanAnyHallwayIsADoorAndADoubleDoorsWidthNeedsARoomBehind) {
  const BuildingRules rules;
  EXPECT_FALSE(rules.isDoor(0.6, true));   // too narrow to pass
  EXPECT_TRUE(rules.isDoor(0.7, false));   // the narrowest single door
  EXPECT_TRUE(rules.isDoor(1.2, false));
  EXPECT_TRUE(rules.isDoor(1.35, false));  // narrower than any hallway's mouth, measured
  EXPECT_FALSE(rules.isDoor(1.6, false));  // a 1.5 m hallway's mouth, or a double door ...
  EXPECT_TRUE(rules.isDoor(1.6, true));    // ... that opens into a room
  EXPECT_TRUE(rules.isDoor(1.85, true));   // the widest double door, measured
  EXPECT_FALSE(rules.isDoor(2.0, true));   // a hallway's mouth, whatever is seen behind
  EXPECT_FALSE(rules.isDoorTracked(1.6, 1));  // one scan is no room
  EXPECT_TRUE(rules.isDoorTracked(1.6, 2));
  EXPECT_TRUE(rules.isDoorTracked(0.9, 0));
  // A door beside a branch is told apart from it; one opening measured twice is not.
  EXPECT_TRUE(rules.differentOpenings(0.9, 2.18));
  EXPECT_FALSE(rules.differentOpenings(0.66, 1.28));
  EXPECT_FALSE(rules.differentOpenings(0.0, 2.18));
  // Two doors' widths are apart beyond one door's spread; an unmeasured width is apart from none.
  EXPECT_TRUE(rules.widthsApart(0.81, 1.76));
  EXPECT_FALSE(rules.widthsApart(1.79, 1.76));
  EXPECT_FALSE(rules.widthsApart(0.0, 1.76));
}

// A hallway whose mouth is as narrow as the widest door leaves the wall at asin(1.5 / 1.9) = 52 deg
// at the least: its walls run 0.78 m beyond the mouth's edges per metre of depth at the most.
TEST(BuildingRules, TheSteepestBranchADoorCouldBeRunsItsWallsSoFarBeyondItsMouth) {
  const BuildingRules rules;
  const double phi = std::asin(1.5 / 1.9);
  EXPECT_NEAR(rules.branchSpread(), std::cos(phi) / std::sin(phi), 1e-12);
  EXPECT_NEAR(rules.branchSpread(), 0.777, 0.001);
}

// A door in a wall across a hallway leaves door_jamb_min (0.2 m) of that wall on each side: in a
// 1.7 m hallway a door up to 1.5 m fits (the widths' errors, 0.1 m each, allowed for), a 1.6 m
// opening is the hallway's mouth; a jamb of 1 m leaves no door in the narrowest hallway.
TEST(BuildingRules, ADoorInAnEndWallIsNarrowerThanTheHallwayByTwoJambs) {
  BuildingRules rules;
  EXPECT_TRUE(rules.fitsInEndWall(0.9, 1.7));
  EXPECT_TRUE(rules.fitsInEndWall(1.45, 1.7));
  EXPECT_FALSE(rules.fitsInEndWall(1.6, 1.7));
  EXPECT_FALSE(rules.fitsInEndWall(1.7, 1.7));
  EXPECT_TRUE(rules.fitsInEndWall(1.8, 2.4));
  rules.door_jamb_min = 1.0;
  std::string why;
  EXPECT_FALSE(rules.valid(&why));
  EXPECT_NE(why.find("door_jamb_min"), std::string::npos);
}

// A door's centre lies half the narrowest door and a frame from the corner of its wall: 0.55 m with
// the office defaults; a wider frame moves it out with it.
TEST(BuildingRules, ADoorsCentreLiesHalfADoorAndAFrameFromItsWallsCorner) {
  BuildingRules rules;
  EXPECT_NEAR(rules.doorFromCorner(), 0.55, 1e-12);
  rules.door_jamb_min = 0.3;
  EXPECT_NEAR(rules.doorFromCorner(), 0.65, 1e-12);
}

TEST(BuildingRules, NoInvertedRange) {
  const BuildingRules rules;
  EXPECT_TRUE(rules.valid());
  BuildingRules bad;
  bad.door_max_width = 0.5;
  std::string why;
  EXPECT_FALSE(bad.valid(&why));
  EXPECT_NE(why.find("door_max_width"), std::string::npos);
}

}  // namespace
