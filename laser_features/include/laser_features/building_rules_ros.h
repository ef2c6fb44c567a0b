// The building rules, the opening tracks and the robot's footprint read by a node (ROS, not part of the ROS-free core):
// from the `building` and `robot` namespaces (config/building.yaml and config/robot.yaml, loaded
// once by the launch file) relative to the node's namespace, so that robots in their own namespaces
// each have theirs; the code's defaults where a launch loads none. The one reader for every package.
#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>

#include "laser_features/building_rules.h"
#include "laser_features/opening_tracks.h"
#include "laser_features/robot_footprint.h"

namespace laser_features {

/// A shared parameter set T from the namespace `ns`, its values visited by `visit(T*, f)`; throws
/// std::invalid_argument naming the parameter when T::valid says it is out of range.
template <typename T, typename Visit>
T readShared(const ros::NodeHandle& nh, const std::string& ns, Visit visit) {
  T values;
  visit(&values, [&](const char* name, auto* value) { nh.param(ns + "/" + name, *value, *value); });
  std::string why;
  if (!values.valid(&why)) throw std::invalid_argument(why);
  return values;
}

/// The building rules (config/building.yaml, the `building` namespace).
inline BuildingRules readBuildingRules(const ros::NodeHandle& nh) {
  return readShared<BuildingRules>(nh, "building", [](BuildingRules* r, auto&& f) { visitBuildingRules(r, f); });
}

/// How openings are tracked over scans (config/opening_tracks.yaml, the `opening_tracks` namespace).
inline OpeningTracks readOpeningTracks(const ros::NodeHandle& nh) {
  return readShared<OpeningTracks>(nh, "opening_tracks", [](OpeningTracks* t, auto&& f) { visitOpeningTracks(t, f); });
}

/// The robot's footprint (config/robot.yaml, the `robot` namespace).
inline RobotFootprint readRobotFootprint(const ros::NodeHandle& nh) {
  return readShared<RobotFootprint>(nh, "robot", [](RobotFootprint* r, auto&& f) { visitRobotFootprint(r, f); });
}

}  // namespace laser_features
