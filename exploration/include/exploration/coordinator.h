// The exploration coordinator (Tomatis, Nourbakhsh & Siegwart 2001, sections 3.1-3.2): a robot
// put into an unknown building explores all of it and leaves a hybrid map.
//
//  - TOPOLOGICAL in hallways: follow the hallway's mid-line along one of the building's headings
//    (the heading estimator's bins); every opening passed becomes a node (pomdp_topo builds them);
//    at a hallway's end turn into an open way (left first), recording the ways not taken as
//    unexplored openings of the node; a dead end is a U-turn. Hallways are explored depth-first:
//    on the known graph the robot travels to the nearest node with an unexplored opening (Dijkstra
//    on the graph, TopoGraph::route) and takes it.
//  - METRIC in rooms: a door passed that is new (the map builder's frontier) or known but not
//    explored, while the belief is confident, is entered: the robot stops, a new place (local map,
//    ekf_local_map) is created with the robot at its origin, the door is stored in it, the room is
//    covered (RoomExplorer: frontiers of a grid of the room in the place's frame, from the EKF's
//    pose, behind a virtual wall across the door) and left by the same door, back onto the
//    hallway's mid-line with the heading it had; the door's opening is marked explored and linked
//    to the place, and the topological map resumes (it stood still meanwhile).
//  - Never from topological to metric while the belief is unconfident (or a loop closure is being
//    verified): the robot keeps following the hallway (which gathers landmarks) until confident.
//  - Done when the map builder is on the known graph, confident, and no unexplored opening is left.
//
// The coordinator does not talk to the other nodes itself: it returns requests (create a place,
// record an opening, ...) that its node carries out as service calls and answers.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/hallway_doors.h"
#include "exploration/hallway_view.h"
#include "exploration/room_explorer.h"
#include "exploration/topo_route.h"
#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"
#include "laser_features/line_extractor.h"
#include "laser_features/opening_extractor.h"

#include <Eigen/Core>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace exploration {

struct CoordinatorParams {
  HallwayViewParams hallway;
  RoomExplorerParams room;
  double lookahead = 1.5;            // m, the hallway goal lies this far ahead on the mid-line
  double end_distance = 1.3;         // m, the hallway ends when the free distance ahead is below this
  laser_features::BuildingRules rules;  // door widths (config/building.yaml): openings outside them are no doors
  HallwayDoorParams doors;           // the hallway's doors (door_* in config/exploration.yaml)
  double settle_time = 0.5;          // s, standing still before a switch (the nodes see the robot stopped)
  double room_time_limit = 600.0;    // s, a room's exploration ends after this (then the robot leaves)
  double room_replan_period = 0.5;   // s, the room's frontier goal is chosen again at most this often
  double exit_time_limit = 120.0;    // s, leaving a room takes at most this, else the door is retried once
  double branch_record_distance = 1.0;  // m travelled after a turn before the ways not taken are recorded
  double u_turn_cost = 2.0;          // m, route cost of turning back on an edge
  int max_route_attempts = 3;        // -, turns round towards one node's opening, or into one branch towards it, before it is given up
  double jump_tolerance = 4.0;       // m, a belief whose node is farther along the graph from the last
                                     // trusted one than the travel since plus this has jumped ...
  double jump_hold_distance = 6.0;   // m, ... and is not acted on until it held for this much travel
  double goal_pass_distance = 3.0;   // m, travel at the goal node (as the belief says) without finding
                                     // its opening before the opening is given up
  double goal_refresh_distance = 0.25;  // m, the hallway goal is re-sent when it moved this much
  double follow_stall_time = 20.0;   // s, following a hallway without getting a robot's diameter away from
                                     // where the robot was this long ago is a hallway end (the hallway goal
                                     // moves with the robot, so the controller's own stuck test never fires)
  double max_time = 0.0;             // s, the exploration gives up after this (sim time); 0: no limit
  bool explore = true;               // -, explore from the start; false: wait for missions (a loaded map)
  double relocation_timeout = 20.0;  // s, a mission's relocation at a door gives no verdict in this: failed
  int max_relocation_failures = 2;   // -, relocations that fail (wrong room), and separately misses of the
                                     // goal's door, before a mission is given up (each resets the belief)
  double mission_time_limit = 1200.0;  // s, a mission ends unsuccessful after this (sim time)
  double mission_goal_tolerance = 0.005;  // m, a mission's goal is reached within this (the EKF's estimate)
  double mission_heading_tolerance = 0.02;  // rad, and its heading within this
  int mission_refine_attempts = 3;  // -, the controller reached the goal but the EKF's estimate is beyond
                                    // the tolerances: the goal is sent again this many times, then ...
  double mission_accept_distance = 0.03;  // m, ... reached within this; the controller stopping (blocked,
                                         // stalled) this close to a mission's goal also counts as reached ...
  double mission_accept_angle = 0.05;    // rad, ... with its heading within this. EKF corrections of the
                                         // goal below these are not re-sent while the robot drives to it
  double mission_stall_time = 20.0;  // s, no 5 cm of progress to a mission's goal in a room for this: unreachable
};

