// The coordinator's requests to the other nodes, carried out as service calls to pomdp_topo and
// ekf_local_map; their outcomes go back to the coordinator. Node-side: exploration_node's helper.
#pragma once

#include <ros/ros.h>

#include <string>
#include <utility>

#include "exploration/coordinator.h"

namespace exploration {

class ServiceRequests {
 public:
  /// `topo_node`, `local_map_node`: the nodes' names; `sigma_xy` (m), `sigma_theta` (rad): a door's
  /// pose error as the laser sees it from the hallway (a relocation's prior without a covariance).
  ServiceRequests(const ros::NodeHandle& nh, std::string topo_node, std::string local_map_node, double sigma_xy,
                  double sigma_theta)
      : nh_(nh), topo_node_(std::move(topo_node)), local_map_node_(std::move(local_map_node)),
        sigma_xy_(sigma_xy), sigma_theta_(sigma_theta) {}

  /// One request (every kind but Finish, the node's own); results reported to `coordinator`.
  void execute(const Request& r, Coordinator* coordinator);
  /// `mapping` on or off in pomdp_topo (missions on a finished map); true when done.
  bool setMapping(bool mapping, std::string* message);

 private:
  /// Calls service `name`. attempts > 1: a call that failed in transport is made again (the servers
  /// answer true, with success in the response): a create_place call once failed so although the
  /// place was made; a second try costs at most an empty place.
  template <typename Srv>
  bool call(const std::string& name, Srv* srv, int attempts = 1);
  static constexpr double kServiceTimeout = 5.0;  // s, the longest wait for a server to be up

  ros::NodeHandle nh_;
  std::string topo_node_, local_map_node_;
  double sigma_xy_ = 0.05, sigma_theta_ = 0.05;
};

}  // namespace exploration
