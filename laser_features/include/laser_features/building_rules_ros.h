// The building rules and the robot's footprint read by a node (ROS, not part of the ROS-free core):
// from the `building` and `robot` namespaces (config/building.yaml and config/robot.yaml, loaded
// once by the launch file) relative to the node's namespace, so that robots in their own namespaces
// each have theirs; the code's defaults where a launch loads none. The one reader for every package.
#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>

#include "laser_features/building_rules.h"
#include "laser_features/robot_footprint.h"

namespace laser_features {

/// Throws std::invalid_argument naming the parameter when the rules are out of range.
inline BuildingRules readBuildingRules(const ros::NodeHandle& nh) {
  BuildingRules rules;
  visitBuildingRules(&rules, [&](const char* name, double* value) { nh.param(std::string("building/") + name, *value, *value); });
  std::string why;
  if (!rules.valid(&why)) throw std::invalid_argument(why);
  return rules;
}

/// The robot's footprint from the `robot` namespace (config/robot.yaml), the same way; throws
/// std::invalid_argument naming the parameter when it is out of range.
inline RobotFootprint readRobotFootprint(const ros::NodeHandle& nh) {
  RobotFootprint footprint;
  visitRobotFootprint(&footprint, [&](const char* name, double* value) { nh.param(std::string("robot/") + name, *value, *value); });
  std::string why;
  if (!footprint.valid(&why)) throw std::invalid_argument(why);
  return footprint;
}

}  // namespace laser_features
