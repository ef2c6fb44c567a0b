// The main() of a node built as one object from (node handle, private node handle) that then spins
// (ROS, not part of the ROS-free core). A parameter out of range throws from the node's constructor:
// the message, which names the parameter, is logged as fatal and the process exits with 1.
#pragma once

#include <ros/ros.h>

#include <exception>

namespace laser_features {

template <class Node>
int runNode(int argc, char** argv, const char* name) {
  ros::init(argc, argv, name);
  ros::NodeHandle nh, pnh("~");  // outside the try: the last handle's end shuts ROS (and its log) down
  try {
    Node node{nh, pnh};
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("%s: %s", name, e.what());
    return 1;
  }
  return 0;
}

}  // namespace laser_features