enum class CoordinatorMode : uint8_t { Topological = 0, Metric = 1, Switching = 2, Done = 3 };
const char* toString(CoordinatorMode mode);

/// One tick's perception: the scan and its features, at one stamp.
struct Perception {
  double stamp = 0.0;                      // s
  laser_features::Pose2D odom;             // robot in the odometry frame at the stamp
  laser_features::Pose2D sensor_in_robot;  // the laser in the robot frame
  std::vector<float> ranges;               // the raw scan (REP 117), for the room grid
  double angle_min = 0.0, angle_increment = 0.0;
  std::vector<Eigen::Vector2d> points;     // scan points, robot frame
  std::vector<laser_features::LineSegment> lines;  // robot frame
  std::vector<laser_features::Opening> openings;   // robot frame
  bool room_pose_valid = false;            // the EKF's robot pose in the active place at the stamp
  laser_features::Pose2D room_pose;
};

/// What pomdp_topo says (its latest messages).
struct TopoView {
  bool valid = false;         // something was received
  std::string mode;           // "frontier", "localized" or "loop_check"
  bool confident = false;
  bool heading_valid = false;
  double heading_offset = 0.0;  // rad, map heading - odometry heading (the heading estimator's correction)
  GraphPosition position;       // the belief's most likely state
};

/// A request to another node.
struct Request {
  enum Kind { CreatePlace, AddDoor, RecordOpening, ClosePlace, SaveMaps, Finish, Relocate, ResetBelief };
  Kind kind = SaveMaps;
  int node = -1;             // RecordOpening: -1 = pomdp_topo's current node
  double bearing = 0.0;      // RecordOpening: rad, map frame
  double width = 0.0;        // RecordOpening: m
  double offset = 0.0;       // RecordOpening: m
  bool explored = false;     // RecordOpening
  int place_id = -1;         // RecordOpening (link), AddDoor, Relocate
  int door_id = -1;          // AddDoor, Relocate
  laser_features::Pose2D pose;  // AddDoor: door in the robot frame; RecordOpening: door in the place;
                                // Relocate: the robot in the door's frame
  bool success = true;       // Finish: complete exploration
  std::string text;          // Finish: summary
};

struct Decision {
  bool has_goal = false;     // drive to (x, y[, theta]) in the odometry frame
  double x = 0.0, y = 0.0;
  std::optional<double> theta;
  std::optional<std::pair<double, double>> tolerance;  // m, rad: the goal's, if not the controller's own
  std::optional<double> passage_width;  // m, the robot is passing a door this wide (MotionController::setPassageWidth)
  bool stop = false;         // stand still (no goal)
  CoordinatorMode mode = CoordinatorMode::Topological;
  std::vector<Request> requests;
};

/// A mission (Tomatis et al. 2001, section 4): from wherever the robot is to a goal pose in a place.
struct MissionOutcome {
  bool finished = false;
  bool success = false;
  std::string message;
  double path_length = 0.0;  // m, odometric
  int relocation_failures = 0;  // relocations that failed (each reset the belief)
  int door_misses = 0;          // times the goal's door was not found after max_route_attempts (each reset the belief)
};

