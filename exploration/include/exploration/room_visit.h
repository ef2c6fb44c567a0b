// The METRIC visit of one room (Tomatis, Nourbakhsh & Siegwart 2001, section 3.2), in the frame of
// the room's place (the robot's pose there from ekf_local_map's EKF): to the door on its axis, the
// room's coverage (RoomExplorer: frontiers of a grid of the room, behind a virtual wall across the
// door), and the way out: a grid path to the door, through it on its axis, and back to where the
// robot left the hallway with the hallway's heading.
//
// The coordinator's state machine says which step runs and since when; RoomVisit sets each step's
// goal and says when the step is over.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include <cmath>

#include "exploration/coordinator_io.h"
#include "exploration/grid_planner.h"
#include "exploration/hallway_doors.h"
#include "exploration/room_explorer.h"
#include "exploration/topo_route.h"
#include "exploration/waypoint_follower.h"
#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace exploration {

/// Parameters of RoomVisit (config/exploration.yaml's room_visit/ keys; each with its unit and default).
struct RoomVisitParams {
  double time_limit = 600.0;       // s, a room's exploration ends after this (then the robot leaves); a
                                   // mission's drive to its goal in the room fails after it
  double replan_period = 0.5;      // s, the room's frontier goal (a mission's grid path, the path to an
                                   // inner door) is chosen again at most this often
  double exit_time_limit = 120.0;  // s, leaving a room takes at most this (a third of it per step through the door)
  bool inner_rooms = true;         // -, after a room's coverage its inner doors (innerDoors()) are looked through and
                                   // the rooms behind them visited as rooms of their own (SuiteVisit), but for
                                   // connecting rooms and hallways; false: they stay virtual walls and rooms
                                   // reachable only through another room are not mapped.
};

class RoomVisit {
 public:
  static constexpr int kExitAttempts = 3;      // ways out tried before the robot counts as stuck inside
  static constexpr double kDoorPassage = 1.0;  // m, from the door's centre: where the robot passes it
  static constexpr double kArrived = 0.15;     // m (and rad): the robot stands at a goal in a room within this

  /// `rules` and `doors`: a door seen on the approach to a new room is one of the building's doors
  /// (BuildingRules), facing the way the tracked one does within doors.tracks.side_angle, within
  /// doors.same_distance of it.
  RoomVisit(const RoomVisitParams& params, const RoomExplorerParams& room, const laser_features::BuildingRules& rules,
            const HallwayDoorParams& doors);
  static bool validate(const RoomVisitParams& params, std::string* error = nullptr);
  const RoomVisitParams& params() const { return params_; }
  const RoomExplorer& explorer() const { return explorer_; }

  /// A new room: its place was created with the robot, standing still at `robot_odom`, at its
  /// origin. `door`: the door as tracked from the hallway; `hallway_heading_odom` (rad): the
  /// heading to leave the room by.
  void beginNewRoom(const laser_features::Pose2D& robot_odom, const DoorTrack& door, double hallway_heading_odom);
  /// A known room: the robot was relocated in its place (`p.room_pose`) at `door` (the graph's
  /// opening, with the door's pose in the place) after leaving the hallway at `hallway_stop_odom`.
  /// `door_width` (m): the door as tracked from the hallway.
  void beginKnownRoom(const Perception& p, const laser_features::Pose2D& hallway_stop_odom, double hallway_heading_odom,
                      const GraphOpening& door, double door_width);

  /// `p` with the robot's pose in the place: the EKF's, or without one the odometry's since the
  /// EKF's last.
  Perception inPlace(const Perception& p);
  /// One scan (`q`, from inPlace()) into the room's grid; near the door, the controller keeps a
  /// clearance that fits it. `approaching`: the robot is on its way to the door (a new room's door
  /// is refined from what is seen then).
  void observe(const Perception& q, bool approaching, Decision* d);

  /// To the door on its axis, facing in. True once there, or after 30 s of `elapsed`.
  bool approachDoor(const Perception& q, double elapsed, Decision* d);
  /// m, how far the new room's door as seen on the approach lies from the door as tracked.
  double doorRefinement() const;

  enum class Coverage { Covering, Done, TimedOut };
  /// The room's coverage: the frontier goal, or a stop. Done when the room explorer is (or cannot
  /// go on); TimedOut after time_limit of `elapsed`; then no goal is set.
  Coverage coverRoom(const Perception& q, double now, double elapsed, Decision* d);

