// The building rules read by a node (ROS, not part of the ROS-free core): from the `building`
// namespace (config/building.yaml, loaded once by the launch file) relative to the node's namespace,
// so that robots in their own namespaces each have theirs; the code's defaults where a launch loads
// none. The one reader for every package.
#pragma once

#include <ros/ros.h>

#include <stdexcept>
#include <string>

#include "laser_features/building_rules.h"

namespace laser_features {

/// Throws std::invalid_argument naming the parameter when the rules are out of range.
inline BuildingRules readBuildingRules(const ros::NodeHandle& nh) {
  BuildingRules rules;
  visitBuildingRules(&rules, [&](const char* name, double* value) { nh.param(std::string("building/") + name, *value, *value); });
  std::string why;
  if (!rules.valid(&why)) throw std::invalid_argument(why);
  return rules;
}

}  // namespace laser_features