struct CoordinatorStats {
  int places = 0;
  int rooms_left_early = 0;   // rooms whose exploration hit the time limit
  int doors_entered = 0;
  int doors_passed = 0;       // doors not entered (explored already, or the belief unconfident)
  int openings_given_up = 0;  // openings the route kept missing (see max_route_attempts)
  int belief_jumps = 0;       // implausible jumps of the belief (see jump_tolerance)
  int turns = 0, u_turns = 0;
  int branch_turns_refused = 0;  // route turns into a branch not made: a door was beside the robot
  double travel = 0.0;        // m, odometric
  double room_free_area = 0.0;  // m^2, sum over the rooms' grids
  size_t peak_room_bytes = 0;
};

class Coordinator {
 public:
  explicit Coordinator(const CoordinatorParams& params = CoordinatorParams());
  static bool validate(const CoordinatorParams& params, std::string* error = nullptr);
  const CoordinatorParams& params() const { return params_; }

  /// The building's axes as pomdp_topo found them (its building_axes topic): the discrete
  /// headings of the hallways. Set before the first update().
  void setHeadingBins(const laser_features::HeadingBins& bins) { bins_ = bins; }
  const laser_features::HeadingBins& headingBins() const { return bins_; }

  /// The topological map as last published.
  void setGraph(const TopoGraph& graph) { graph_ = graph; }
  const TopoGraph& graph() const { return graph_; }

  /// One tick: what to do now. `motion_reached` / `motion_blocked`: the motion controller's status
  /// for the last goal sent.
  Decision update(const Perception& p, const TopoView& topo, bool motion_reached, bool motion_blocked);

  /// Answers to the requests of the last update().
  void placeCreated(bool ok, int place_id);
  void openingRecorded(bool ok, int node);
  /// ekf_local_map's verdict on a relocation at a door (its `relocation` topic).
  void relocationResult(int place_id, bool success, const std::string& verdict);

  /// Starts a mission to `goal` (m, m, rad) in the frame of place `place_id`: metric out of the
  /// room the robot is in, topological along the graph to the place's door, relocation there,
  /// metric to the goal. Only when no exploration and no other mission runs; false and the reason
  /// when it cannot be run (an unknown place, a place no node links).
  bool startMission(int place_id, const laser_features::Pose2D& goal, std::string* why);
  /// Ends the running mission where the robot is (unsuccessful, `why`).
  void cancelMission(const std::string& why);
  bool missionActive() const { return mission_active_; }
  /// The last mission's outcome (finished once it ended).
  const MissionOutcome& missionOutcome() const { return mission_outcome_; }
  /// m, the mission's expected distance left (along the graph, then straight to the goal).
  double missionDistanceLeft() const { return mission_distance_left_; }
  /// Idle: no exploration and no mission runs (the robot stands, in a room or in a hallway).
  bool idle() const { return state_ == State::Idle || state_ == State::Done; }

  CoordinatorMode mode() const { return mode_; }
  const std::string& state() const { return state_text_; }
  const CoordinatorStats& stats() const { return stats_; }
  int currentPlace() const { return place_id_; }
  const RoomExplorer& room() const { return room_; }
  bool done() const { return state_ == State::Done; }

 private:
  enum class State { Init, Follow, Turn, StopForDoor, EnterRoom, ApproachDoor, Room, ExitPath, ExitDoor, Done,
                     Idle, Relocate, GoToGoal };
  /// A door seen beside the hallway, tracked over scans in the odometry frame (hallway-local: the
  /// tracks are dropped once far behind).

