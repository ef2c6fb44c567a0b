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
// The Coordinator runs the state machine, follows the hallways and chooses the route; a room's
// visit (RoomVisit, room_visit.h) and a mission's relocation and drive to its goal (MissionRunner,
// mission_runner.h) are classes of their own that it delegates to.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/hallway_view.h"
#include "exploration/mission_runner.h"
#include "exploration/room_explorer.h"
#include "exploration/room_visit.h"
#include "exploration/topo_route.h"
#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"

#include <Eigen/Core>

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
  RoomVisitParams room_visit;        // a room's visit (room_visit/* in config/exploration.yaml)
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
  MissionParams mission;             // missions (mission/* in config/exploration.yaml)
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
  bool missionActive() const { return mission_.active(); }
  /// The last mission's outcome (finished once it ended).
  const MissionOutcome& missionOutcome() const { return mission_.outcome(); }
  /// m, the mission's expected distance left (along the graph, then straight to the goal).
  double missionDistanceLeft() const { return mission_.distanceLeft(); }
  /// Idle: no exploration and no mission runs (the robot stands, in a room or in a hallway).
  bool idle() const { return state_ == State::Idle || state_ == State::Done; }

  CoordinatorMode mode() const { return mode_; }
  const std::string& state() const { return state_text_; }
  const CoordinatorStats& stats() const { return stats_; }
  int currentPlace() const { return place_id_; }
  const RoomExplorer& room() const { return visit_.explorer(); }
  bool done() const { return state_ == State::Done; }

 private:
  enum class State { Init, Follow, Turn, StopForDoor, EnterRoom, ApproachDoor, Room, ExitPath, ExitDoor, Done,
                     Idle, Relocate, GoToGoal };

  void setState(State s, const std::string& text);
  /// The door passed is one the robot came out of a moment ago (see left_doors_).
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
  /// map frame, and square to the axes where a wing's hallway runs at axis_offset_ to them (a node's
  /// side openings are bin heading +-90 deg in pomdp_topo's map).
  double topoBearing(double odom_bearing, const TopoView& topo) const;
  /// At a hallway's end with no way open along the axes: a hallway leaving at an angle (a wing),
  /// its direction in the robot frame.
  std::optional<double> obliqueWayAtEnd(const Perception& p, double dir_robot, const HallwayView& v) const;
  /// The lane (lateral offset, m, robot frame) past an obstacle ahead in the hallway, if there is one.
  std::optional<double> laneAround(const Perception& p, double dir_robot, const HallwayView& v, bool blocked);
  /// Following without progress for follow_stall_time (see there).
  bool followStalled(const Perception& p);
  void follow(const Perception& p, const TopoView& topo, bool blocked, Decision* d);
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
  void finish(bool success, const std::string& why, Decision* d);
  /// The route the robot follows: to the mission's door, or to the nearest unexplored opening.
  RouteStep plan(const GraphPosition& pos) const;
  // A room's visit (visit_ in the room's place; the METRIC states): the visit's steps by state, and
  // what they end in.
  void visitRoom(const Perception& p, Decision* d);
  void approachDoor(const Perception& q, Decision* d);
  void coverRoom(const Perception& q, Decision* d);
  void leaveRoom(const Perception& q, Decision* d);
  /// Out of the room, back on the hallway (`exact`: where the robot left it, with its heading).
  void backOnHallway(bool exact, Decision* d);
  // A mission's steps (mission_): out of the room the robot stands in, the relocation at the goal's
  // door, the drive to the goal, the end.
  void leaveRoomForMission(const std::string& text);
  void beginRelocation(const Perception& p, Decision* d);
  void relocate(const Perception& p, const TopoView& topo, Decision* d);
  /// Into GoToGoal; `inside`: the robot is in the room already (not at its door).
  void beginGoToGoal(const std::string& text, bool inside);
  void endMission(bool success, const std::string& why, Decision* d);

  CoordinatorParams params_;
  laser_features::HeadingBins bins_;  // pomdp_topo's, from building_axes
  TopoGraph graph_;
  RoomVisit visit_;
  MissionRunner mission_;
  State state_ = State::Init;
  CoordinatorMode mode_ = CoordinatorMode::Topological;
  std::string state_text_ = "waiting for the first scan and the topological map";
  CoordinatorStats stats_;
  double state_since_ = 0.0;     // s, stamp when the state began
  double now_ = 0.0;
  double start_time_ = -1.0;
  bool have_last_odom_ = false;
  laser_features::Pose2D last_odom_;
  double travel_ = 0.0;          // m, odometric
  MotionFeedback motion_;          // the motion controller's last status in a room's states

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
  // The door being entered, and the place of its room.
  DoorTrack door_;
  // The doors the robot came out of within the last kLeftDoorsTravel of travel, and the travel then:
  // none is entered again from just outside it (two doors facing the robot in turn at a hallway's
  // end would otherwise be entered again and again).
  std::vector<std::pair<DoorTrack, double>> left_doors_;
  static constexpr double kLeftDoorsTravel = 10.0;  // m
  // The node pomdp_topo's frontier was last at, and the travel when it became so.
  int frontier_node_ = -1;
  double frontier_node_travel_ = 0.0;
  double door_bearing_map_ = 0.0;  // rad, map frame, through the door into the room
  int door_node_ = -1;
  int place_id_ = -1;
  laser_features::Pose2D hallway_pose_odom_;  // where the robot left the hallway
  int hallway_bin_ = 0;
  double hallway_offset_ = 0.0;  // rad, axis_offset_ of the hallway left for the room
  bool place_ok_ = false;
  bool in_room_ = false;            // Idle: the robot stands in place place_id_ (after a mission)
  std::vector<Request> pending_requests_;  // to go out with the next update (from cancelMission)
};

}  // namespace exploration
