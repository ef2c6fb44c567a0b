// tf lookups for the nodes of every package (ROS, not part of the ROS-free core): one way to wait
// for a transform.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/ros.h>
#include <tf2/exceptions.h>
#include <tf2/utils.h>
#include <tf2_ros/buffer.h>

#include <algorithm>
#include <string>

#include "laser_features/geometry.h"

namespace laser_features {

/// The transform target <- source at `stamp`, waiting at most `timeout` seconds of WALL time for it
/// to arrive. tf2's own timeout counts ROS time, which stands still when a bag's /clock stops (the
/// end of a replay): a node waiting then would block its callbacks, and the services others call on
/// it, for ever. False, with the reason in `why`, when it does not come.
inline bool lookupTransform(const tf2_ros::Buffer& tf, const std::string& target, const std::string& source,
                            const ros::Time& stamp, double timeout, geometry_msgs::TransformStamped* out,
                            std::string* why = nullptr) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(std::max(0.0, timeout));
  std::string error;
  while (!tf.canTransform(target, source, stamp, &error)) {  // (canTransform appends to error)
    if (!ros::ok() || ros::WallTime::now() >= deadline) {
      if (why != nullptr) *why = error;
      return false;
    }
    ros::WallDuration(0.0001).sleep();  // fine: a lockstep step waits on this
    error.clear();
  }
  try {
    *out = tf.lookupTransform(target, source, stamp);
    return true;
  } catch (const tf2::TransformException& e) {
    if (why != nullptr) *why = e.what();
    return false;
  }
}

/// The same, as the 2D pose (x, y, yaw) of `source` in `target`.
inline bool lookupPose2D(const tf2_ros::Buffer& tf, const std::string& target, const std::string& source,
                         const ros::Time& stamp, double timeout, Pose2D* out, std::string* why = nullptr) {
  geometry_msgs::TransformStamped t;
  if (!lookupTransform(tf, target, source, stamp, timeout, &t, why)) return false;
  *out = Pose2D{t.transform.translation.x, t.transform.translation.y, tf2::getYaw(t.transform.rotation)};
  return true;
}

}  // namespace laser_features