  /// The way out begins: a grid path from where the robot was last seen in the room to its door.
  void beginExit();
  /// Along the path out. True when it ends, or after exit_time_limit of `elapsed`.
  bool followExitPath(const Perception& q, double elapsed, Decision* d);
  /// Through the door begins, at `now` (s).
  void beginDoorExit(double now);
  enum class Exit {
    Passing,    // on the way (a goal is set)
    TryAgain,   // ended still inside the room: a new way out begins (exitAttempts() so far)
    Stuck,      // ... for the kExitAttempts-th time
    Back,       // out, back where the robot left the hallway
    NearlyBack  // out, the way back not reached exactly (its time ran out)
  };
  /// Through the door on its axis (a point inside, a point outside) back to where the robot left
  /// the hallway, with the hallway's heading. `elapsed`: since beginDoorExit() or TryAgain.
  Exit exitThroughDoor(const Perception& q, double now, double elapsed, const MotionFeedback& motion, Decision* d);
  int exitAttempts() const { return exit_attempts_; }
  /// The robot leaves the room by the other way of the hallway (a mission's route leads there).
  void turnExitHeadingRound();

  /// The door in the place: its centre and the direction into the room.
  const laser_features::Pose2D& doorInPlace() const { return door_in_place_; }
  /// The room's other doors as seen from inside it while covering it (each the mean of its
  /// sightings), in the odometry frame as the EKF last placed the place: centre, direction into the
  /// room, width.
  std::vector<DoorTrack> otherDoorsOdom() const;
  /// The same doors in the place: centre and direction into the room.
  std::vector<laser_features::Pose2D> otherDoorsInPlace() const;
  /// A door of the room seen from inside it, in the place: centre, direction into the room, width.
  struct DoorInPlace {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double into = 0.0;  // rad
    double width = 0.0; // m
    int sightings = 0;
  };
  /// While the rooms behind are visited, only the doors stay closed by virtual walls
  /// (RoomExplorer::openFurnitureGaps); the way out has them all again.
  void openFurnitureGaps() { explorer_.openFurnitureGaps(); }
  void closeFurnitureGaps() { explorer_.closeFurnitureGaps(); }
  /// The room's doors that are not in its entry door's wall: doors into rooms reachable through this
  /// one (a suite) or into another hallway. A door in the entry's wall lies on that wall's line (to
  /// within the direction error of the entry door over the room, a few centimetres per metre); one in
  /// a side wall lies past the corner by at least half the narrowest door plus a jamb
  /// (BuildingRules::doorFromCorner), one in the back wall by the room's depth.
  /// Seen from inside at least twice as a gap in a wall (laser_features' Opening::in_wall: a wall
  /// piece runs on from one of its edges; the gaps between table and chair legs have none), and
  /// leading out of the room (RoomExplorer::leadsOutOfRoom, kDoorPassage behind it: a gap between
  /// furniture and a wall is none).
  std::vector<DoorInPlace> innerDoors() const;
  /// The room's extent (RoomExplorer::extent) in the odometry frame as the EKF last placed the place.
  std::optional<RoomExtent> extentOdom() const;
  /// The place's origin in the odometry frame, as the EKF last placed it.
  const laser_features::Pose2D& placeOriginOdom() const { return place_origin_odom_; }
  /// The odometry's drift over the visit as the EKF measured it: the place's origin in the odometry
  /// frame as last placed, composed with the inverse of where the visit's first EKF pose placed it.
  /// A point of the building at `x` in the odometry frame before the visit is at drift · x after it.
  /// None where no EKF pose came during the visit.
  std::optional<laser_features::Pose2D> odometryDrift() const;
  /// The door entered by, in the odometry frame as the EKF last placed the place (the odometry's
  /// drift inside the room taken out): centre, direction into the room, width as tracked.
  DoorTrack doorOdom() const;
  /// A goal `g` (and heading `theta`) in the place as an odometry goal for the robot of `q`.
  void goalInPlace(const Perception& q, const Eigen::Vector2d& g, std::optional<double> theta, Decision* d) const;
  /// A grid path in the room as seen so far (RoomExplorer::pathTo); with `clear_of_scan`, kept clear
  /// of the latest scan's returns too (what the grid lost of table and chair legs: planExit()).
  std::optional<Path> pathTo(const Eigen::Vector2d& robot, const Eigen::Vector2d& goal, bool clear_of_scan = false) {
    static const std::vector<Eigen::Vector2d> kNone;
    return explorer_.pathTo(robot, goal, clear_of_scan ? scan_in_place_ : kNone);
  }
  /// The planner whose snapshot made the last pathTo() path.
  const GridPlanner& pathPlanner() const { return explorer_.pathPlanner(); }