  void setState(State s, const std::string& text);
  /// The door passed is the one the robot last came out of (see left_door_).
  bool justLeft(const DoorTrack& door) const;
  double binHeading(int bin) const;   // map frame
  int startBin(const Perception& p, const TopoView& topo) const;  // the bin the exploration sets off along
  /// 0: the hallway at the start runs along the robot's own bin, 1: across it; none: no walls seen
  /// on both sides of the robot.
  std::optional<int> startHallwayAxis(const Perception& p, const TopoView& topo) const;
  int binOf(double map_heading) const;
  double odomHeadingOfBin(int bin, const TopoView& topo) const;
  /// The hallway's heading in the odometry frame: bin_'s and the hallway's offset from it.
  double odomHallwayHeading(const TopoView& topo) const { return odomHeadingOfBin(bin_, topo) + axis_offset_; }
  /// The hallway's direction (robot frame) from its walls: along the direction followed, else the
  /// walls of a hallway at an angle to it (a wing, a bend); the offset from bin_ is kept (re-binned
  /// past half a bin). The view along the result in `v`.
  double trackHallwayAxis(const Perception& p, const TopoView& topo, HallwayView* v);
  /// A bearing in the odometry frame (a door's, into its room) as the topological map has it: in the
  /// map frame, and square to the axes where a wing's hallway runs at axis_offset_ to them
  /// (pomdp_topo's front end takes a wing's openings relative to its walls the same way).
  double topoBearing(double odom_bearing, const TopoView& topo) const;
  /// At a hallway's end with no way open along the axes: a hallway leaving at an angle (a wing),
  /// its direction in the robot frame.
  std::optional<double> obliqueWayAtEnd(const Perception& p, double dir_robot, const HallwayView& v) const;
  /// The lane (lateral offset, m, robot frame) past an obstacle ahead in the hallway, if there is one.
  std::optional<double> laneAround(const Perception& p, double dir_robot, const HallwayView& v, bool blocked);
  /// Following without progress for follow_stall_time (see there).
  bool followStalled(const Perception& p);
  /// Asks ekf_local_map to relocate the robot (odometry pose) in the mission's place at its door
  /// (as seen, odometry frame); the verdict is pending from then on.
  void askRelocation(const laser_features::Pose2D& door_odom, const laser_features::Pose2D& robot_odom, Decision* d);
  void follow(const Perception& p, const TopoView& topo, bool blocked, Decision* d);
  // The steps of roomStep() (place frame: the robot's position, the door's centre and the direction
  // into the room): to the door on its axis, the room's coverage, the way out.
  void approachDoor(const Perception& p, const Eigen::Vector2d& robot, const Eigen::Vector2d& door,
                    const Eigen::Vector2d& into, Decision* d);
  void coverRoom(const Perception& p, const Eigen::Vector2d& robot, const Eigen::Vector2d& door, Decision* d);
  void leaveRoom(const Perception& p, const Eigen::Vector2d& robot, const Eigen::Vector2d& door,
                 const Eigen::Vector2d& into, Decision* d);
  // The states' steps of update(): the start (which way to set off), a turn on the spot, the stop
  // at a door (enter it, or on if pomdp_topo took it for a known one), a place created for the room.
  void start(const Perception& p, const TopoView& topo, Decision* d);
  void turn(const Perception& p, bool motion_reached, bool motion_blocked, Decision* d);
  void stopForDoor(const Perception& p, const TopoView& topo, Decision* d);
  void enterRoom(const Perception& p, const TopoView& topo, Decision* d);
  /// Pieces of follow(); those returning bool end the tick when true (a decision was made).
  void recordWaysNotTaken(bool sure, Decision* d);  // the ways not taken at the last turn, at its node
  /// On the known map with a sure belief: the route, the end of the exploration or mission, and a
  /// turn round or an opening given up for it.
  bool followRoute(const Perception& p, const TopoView& topo, RouteStep* route, Decision* d);
  /// Marks the route's goal opening explored (given up unreached) and says so.
  void giveUpRouteGoal(const RouteStep& route, Decision* d);
  bool giveUpGoalPassed(const TopoView& topo, const RouteStep& route, int near, Decision* d);
  bool turnRoundForRoute(const Perception& p, const TopoView& topo, const RouteStep& route, int near, Decision* d);
  bool enterPassedDoor(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v, Decision* d);
  bool turnIntoRouteBranch(const Perception& p, const TopoView& topo, const RouteStep& route, bool sure,
                           double dir_robot, const HallwayView& v, Decision* d);
  void decideAtEnd(const Perception& p, const TopoView& topo, const HallwayView& v, Decision* d);
  bool mayEnter(const TopoView& topo, const DoorTrack& door);
  /// Opening `o` is the opening at `bearing` (map frame, rad) measured `width` (m) wide.
  bool sameOpening(const GraphOpening& o, double bearing, double width) const;
  /// On the frontier, the node pomdp_topo is at has `door` already, explored (pomdp_topo joined
  /// the door to that node rather than making a new one).
  bool exploredAtFrontierNode(const TopoView& topo, const DoorTrack& door) const;
  bool beliefPlausible(const TopoView& topo);
  /// The goal of a turn on the spot: where the robot is now, with the turn's heading.
  void turnGoal(const Perception& p, Decision* d) const;
  void startTurn(int bin, const Perception& p, const TopoView& topo, std::vector<int> not_taken);
  void room(const Perception& p, Decision* d);
  /// On the way to a new room's door: the door as seen now (the mean of its sightings on the
  /// approach) replaces door_in_place_ when it differs by more than 5 cm; true if it did.
  bool refineDoor(const Perception& p);
  void roomStep(const Perception& p, Decision* d);  // with the robot's pose in the place
  void goalInPlace(const Perception& p, const Eigen::Vector2d& g, std::optional<double> theta, Decision* d) const;
  void finish(bool success, const std::string& why, Decision* d);
  /// The route the robot follows: to the mission's door, or to the nearest unexplored opening.
  RouteStep plan(const GraphPosition& pos) const;
  void endMission(bool success, const std::string& why, Decision* d);
  void relocate(const Perception& p, const TopoView& topo, Decision* d);
  void missionGoal(const Perception& p, Decision* d);
  /// Into GoToGoal; `inside`: the robot is in the room already (not at its door).
  void beginGoToGoal(const std::string& text, bool inside);

