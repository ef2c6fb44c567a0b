// The robot's footprint, shared by every node that keeps the robot clear of walls or decides what it
// fits through: one struct, one YAML (config/robot.yaml, loaded by every launch file into the
// `robot` namespace, as costmap_common_params.yaml is for move_base's costmaps), one reader
// (robot_footprint_ros.h). The radius is urdf/robot.urdf's base_link collision cylinder (bullet_sim's
// test_robot_footprint checks they agree); for another robot, both change together.
//
// ROS-free: the standard library only.
#pragma once

#include <cmath>
#include <string>

namespace laser_features {

struct RobotFootprint {
  double radius = 0.25;         // m, the robot is a circle of this radius
  double safety_margin = 0.10;  // m, clearance kept to obstacles on top of the radius (motion, planning)

  bool valid(std::string* error = nullptr) const {
    if (std::isfinite(radius) && radius > 0.0 && std::isfinite(safety_margin) && safety_margin >= 0.0) return true;
    if (error) *error = "robot/radius must be > 0 and robot/safety_margin >= 0";
    return false;
  }
};

/// Every footprint value with its key in config/robot.yaml (under the `robot` namespace).
template <typename Visitor>
void visitRobotFootprint(RobotFootprint* f, Visitor&& visit) {
  visit("radius", &f->radius);
  visit("safety_margin", &f->safety_margin);
}

}  // namespace laser_features
