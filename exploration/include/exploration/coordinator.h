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
//    to the place, and the topological map resumes (it stood still meanwhile). Before it leaves, each
//    room behind a door of the room that is not in its entry's wall is visited the same way, from
//    the room (SuiteVisit, suite_visit.h): a place of its own, covered, left by that door.
//  - Never from topological to metric while the belief is unconfident (or a loop closure is being
//    verified): the robot keeps following the hallway (which gathers landmarks) until confident.
//  - Done when the map builder is on the known graph, confident, and no unexplored opening is left.
//
// The coordinator does not talk to the other nodes itself: it returns requests (create a place,
// record an opening, ...) that its node carries out as service calls and answers.
//
// The Coordinator runs the state machine: the start, the switch at a door between the hallway and
// the room, missions, the end. Navigating the hallways (HallwayNavigator, hallway_navigator.h:
// following a hallway, the doors passed and whether one is entered, the route, the turns), a room's
// visit with the rooms behind it (RoomSequence, room_sequence.h) and a mission's relocation and drive
// to its goal (MissionRunner, mission_runner.h) are classes of their own that it delegates to.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/coordinator_params.h"
#include "exploration/door_entry.h"
#include "exploration/hallway_follower.h"
#include "exploration/hallway_navigator.h"
#include "exploration/mission_runner.h"
#include "exploration/progress_watch.h"
#include "exploration/room_explorer.h"
#include "exploration/room_sequence.h"
#include "exploration/topo_route.h"
#include "laser_features/building_axes.h"
#include "laser_features/geometry.h"

#include <cstddef>
#include <string>
#include <vector>

namespace exploration {

struct CoordinatorStats {
  int places = 0;
  int rooms_left_early = 0;   // rooms whose exploration hit the time limit
  int inner_rooms = 0;        // rooms entered from another room (SuiteVisit), among places
  int inner_doors_left = 0;   // inner doors looked through and left: a hallway or a connecting room behind
  int inner_doors_given_up = 0;  // inner doors no path reached, or not reached or looked through in time
  int doors_entered = 0;
  int doors_passed = 0;       // doors not entered (explored already, or the belief unconfident)
  int mapped_room_doors = 0;  // among them, doors of rooms mapped earlier, linked to their places
  int openings_given_up = 0;  // openings the route kept missing (see max_route_attempts), also when tried once more
  int openings_set_aside = 0;  // openings the route missed the first time (tried again when the others are explored)
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
  const CoordinatorParams& params() const { return params_; }

  /// The building's axes as pomdp_topo found them (its building_axes topic): the discrete
  /// headings of the hallways. Set before the first update().
  void setHeadingBins(const laser_features::HeadingBins& bins) { hallway_.setHeadingBins(bins); }
  const laser_features::HeadingBins& headingBins() const { return hallway_.headingBins(); }

  /// The topological map as last published.
  void setGraph(const TopoGraph& graph) {
    graph_ = graph;
    progress_.mapChanged(graph_);
  }
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
  const std::string& state() const { return state_ == State::Room ? room_.text() : state_text_; }
  CoordinatorStats stats() const;
  int currentPlace() const { return places_.place_id; }
  /// The place the robot is in: currentPlace(), but the host room's place until the robot has
  /// passed the door of a room behind it (on its way in and out).
  int placeOfRobot() const { return room_.placeOfRobot(places_.place_id); }
  const RoomExplorer& room() const { return room_.visit().explorer(); }
  bool done() const { return state_ == State::Done; }

 private:
  // Room: a room's visit runs (room_, its steps); GoToGoal: a mission's drive in its goal's room.
  enum class State { Init, Follow, Turn, StopForDoor, EnterRoom, Room, Done, Idle, Relocate, GoToGoal };

  void setState(State s, const std::string& text);
  // The states' steps of update(): the start (which way to set off), following the hallway, a turn
  // on the spot, the stop at a door (enter it, or on if pomdp_topo took it for a known one), a place
  // created for the room.
  void start(const Perception& p, const TopoView& topo, Decision* d);
  void follow(const Perception& p, const TopoView& topo, bool blocked, Decision* d);
  void turn(const Perception& p, bool motion_reached, bool motion_blocked, Decision* d);
  void stopForDoor(const Perception& p, const TopoView& topo, Decision* d);
  void enterRoom(const Perception& p, const TopoView& topo, Decision* d);
  /// The map and the robot on it, for the hallway's navigation.
  HallwayContext hallwayContext() const { return HallwayContext{graph_, travel_, missionDoor()}; }
  /// On the known map no unexplored opening is left: the exploration ends, complete only if no
  /// opening was given up and no room left at its time limit.
  void noOpeningLeft(Decision* d);
  /// The exploration makes no progress (ProgressWatch): it ends, incomplete.
  bool stalled(const TopoView& topo, Decision* d);
  /// The mission's door was not found after max_route_attempts turns towards it: the belief is
  /// reset, or the mission fails after max_relocation_failures such misses.
  void missedMissionDoor(const RouteStep& route, Decision* d);
  /// The running mission's door, if a mission runs.
  const PlaceDoor* missionDoor() const { return mission_.active() ? &mission_.door() : nullptr; }
  void finish(bool success, const std::string& why, Decision* d);
  /// A tick of the room's visit (room_; the METRIC states), and what it ends in.
  void visitRoom(const Perception& p, Decision* d);
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
  TopoGraph graph_;
  HallwayNavigator hallway_;
  RoomSequence room_;
  MissionRunner mission_;
  ProgressWatch progress_;
  State state_ = State::Init;
  CoordinatorMode mode_ = CoordinatorMode::Topological;
  std::string state_text_ = "waiting for the first scan and the topological map";
  CoordinatorStats stats_;  // all but the hallway's, the route's and the rooms' counts (hallway_, room_; all in stats())
  double state_since_ = 0.0;     // s, stamp when the state began
  double now_ = 0.0;
  double start_time_ = -1.0;
  bool have_last_odom_ = false;
  laser_features::Pose2D last_odom_;
  double travel_ = 0.0;          // m, odometric
  double hallway_travel_ = 0.0;  // m, odometric, in the hallway's states (Follow, Turn) only
  MotionFeedback motion_;          // the motion controller's last status in a room's states

  // The door being entered (hallway_.door()), the opening it is entered as, and the place of its room.
  double door_bearing_map_ = 0.0;  // rad, map frame, through the door into the room
  // The new room's place origin in the map frame (TopoView::map_from_odom at its creation): its
  // doors go to HallwayNavigator::roomMapped when the robot is out.
  std::optional<laser_features::Pose2D> place_origin_map_;
  int door_node_ = -1;
  RoomSequence::Places places_;     // the active place (the host's, or a room's behind it) and its creation
  laser_features::Pose2D hallway_pose_odom_;  // where the robot left the hallway ...
  HallwayDirection entry_hallway_;            // ... and that hallway's direction
  bool in_room_ = false;            // Idle: the robot stands in the active place (after a mission)
  std::vector<Request> pending_requests_;  // to go out with the next update (from cancelMission)
};

}  // namespace exploration