  CoordinatorParams params_;
  laser_features::HeadingBins bins_;  // pomdp_topo's, from building_axes
  TopoGraph graph_;
  RoomExplorer room_;
  State state_ = State::Init;
  CoordinatorMode mode_ = CoordinatorMode::Topological;
  std::string state_text_ = "waiting for the first scan and the topological map";
  CoordinatorStats stats_;
  double state_since_ = 0.0;     // s, stamp when the state began
  double now_ = 0.0;
  double start_time_ = -1.0;
  bool have_last_odom_ = false;
  laser_features::Pose2D last_odom_;

  // Hallway following.
  int bin_ = 0;                  // travel heading bin (map frame)
  double axis_offset_ = 0.0;     // rad, the hallway followed runs this far from bin_'s heading (a wing at
                                 // an angle to the building's axes; 0 along them)
  Eigen::Vector2d stall_anchor_ = Eigen::Vector2d::Zero();  // odometry frame: where the stall window began
  double stall_since_ = -1.0;    // s, when (-1: not following)
  bool lane_valid_ = false;      // a lane past an obstacle is being kept ...
  Eigen::Vector2d lane_point_odom_ = Eigen::Vector2d::Zero();  // ... through this point (odometry frame)
  bool have_goal_ = false;
  Eigen::Vector2d last_goal_ = Eigen::Vector2d::Zero();
  HallwayDoors doors_;  // the doors along the hallway being followed
  // Each side's wall line where last seen (a point on it, odometry frame; 0 left, 1 right) and the
  // travel then. A wall broken into pieces shorter than wall_min_length by the doors in it is not
  // seen as a wall, but a gap behind it is still no door (large_floor: a 0.97 m "door" 1.63 m to
  // the left of a hallway whose wall is 1.1 m away, with no wall seen on that side).
  int route_behind_ticks_ = 0;     // consecutive ticks the route pointed back (U-turn hysteresis)
  int trusted_node_ = -1;          // the belief's node when last trusted
  double trusted_travel_ = 0.0;    // m, travel_ when it became the trusted node
  double distrust_until_ = 0.0;    // m, travel_ before which a jumped belief is not acted on
  long refused_branch_node_ = -1;  // the last node whose branch turn was refused (a door beside)
  int goal_pass_node_ = -1;        // the route's goal node the robot is at (as the belief says)
  double goal_pass_travel_ = 0.0;  // m, travel_ when it got there
  std::map<uint32_t, int> route_attempts_;  // U-turns towards each goal node
  std::map<std::pair<uint32_t, uint32_t>, int> branch_turns_;  // turns into (node's branch, towards goal node)
  int enter_node_ = -1;                     // the known door's node being entered (-1: a new door)
  double enter_bearing_ = 0.0;              // rad, map frame, its opening's bearing
  double last_turn_travel_ = -1e9;  // m, travel_ at the last turn
  // Turning.
  int turn_bin_ = 0;
  double turn_odom_heading_ = 0.0;
  std::vector<int> pending_branches_;  // bins to record as unexplored after the turn
  double pending_branch_travel_ = -1.0;
  double travel_ = 0.0;
  // Room.
  DoorTrack door_;
  // The door the robot last came out of, and the travel then: never entered again from just outside
  // it (large_floor: room_2_12 entered again 1.6 s after leaving it, its door seen anew from beside
  // it while pomdp_topo was still on the frontier).
  std::optional<DoorTrack> left_door_;
  double left_door_travel_ = 0.0;
  // The node pomdp_topo's frontier was last at, and the travel when it became so.
  int frontier_node_ = -1;
  double frontier_node_travel_ = 0.0;
  double door_bearing_map_ = 0.0;  // rad, map frame, through the door into the room
  double exit_theta_place_ = 0.0;  // rad, the hallway heading in the place frame
  int door_node_ = -1;
  int place_id_ = -1;
  laser_features::Pose2D hallway_pose_odom_;  // where the robot left the hallway
  laser_features::Pose2D door_in_place_;
  Eigen::Vector2d door_tracked_in_place_ = Eigen::Vector2d::Zero();  // the new room's door as tracked from the hallway
  Eigen::Vector2d door_seen_sum_ = Eigen::Vector2d::Zero();  // its sightings on the approach (place frame)
  int door_seen_count_ = 0;
  int hallway_bin_ = 0;
  double hallway_offset_ = 0.0;  // rad, axis_offset_ of the hallway left for the room
  bool place_ok_ = false;
  std::vector<Eigen::Vector2d> exit_path_;  // place frame
  size_t exit_index_ = 0;
  int exit_step_ = 0;               // ExitDoor: 0 inside the door, 1 outside, 2 back on the hallway
  int exit_attempts_ = 0;           // ways out of the room tried that ended still inside it
  static constexpr int kExitAttempts = 3;
  static constexpr double kDoorPassage = 1.0;  // m, from the door's centre: where the robot passes it
  double exit_step_since_ = 0.0;
  laser_features::Pose2D place_origin_odom_;  // the place's origin in the odometry frame (as the EKF last placed it)
  bool reached_ = false, blocked_ = false;    // the motion controller's last status
  double last_room_plan_ = -1e9;
  std::optional<Eigen::Vector2d> room_goal_;
  bool exit_retried_ = false;
  Eigen::Vector2d hallway_in_place_ = Eigen::Vector2d::Zero();  // where the robot left the hallway, place frame
  Eigen::Vector2d last_room_position_ = Eigen::Vector2d::Zero();  // the robot in the place, last tick
  bool in_room_ = false;            // Idle: the robot stands in place place_id_ (after a mission)
  // Mission.
  bool mission_active_ = false;
  int mission_place_ = -1;
  laser_features::Pose2D mission_goal_;
  PlaceDoor mission_door_;
  double mission_start_travel_ = 0.0;
  double mission_start_time_ = 0.0;
  double mission_distance_left_ = 0.0;
  MissionOutcome mission_outcome_;
  std::vector<Request> pending_requests_;  // to go out with the next update (from cancelMission)
  bool relocation_pending_ = false;   // Relocate: no verdict yet
  bool relocation_ok_ = false;
  std::string relocation_verdict_;
  int relocation_failures_ = 0;
  int mission_door_misses_ = 0;
  int relocate_step_ = 0;             // Relocate: 0 from the hallway, 1 moving in front of the door, 2 from there
  double relocate_step_since_ = 0.0;
  bool relocation_retried_ = false;   // Relocate: a second relocation asked for from in front of the door
  laser_features::Pose2D mission_goal_odom_;  // GoToGoal: the goal as last sent, odometry frame
  bool mission_goal_odom_valid_ = false;
  int mission_refines_ = 0;         // GoToGoal: times the goal was sent again after the controller reached it
  bool mission_entered_ = false;    // GoToGoal: the robot has been entry_depth inside the door
  std::vector<Eigen::Vector2d> mission_path_;  // GoToGoal: grid path to the goal (place frame)
  size_t mission_path_index_ = 0;
  double mission_best_ = 0.0;       // m, GoToGoal: the shortest way left to the goal so far ...
  double mission_best_time_ = 0.0;  // s, ... when it got 5 cm shorter last
  double mission_path_length_ = 0.0;  // m, GoToGoal: the last grid path's length (straight: the distance)
  bool mission_had_path_ = false;     // GoToGoal: the last plan found a grid path
};

}  // namespace exploration
