// The robot as the simulator needs it, read from a URDF with urdfdom (no ROS types).
#pragma once

#include <stdexcept>
#include <string>

namespace bullet_sim {

struct RobotModel {
  double radius = 0.25;        // m, footprint radius (the base link's cylinder collision)
  double laser_x = 0.0;        // m, laser origin in the base frame
  double laser_y = 0.0;        // m
  double laser_z = 0.3;        // m
  double laser_yaw = 0.0;      // rad
  std::string base_frame = "base_link";
  std::string laser_frame = "laser";
  // The panoramic camera (PanoramicCamera), when asked for: its pose in the base frame.
  bool has_camera = false;
  double camera_x = 0.0, camera_y = 0.0, camera_z = 0.0, camera_yaw = 0.0;  // m, m, m, rad
  std::string camera_frame;
};

class RobotModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads the footprint radius from the cylinder collision of `base_link` and the laser pose from the
// chain of fixed joints from `base_link` to `laser_link` (and the camera's to `camera_link`, unless
// empty). Throws RobotModelError naming what is missing.
RobotModel robotModelFromUrdf(const std::string& urdf_xml, const std::string& base_link, const std::string& laser_link,
                              const std::string& camera_link = "");

}  // namespace bullet_sim
