// WaypointFollower: drives along a GridPlanner path, one waypoint at a time, as the motion
// controller is given one goal at a time.
//
// A waypoint is passed once the robot is within kPassRadius of it, so that the robot does not stop
// at every bend, but only where the straight way from the robot to the next waypoint is
// traversable in the planner's snapshot. A path bends round an obstacle's inflation; a robot that
// cut the bend would head for the next waypoint across that inflation, where the controller (which
// keeps robot radius + safety margin from every scan point, as the planner's inflation does) finds
// no free heading and turns to and fro. Such a robot drives on to the waypoint itself: from there
// the way on is the planner's own line of sight. Within kOnWaypoint it is passed in any case.
//
// ROS-free.
#pragma once

#include "exploration/grid_planner.h"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace exploration {

class WaypointFollower {
 public:
  /// m: a waypoint this near is passed where the way on is clear, so that the robot turns onto the
  /// next leg before it slows down for the waypoint (the controller slows down within
  /// motion/slow_down_distance, 0.8 m, of its goal).
  static constexpr double kPassRadius = 0.3;
  /// m: a waypoint this near is passed whatever lies on the way on: twice the controller's
  /// goal_tolerance (0.05 m), so a waypoint the controller reached (and stopped at) is always passed.
  static constexpr double kOnWaypoint = 0.1;

  /// A new path (its waypoints from the planner), followed from its first waypoint.
  void set(std::vector<Eigen::Vector2d> waypoints);
  void clear() { set({}); }

  /// Passes the waypoints the robot is done with (see the header comment), by the snapshot of the
  /// planner that made the path.
  void advance(const Eigen::Vector2d& robot, const GridPlanner& planner);

  bool empty() const { return waypoints_.empty(); }
  std::size_t size() const { return waypoints_.size(); }
  /// The waypoint to head for; size() once every waypoint is passed.
  std::size_t index() const { return index_; }
  /// Every waypoint passed.
  bool done() const { return index_ >= waypoints_.size(); }
  /// A waypoint before the path's last is the one to head for (the last is the goal itself,
  /// which callers drive to by their own rule).
  bool beforeLast() const { return index_ + 1 < waypoints_.size(); }
  /// The waypoint to head for (not done()).
  const Eigen::Vector2d& current() const { return waypoints_[index_]; }
  /// What is left of the path, from `robot` to the waypoint to head for and on, is clear in
  /// `planner`'s snapshot (GridPlanner::clearLine leg by leg; true once done()).
  bool restClear(const Eigen::Vector2d& robot, const GridPlanner& planner) const;

 private:
  std::vector<Eigen::Vector2d> waypoints_;
  std::size_t index_ = 0;
};

}  // namespace exploration