 private:
  struct DoorSighting {
    Eigen::Vector2d centre;  // m, place frame
    double width;            // m
  };
  /// The door as the scan `q` shows it: of the openings of a door's width (BuildingRules) whose
  /// direction lies within doors.tracks.side_angle of `facing` (rad, place frame), the nearest to `near`
  /// (place frame) within doors.same_distance.
  std::optional<DoorSighting> seeDoor(const Perception& q, const Eigen::Vector2d& near, double facing) const;
  /// The door to go out by: the mean of its sightings from inside the room since beginDoorExit()
  /// (`q`'s among them), or the door as placed until it is seen.
  DoorSighting doorOnTheWayOut(const Perception& q);
  /// On the way to a new room's door: the door as seen now (the mean of its sightings on the
  /// approach) replaces door_in_place_ when it differs by more than 5 cm; true if it did.
  bool refineDoor(const Perception& q);
  /// A grid path from the robot's last position to the door (the exit attempts are kept).
  void planExit();
  /// One sighting from inside of a door other than the entry (place frame): into its mean.
  /// `in_wall`: seen as a gap in a wall (Opening::in_wall).
  void seeOtherDoor(const Eigen::Vector2d& centre, double into, double width, bool in_wall);

  RoomVisitParams params_;
  laser_features::BuildingRules rules_;
  HallwayDoorParams doors_;
  RoomExplorer explorer_;
  bool new_room_ = false;           // begun by beginNewRoom (its door is refined on the approach)
  double door_width_ = 0.0;         // m, the door as tracked from the hallway
  laser_features::Pose2D place_origin_odom_;  // the place's origin in the odometry frame (as the EKF last placed it)
  std::optional<laser_features::Pose2D> first_origin_odom_;  // as the visit's first EKF pose placed it
  laser_features::Pose2D door_in_place_;
  Eigen::Vector2d door_tracked_in_place_ = Eigen::Vector2d::Zero();  // a new room's door as tracked from the hallway
  Eigen::Vector2d door_seen_sum_ = Eigen::Vector2d::Zero();  // its sightings on the approach (place frame)
  int door_seen_count_ = 0;
  Eigen::Vector2d hallway_in_place_ = Eigen::Vector2d::Zero();  // where the robot left the hallway, place frame
  double exit_theta_place_ = 0.0;   // rad, the hallway heading in the place frame
  Eigen::Vector2d last_position_ = Eigen::Vector2d::Zero();  // the robot in the place when last seen inside
  // The latest scan's returns there (place frame): obstacles for a way out planned after one has
  // failed, whatever the grid has lost of them (planExit).
  std::vector<Eigen::Vector2d> scan_in_place_;
  double last_plan_ = -1e9;         // s, when the frontier goal was last chosen
  std::optional<Eigen::Vector2d> goal_;  // the frontier goal
  WaypointFollower exit_path_;  // place frame
  int exit_step_ = 0;               // through the door: 0 inside the door, 1 outside, 2 back on the hallway
  double exit_step_since_ = 0.0;    // s
  int exit_attempts_ = 0;           // ways out of the room tried that ended still inside it
  Eigen::Vector2d exit_seen_sum_ = Eigen::Vector2d::Zero();  // the door's sightings from inside on the way out (place frame)
  double exit_width_sum_ = 0.0;     // m, their widths
  int exit_seen_count_ = 0;
  struct SeenDoor {                 // another door of the room, place frame: sums of its sightings
    Eigen::Vector2d centre_sum = Eigen::Vector2d::Zero();
    Eigen::Vector2d into_sum = Eigen::Vector2d::Zero();  // unit vectors into the room
    double width_sum = 0.0;
    int count = 0;
    int in_wall = 0;                // sightings as a gap in a wall (Opening::in_wall)
    Eigen::Vector2d centre() const { return centre_sum / count; }
    double into() const { return std::atan2(into_sum.y(), into_sum.x()); }  // rad, the mean direction into the room
  };
  std::vector<SeenDoor> other_doors_;
};

}  // namespace exploration
