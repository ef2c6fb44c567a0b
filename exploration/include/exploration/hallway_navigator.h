// Navigating the hallways (Tomatis, Nourbakhsh & Siegwart 2001, section 3.1), the TOPOLOGICAL mode:
// each tick of following a hallway's mid-line (HallwayFollower), the doors it stops at to enter
// (HallwayDoorStops), the route on the known map (RoutePolicy), and the turns:
// at a hallway's end into an open way (left first, or the route's), the ways not taken recorded as
// unexplored openings of the node once the map builder has made it, a U-turn at a dead end; a turn
// round or into a branch for the route.
//
// HallwayNavigator says what a tick came to (HallwayStep): on along the hallway, a turn begun, a
// stop at a door to enter its room, no unexplored opening left, a mission's door unreachable or
// missed. The coordinator's state machine carries that out: it ends the exploration or the mission,
// and switches to the room.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/door_entry.h"
#include "exploration/grid_planner.h"
#include "exploration/hallway_door_stops.h"
#include "exploration/hallway_doors.h"
#include "exploration/hallway_follower.h"
#include "exploration/hallway_view.h"
#include "exploration/route_policy.h"
#include "exploration/topo_route.h"
#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"

#include <optional>
#include <string>
#include <vector>

namespace exploration {

/// The counts of the hallway's navigation (in CoordinatorStats).
struct HallwayStats {
  int doors_passed = 0;  // doors not entered (explored already, or the belief unconfident)
  int mapped_room_doors = 0;  // among them, doors of rooms mapped earlier, linked to their places
  int turns = 0, u_turns = 0;
};

class HallwayNavigator {
 public:
  /// `branch_record_distance` (m): travelled after a turn before the ways not taken are recorded.
  HallwayNavigator(const HallwayFollowerParams& follow, const HallwayViewParams& view,
                   const laser_features::BuildingRules& rules, const PlannerParams& robot,
                   const HallwayDoorParams& doors, const RoutePolicyParams& route, double branch_record_distance);
  /// The hallway view's parameters with their derived sizes.
  const HallwayViewParams& viewParams() const { return follower_.viewParams(); }
  HallwayStats stats() const {
    HallwayStats s = stats_;
    s.doors_passed = door_stops_.doorsPassed();
    s.mapped_room_doors = door_stops_.mappedRoomDoors();
    return s;
  }
  const RouteStats& routeStats() const { return route_.stats(); }

  /// The building's axes (pomdp_topo's building_axes): the discrete headings of the hallways.
  void setHeadingBins(const laser_features::HeadingBins& bins) {
    follower_.setHeadingBins(bins);
    door_stops_.setHeadingBins(bins);
    route_.setHeadingBins(bins);
  }
  const laser_features::HeadingBins& headingBins() const { return follower_.headingBins(); }

  /// Each tick, whatever the state: the node pomdp_topo's frontier stands at, and the travel (m).
  void observe(const TopoView& topo, double travel) { door_stops_.observe(topo, travel); }
  /// The coordinator's state changed: the stall window and the lane past an obstacle start again.
  void restart() { follower_.restart(); }

  // The start, once pomdp_topo's first messages are in (the robot may face any way).
  /// The direction followed is the bin the robot faces.
  void faceRobotsBin(const Perception& p, const TopoView& topo) { follower_.faceRobotsBin(p, topo); }
  /// Along the hallway the robot stands in: on a new stretch, mid-hallway, the way behind is
  /// requested as an unexplored opening of the start node. True when a turn onto it begins.
  bool setOff(const Perception& p, const TopoView& topo, Decision* d);

  /// One tick of following the hallway (`blocked`: the motion controller's status).
  HallwayStep follow(const Perception& p, const TopoView& topo, bool blocked, const HallwayContext& at, Decision* d);
  /// One tick of a turn on the spot: true once turned (the bin turned to is followed from then on).
  bool turn(const Perception& p, bool motion_reached, bool motion_blocked, double travel, Decision* d);

  /// The door the robot last stopped at (HallwayStep::StopForDoor), as tracked.
  const DoorTrack& door() const { return door_stops_.door(); }
  /// Stopped at door(): the opening it is entered as; none when pomdp_topo has since taken it for
  /// a known one or for its node's explored one (it is passed, `why_passed` says so).
  std::optional<EntryOpening> enterAfterStop(const TopoView& topo, const HallwayContext& at, std::string* why_passed) {
    return door_stops_.enterAfterStop(topo, at, why_passed);
  }

