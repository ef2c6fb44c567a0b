// What the topological map builder did or found, as it happens: a node made, an opening or a
// corner landmark added or deleted, a loop hypothesis opened, closed or rejected, nodes merged, the
// belief lost, gated or reset, an odometry jump, a new stretch begun. The node publishes each on
// `topo_events` (hybrid_slam_msgs/TopoEvent, the same kinds) and logs its text; evaluation counts
// them by kind, never by their text.
//
// ROS-free: the standard library only.
#pragma once

#include <cstdint>
#include <string>

namespace pomdp_topo {

struct TopoEvent {
  // TopoEvent.msg has the same kinds (ros_conversions maps each in a switch the compiler checks for
  // completeness).
  enum class Kind : uint8_t {
    NodeCreated = 0,      // node: the new node; other_node: the node its stretch came from (-1: the start)
    OpeningAdded = 1,     // node: the node that got an opening
    LandmarkAdded = 2,    // edge: the edge that got a corner landmark
    LandmarkDeleted = 3,  // edge: the edge that lost one
    LoopHypothesis = 4,   // node: the new node that may be an old one; map building paused
    LoopClosed = 5,       // node: the new node dropped; other_node: the old node kept
    LoopRejected = 6,     // node: the new node, a new place after all
    NodesMerged = 7,      // node: the node dropped; other_node: the node kept
    BeliefLost = 8,       // the map does not explain the observations: the belief reset to uniform
    BeliefGated = 9,      // no belief near the dead-reckoned position or heading: uniform over the states there
    BeliefReset = 10,     // node: where the belief put the robot off the graph where the dead reckoning does not
    OdometryJump = 11,    // the robot was moved (node: the frontier's node, its way left unexplored; -1: none)
    Relocalized = 12,     // confident again after an odometry jump
    NewStretch = 13,      // node: the node the belief leaves the known graph at
  };
  Kind kind = Kind::NodeCreated;
  int node = -1;
  int other_node = -1;
  int edge = -1;
  std::string text;  // the log line
};

}  // namespace pomdp_topo
