// PathDriver: drives the frontier baseline's goal along its planned path (move_base's global plan,
// in explore_lite). The motion controller gets the path's waypoints one at a time: the next one
// when the robot is within waypoint_tolerance of the current (or the controller reached it); the
// last one, the goal, is driven to exactly. A replanned path replaces the controller's goal only
// when its waypoint moved more than goal_refresh_distance (every setGoal() restarts the
// controller's stuck detection). The goal ends reached within goal_reach_tolerance of it (or when
// the controller reached it), stopped when the controller gave up (Blocked, Bumped); either asks
// the caller to plan again at once.
//
// ROS-free and not thread-safe: frontier_baseline_node calls it under its lock from the planning
// and the control threads.
#pragma once

#include "exploration/motion_controller.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace exploration {

struct PathDriverParams {
  double waypoint_tolerance = 0.3;      // m, the next waypoint of the path is taken this close
  double goal_reach_tolerance = 0.4;    // m, the goal counts as reached this close
  double goal_refresh_distance = 0.25;  // m, a replanned waypoint replaces the controller's goal when
                                        // it moved this much
};

class PathDriver {
 public:
  /// Throws std::invalid_argument when MotionController::validate() refuses `motion`.
  PathDriver(const MotionParams& motion, const PathDriverParams& params);

  /// A newly planned path from `robot` (its first point, the start, is skipped unless it is the
  /// only one). Empty: nothing changes.
  void follow(const std::vector<Eigen::Vector2d>& path, const Eigen::Vector2d& robot);
  /// No path: the controller's goal cancelled.
  void stop();
  /// The latest scan's points in the robot frame at `stamp` (MotionController::setScan).
  void setScan(const std::vector<Eigen::Vector2d>& points_in_robot, double stamp);

  struct Step {
    Command command;             // the velocity to publish
    MotionStatus status = MotionStatus::Idle;
    bool replan = false;         // the goal ended this step (reached or stopped): plan again now
    bool warn = false;           // the controller's status changed to one worth a warning
                                 // (Blocked or Bumped on a path, NoScan, Invalid): statusText()
  };
  /// One control cycle at `pose` (the planning frame), sim time `now`, `dt` since the last.
  Step update(const laser_features::Pose2D& pose, double now, double dt, bool bumper);

  /// Whether the goal was reached / the controller stopped since the last call; clears both.
  void takeEnds(bool* reached, bool* stopped);

  std::string statusText() const { return motion_.statusText(); }

 private:
  void sendGoal(const Eigen::Vector2d& target);
  /// Moves on past the waypoints within waypoint_tolerance of `robot` (never past the goal); true
  /// when it moved.
  bool skipReached(const Eigen::Vector2d& robot);

  PathDriverParams params_;
  MotionController motion_;
  std::vector<Eigen::Vector2d> waypoints_;  // the path to the goal after the robot's position
  std::size_t waypoint_ = 0;                // the one the controller drives to
  Eigen::Vector2d target_ = Eigen::Vector2d::Zero();
  bool reached_ = false, stopped_ = false;
  MotionStatus last_status_ = MotionStatus::Idle;
};

}  // namespace exploration
