// ekf_local_map's robot poses in the active place (`local_pose`, frame `place_<id>`), kept by stamp:
// the coordinator's perception of a scan gets the EKF's pose of that very scan. Node-side (ROS).
#pragma once

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <ros/time.h>

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <map>

#include "laser_features/geometry.h"

namespace exploration {

class LocalPoses {
 public:
  /// A pose of `local_pose`; other frames than place_<id> are ignored.
  void add(const geometry_msgs::PoseWithCovarianceStamped& msg);
  /// The robot's pose in `place` at `stamp` with its covariance: the EKF's of that stamp, or its
  /// latest one of `place` up to kMaxAge old moved by the odometry since (a room is metric; its
  /// covariance is then unknown: zero). `odom_at(t, &pose)` gives the odometry at t. False if none.
  bool at(int place, const ros::Time& stamp, const laser_features::Pose2D& odom_now,
          const std::function<bool(const ros::Time&, laser_features::Pose2D*)>& odom_at, laser_features::Pose2D* pose,
          Eigen::Matrix3d* cov) const;
  int lastPlace() const { return last_place_; }
  const geometry_msgs::PoseWithCovarianceStamped& lastMessage() const { return last_msg_; }

  static constexpr double kMaxAge = 0.3;  // s: a few scans; the odometry over it is good to millimetres
  static constexpr size_t kKept = 20;     // poses by stamp (2 s at 10 Hz): the features of a scan come within it

 private:
  struct Entry {
    int place = -1;
    laser_features::Pose2D pose;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // over (x, y, theta)
  };
  std::map<uint64_t, Entry> by_stamp_;
  int last_place_ = -1;  // of last_msg_
  geometry_msgs::PoseWithCovarianceStamped last_msg_;
};

}  // namespace exploration