  /// The direction followed; the heading (odometry frame) of a direction's hallway.
  const HallwayDirection& direction() const { return follower_.direction(); }
  double odomHeading(const HallwayDirection& direction, const TopoView& topo) const {
    return follower_.odomHeading(direction, topo);
  }
  /// Out of a room by `door_left` (RoomVisit::doorOdom) at `travel` (m), back on the hallway along
  /// `direction`: a new goal on the mid-line; neither the door nor the room's `other_doors` (seen
  /// from inside it) are entered again from the hallway; the route's turns count from here. `drift`:
  /// the odometry's in the room as the EKF measured it (RoomVisit::odometryDrift; none: unmeasured).
  void backFromRoom(const HallwayDirection& direction, const DoorTrack& door_left,
                    const std::vector<DoorTrack>& other_doors, double travel,
                    const std::optional<laser_features::Pose2D>& drift);
  /// The room of place `place_id` is mapped (DoorEntry::roomMapped): none of its doors is entered
  /// again from a hallway.
  void roomMapped(int place_id, const laser_features::Pose2D& origin_map,
                  const std::vector<laser_features::Pose2D>& doors_in_place) {
    door_stops_.roomMapped(place_id, origin_map, doors_in_place);
  }
  /// The next goal is a new one (the robot leaves the hallway's mid-line for a while).
  void forgetGoal() { follower_.forgetGoal(); }
  /// A mission sets off along the hallway at `travel` (m): a new goal, and the route may turn the
  /// robot round at once.
  void beginMission(double travel) {
    follower_.forgetGoal();
    route_.allowTurnRound(travel);
  }
  /// The turns towards each goal of the route count afresh (a mission starts, its belief is reset).
  void clearRouteAttempts() { route_.clearAttempts(); }

 private:
  /// Pieces of follow(); those returning bool end the tick when true (`step` says how).
  void recordWaysNotTaken(bool sure, double travel, double stamp, Decision* d);  // the ways not taken at the last turn
  /// On the known map with a sure belief: the route (in `step`), the end of the exploration, a
  /// mission's door unreachable, and a turn round or an opening given up for it.
  bool followRoute(const Perception& p, const TopoView& topo, const HallwayContext& at, HallwayStep* step, Decision* d);
  /// Carries out what the route asks (a turn, an opening given up, a mission's door missed).
  bool actOnRoute(const RouteAction& action, const Perception& p, const TopoView& topo, HallwayStep* step, Decision* d);
  bool turnIntoRouteBranch(const Perception& p, const TopoView& topo, bool sure, double dir_robot, const HallwayView& v,
                           const HallwayContext& at, HallwayStep* step, Decision* d);
  /// The turn at a hallway's end (or where the robot is blocked): into an open way, else a U-turn.
  /// `at_angle`: the hallways at an angle found leaving the end (odometry frame).
  void turnAtEnd(const Perception& p, const TopoView& topo, const HallwayView& v, const HallwayContext& at,
                 HallwayStep* step, std::vector<WayLine>* at_angle);
  /// The hallway followed opened into an open area (HallwayFollower::intoOpenArea): a turn along its
  /// wall begins, unless a route leads across it (then false).
  bool turnInOpenArea(const TopoView& topo, const HallwayContext& at, HallwayStep* step);
  /// A turn on the spot onto `bin` begins; `not_taken`: bins to record as unexplored after it.
  void beginTurn(int bin, const TopoView& topo, std::vector<int> not_taken);
  /// Into a hallway at an angle just turned into: the goal on the way's line until the robot is in
  /// it (true; its goal set), or none (false).
  bool intoWayAtAngle(const Perception& p, bool blocked, Decision* d);
  /// The goal of a turn on the spot: where the robot is now, with the turn's heading.
  void turnGoal(const Perception& p, Decision* d) const;
  /// The belief is localized and confident, and not on hold after a jump.
  bool beliefTrusted(const TopoView& topo, double travel) const { return route_.beliefTrusted(topo, travel); }

  double branch_record_distance_;
  HallwayFollower follower_;
  RoutePolicy route_;
  HallwayDoorStops door_stops_;  // after follower_ and route_, which it reads
  HallwayStats stats_;  // turns and U-turns (the door counts are door_stops_')
  // Turning.
  int turn_bin_ = 0;
  double turn_odom_heading_ = 0.0;
  std::vector<int> pending_branches_;  // bins to record as unexplored after the turn
  // A way out of a hallway's end: its bin, and for a hallway at an angle its way.
  struct EndWay {
    int bin = 0;
    std::optional<ObliqueWay> oblique;
  };
  std::optional<WayLine> way_line_;  // the hallway at an angle just turned into (intoWayAtAngle)
  double pending_branch_travel_ = -1.0;
  double u_turn_travel_ = -1e9;  // m, travel at the last U-turn at a hallway's end
  // s, when ways not taken were last recorded: no "complete" until pomdp_topo's map has them (it is
  // published after every scan; kRecordSettleTime is many scans).
  double recorded_stamp_ = -1e9;
  static constexpr double kRecordSettleTime = 2.0;
};

}  // namespace exploration
