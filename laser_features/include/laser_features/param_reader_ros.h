// A node's own parameters (ROS, not part of the ROS-free core): each package's visitParams list
// read from the node's private namespace, each parameter with the core's default as its default
// (config/<node>.yaml holds the same values). The one reader for every package's node.
#pragma once

#include <ros/node_handle.h>

#include <stdexcept>
#include <string>
#include <type_traits>

namespace laser_features {

struct RosParamReader {
  const ros::NodeHandle& nh;
  void operator()(const char* name, double* value) const { nh.param(name, *value, *value); }
  void operator()(const char* name, int* value) const { nh.param(name, *value, *value); }
  void operator()(const char* name, bool* value) const { nh.param(name, *value, *value); }
  void operator()(const char* name, std::string* value) const { nh.param(name, *value, *value); }
  /// A count (an unsigned field): at least 1, else std::invalid_argument naming the parameter.
  template <typename Count, typename = std::enable_if_t<std::is_unsigned_v<Count> && !std::is_same_v<Count, bool>>>
  void operator()(const char* name, Count* value) const {
    int v = static_cast<int>(*value);
    nh.param(name, v, v);
    if (v < 1) throw std::invalid_argument(nh.resolveName(name) + " must be >= 1 (a count), not " + std::to_string(v));
    *value = static_cast<Count>(v);
  }
};

}  // namespace laser_features
