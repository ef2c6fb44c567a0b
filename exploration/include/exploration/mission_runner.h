// A mission (Tomatis, Nourbakhsh & Siegwart 2001, section 4): from wherever the robot is to a goal
// pose in a place of the finished map. Metric out of the room the robot is in, topological along
// the graph to the place's door, relocation there (ekf_local_map matches the place's map with the
// robot's pose given by the door), metric to the goal.
//
// MissionRunner keeps the mission (its goal, the place's door on the graph, its outcome), runs the
// relocation at the door and drives the robot to the goal inside the room. The coordinator's state
// machine says which step runs and since when, and carries out what the steps report.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/room_visit.h"
#include "exploration/topo_route.h"
#include "exploration/waypoint_follower.h"
#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace exploration {

/// Parameters of MissionRunner (config/exploration.yaml's mission/ keys; each with its unit and default).
struct MissionParams {
  double relocation_timeout = 20.0;  // s, a mission's relocation at a door gives no verdict in this: failed
  int max_relocation_failures = 2;   // -, relocations that fail (wrong room), and separately misses of the
                                     // goal's door, before a mission is given up (each resets the belief)
  double time_limit = 1200.0;        // s, a mission ends unsuccessful after this (sim time)
  double goal_tolerance = 0.005;     // m, a mission's goal is reached within this (the EKF's estimate)
  double heading_tolerance = 0.02;   // rad, and its heading within this
  int refine_attempts = 3;           // -, the controller reached the goal but the EKF's estimate is beyond
                                     // the tolerances: the goal is sent again this many times, then ...
  double accept_distance = 0.03;     // m, ... reached within this; the controller stopping (blocked,
                                     // stalled) this close to a mission's goal also counts as reached ...
  double accept_angle = 0.05;        // rad, ... with its heading within this. EKF corrections of the
                                     // goal below these are not re-sent while the robot drives to it
  double stall_time = 20.0;          // s, no 5 cm of progress to a mission's goal in a room for this: unreachable
};

/// A mission's outcome.
struct MissionOutcome {
  bool finished = false;
  bool success = false;
  std::string message;
  double path_length = 0.0;  // m, odometric
  int relocation_failures = 0;  // relocations that failed (each reset the belief)
  int door_misses = 0;          // times the goal's door was not found after max_route_attempts (each reset the belief)
};

/// How the relocation at the goal's door stands after a tick (MissionRunner::relocate()).
struct RelocationStep {
  enum Kind {
    Pending,     // no verdict yet, or no EKF pose yet
    Relocated,   // the robot is in the goal's place: into the room
    AskedAgain,  // asked again, from in front of the door
    Failed,      // not the goal's room (or no verdict): the belief is to be reset
    GaveUp       // ... the max_relocation_failures + 1-th time: the mission fails
  };
  Kind kind = Pending;
  std::string text;  // the state's text from now on (Pending: empty when it stays)
};

/// How a mission ended (MissionRunner::driveToGoal()).
struct MissionEnd {
  bool success = false;
  std::string why;
};

class MissionRunner {
 public:
  explicit MissionRunner(const MissionParams& params = MissionParams());
  static bool validate(const MissionParams& params, std::string* error = nullptr);
  const MissionParams& params() const { return params_; }

  /// Starts a mission to `goal` (m, m, rad) in the frame of place `place_id`; false and the reason
  /// when it cannot be run (a goal not finite, a place no door of `graph` links). `travel` (m, the
  /// odometric travel so far) and `now` (s): where the mission's length and time count from.
  bool start(int place_id, const laser_features::Pose2D& goal, const TopoGraph& graph, double travel, double now,
             std::string* why);
  /// The mission ends (`travel`, m: the odometric travel so far).
  void end(bool success, const std::string& why, double travel);
  bool active() const { return active_; }
  bool timedOut(double now) const { return now - start_time_ > params_.time_limit; }
  int place() const { return place_; }
  /// The goal place's door on the graph.
  const PlaceDoor& door() const { return place_door_; }
  const MissionOutcome& outcome() const { return outcome_; }
  /// m, the expected distance left (along the graph, then straight to the goal).
  double distanceLeft() const { return distance_left_; }
  /// The distance left on the way to the goal's door by `route`: along it, then straight to the goal.
  void updateDistanceLeft(const RouteStep& route);
  /// The goal's door was missed (the route turned round for it max_route_attempts times): true when
  /// the mission is to be given up (more than max_relocation_failures misses).
  bool missDoor();
  int doorMisses() const { return door_misses_; }

