// One service call from a node of this package, the same way in every node: wait for the server,
// call, and say what failed. Node-side (ROS).
#pragma once

#include <ros/ros.h>

#include <string>

namespace exploration {

/// Calls service `name` (waiting up to `timeout` s for it). attempts > 1: a call that failed in
/// transport is made again (the servers answer true, with success in the response). Errors are
/// logged with `who` (the node) in front; false on failure.
template <typename Srv>
bool callService(ros::NodeHandle& nh, const std::string& who, const std::string& name, Srv* srv, double timeout,
                 int attempts = 1) {
  for (int attempt = 1;; ++attempt) {
    ros::ServiceClient client = nh.serviceClient<Srv>(name);
    if (!client.waitForExistence(ros::Duration(timeout))) {
      ROS_ERROR("%s: service %s is not available", who.c_str(), name.c_str());
      return false;
    }
    if (client.call(*srv)) return true;
    if (attempt >= attempts) {
      ROS_ERROR("%s: the call to %s failed", who.c_str(), name.c_str());
      return false;
    }
    ROS_WARN("%s: the call to %s failed; calling it again", who.c_str(), name.c_str());
  }
}

}  // namespace exploration