  /// The robot stopped past the goal's door (`door`, as tracked): ekf_local_map is asked to
  /// relocate it (`robot_odom`) in the place at its door; the verdict is pending from then on.
  void beginRelocation(const DoorTrack& door, const laser_features::Pose2D& robot_odom, Decision* d);
  /// ekf_local_map's verdict on the relocation.
  void relocationResult(bool success, const std::string& verdict);
  /// One tick of the relocation (`elapsed`: s since it was last asked for).
  RelocationStep relocate(const Perception& p, const DoorTrack& door, double now, double elapsed,
                          const MotionFeedback& motion, Decision* d);

  /// The drive to the goal in the room begins; `inside`: the robot is in the room already (not at its door).
  void beginGoToGoal(bool inside, double now);
  /// One tick of the drive to the goal (`q` in the place, `elapsed`: s since it began); the end
  /// when the goal is reached or given up.
  std::optional<MissionEnd> driveToGoal(const Perception& q, RoomVisit& visit, double now, double elapsed,
                                        const MotionFeedback& motion, Decision* d);

 private:
  /// The robot's error from the goal this tick (the EKF's estimate).
  struct GoalError {
    double distance = 0.0;  // m
    double heading = 0.0;   // rad
    bool close = false;     // within accept_distance and accept_angle
    std::string text;       // " (estimate ... from the goal)"
  };

  /// Asks ekf_local_map to relocate the robot (odometry pose) in the place at its door (as seen,
  /// odometry frame); the verdict is pending from then on.
  void askRelocation(const laser_features::Pose2D& door_odom, const laser_features::Pose2D& robot_odom, Decision* d);
  /// In front of the door, facing in (relocate step 1): false while on the way (a goal is set).
  bool moveInFrontOfDoor(const Perception& p, const DoorTrack& door, double now, const MotionFeedback& motion, Decision* d);
  /// The door as seen now from in front of it: the opening nearest to the tracked one.
  laser_features::Pose2D doorSeen(const Perception& p, const DoorTrack& door) const;
  /// The grid path to the goal in the room as seen, and the progress along it.
  void planPath(RoomVisit& visit, const Eigen::Vector2d& robot, const Eigen::Vector2d& goal, double distance, double now);
  /// The final goal, re-sent only when the EKF's correction moved it; the end when it is reached or
  /// the controller gave up on it (`blocked_at_goal`).
  std::optional<MissionEnd> finalGoal(const Perception& q, const RoomVisit& visit, const GoalError& error,
                                      const MotionFeedback& motion, bool* blocked_at_goal, Decision* d);

  MissionParams params_;
  bool active_ = false;
  int place_ = -1;
  laser_features::Pose2D goal_;  // in the place
  PlaceDoor place_door_;
  double start_travel_ = 0.0;    // m
  double start_time_ = 0.0;      // s
  double distance_left_ = 0.0;   // m
  MissionOutcome outcome_;
  int door_misses_ = 0;
  // Relocation.
  bool relocation_pending_ = false;  // no verdict yet
  bool relocation_ok_ = false;
  std::string relocation_verdict_;
  int relocation_failures_ = 0;
  int relocate_step_ = 0;            // 0 from the hallway, 1 moving in front of the door, 2 from there
  double relocate_step_since_ = 0.0;
  bool relocation_retried_ = false;  // a second relocation asked for from in front of the door
  // The drive to the goal.
  laser_features::Pose2D goal_odom_;  // the goal as last sent, odometry frame
  bool goal_odom_valid_ = false;
  int refines_ = 0;                 // times the goal was sent again after the controller reached it
  bool entered_ = false;            // the robot has been entry_depth inside the door
  WaypointFollower path_;  // grid path to the goal (place frame)
  double last_plan_ = -1e9;         // s, when the grid path was last planned
  double best_ = 0.0;               // m, the shortest way left to the goal so far ...
  double best_time_ = 0.0;          // s, ... when it got 5 cm shorter last
  double path_length_ = 0.0;        // m, the last grid path's length (straight: the distance)
  bool had_path_ = false;           // the last plan found a grid path
};

}  // namespace exploration
