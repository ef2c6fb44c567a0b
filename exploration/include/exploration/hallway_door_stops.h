// The doors the robot stops at along a hallway, to enter their rooms (the TOPOLOGICAL mode's half
// that HallwayNavigator hands doors to): the doors passed (HallwayDoors), the doors beside a
// hallway's end it turned at, a door in a dead end's end wall; whether one is entered (DoorEntry:
// new, or known and unexplored, from a sure belief), recorded explored when it is a door of a room
// mapped already, and the door stopped at with the opening it is entered as.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/door_entry.h"
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

/// The map and the robot on it this tick, as the hallway's navigation sees them.
struct HallwayContext {
  const TopoGraph& graph;         // the topological map as last published
  double travel;                  // m, odometric
  const PlaceDoor* mission_door;  // the running mission's door; none while exploring
};

/// What a tick of following the hallway came to (HallwayNavigator::follow()).
struct HallwayStep {
  enum Kind {
    Following,    // on along the hallway (its goal set; none the tick an opening is given up)
    Turning,      // a turn on the spot begins (its goal set): turn() until it is done
    StopForDoor,  // a door passed is entered (door()): the robot stops
    Complete,     // on the known map no unexplored opening is left, none set aside (no mission runs)
    NoRoute,      // the mission's door has no route on the topological map
    MissedDoor,   // the mission's door was not found after max_route_attempts turns towards it
  };
  Kind kind = Following;
  std::string text;  // the state text (Following, Turning, StopForDoor)
  RouteStep route;   // the route planned this tick on the known map (found: false if none was)
};

/// A hallway at an angle leaving a hallway's end: its line in the odometry frame. It is found from
/// where the crossing's centre is expected, not from where the robot turns: the line is followed
/// for `length` m before the hallway is judged from the robot (the sector from beside its mouth
/// meets the mouth's corner).
struct WayLine {
  Eigen::Vector2d origin;  // odometry frame
  double heading = 0.0;
  double length = 0.0;
};

class HallwayDoorStops {
 public:
  /// `follower` gives a door's bearing on the topological map, `route` whether the belief is
  /// trusted; both outlive this (they are the navigator's, as this is).
  HallwayDoorStops(const HallwayDoorParams& params, const laser_features::BuildingRules& rules,
                   const HallwayFollower& follower, const RoutePolicy& route);
  HallwayDoorStops(const HallwayDoorStops&) = delete;
  HallwayDoorStops& operator=(const HallwayDoorStops&) = delete;

  void setHeadingBins(const laser_features::HeadingBins& bins) { entry_.setHeadingBins(bins); }
  /// Each tick, whatever the state: the node pomdp_topo's frontier stands at, and the travel (m).
  void observe(const TopoView& topo, double travel) { entry_.observe(topo, travel); }

  /// Each tick of following: driven on from the end turned at (beyond the span of two doors from
  /// where it turned or came back out of a room), the doors left there are behind.
  void forgetEndPassed(double travel);
  /// Pieces of HallwayNavigator::follow(); true ends the tick with a stop (`step` says which door).
  /// The door beside the hallway's end (HallwayDoors::besideEnd) the robot turned at, once turned.
  bool enterAfterTurn(const Perception& p, const TopoView& topo, const HallwayContext& at, HallwayStep* step,
                      Decision* d);
  /// The doors along the hallway are tracked this tick; one passed is entered if it may be.
  bool enterPassed(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v,
                   const HallwayContext& at, HallwayStep* step, Decision* d);
  /// At a dead end (no side open), a door in the end wall is entered as a door passed would be.
  bool enterInEndWall(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v,
                      const HallwayContext& at, HallwayStep* step, Decision* d);
  /// A door tracked abeam on the side `side` (+1 left, -1 right): no branch of the route.
  std::optional<DoorTrack> abeam(const laser_features::Pose2D& odom, double dir_robot, double side) const {
    return doors_.abeam(odom, dir_robot, side);
  }

  /// The doors tracked now, before a turn forgets them (turned()).
  const HallwayDoors& tracked() const { return doors_; }
  /// The robot turned at a hallway's end (not blocked): of the doors `at_end` tracked there, the one
  /// beside the end is entered once turned (`turned_back`: a U-turn), every other one in turn after
  /// (one passed on the way back is entered only while the stretch is new, and a room visit from
  /// the end can outlast that); none in the mouth of a hallway at an angle `at_angle` leaving it.
  void rememberAtEnd(HallwayDoors at_end, const Perception& p, double dir_robot, const HallwayView& v,
                     bool turned_back, const std::vector<WayLine>& at_angle, TopoMode mode, double travel);
  /// A turn begins: the doors and walls seen so far belong to the hallway being left.
  void turned();
  /// Out of a room by `door_left` at `travel` (m), back on the hallway: neither it nor the room's
  /// `other_doors` are entered again; the next door left at the end turned at is offered. The doors
  /// tracked before move by the odometry's `drift` in the room (HallwayDoors::roomVisited).
  void backFromRoom(const DoorTrack& door_left, const std::vector<DoorTrack>& other_doors, double travel,
                    const std::optional<laser_features::Pose2D>& drift);
  /// The room of place `place_id` is mapped (DoorEntry::roomMapped).
  void roomMapped(int place_id, const laser_features::Pose2D& origin_map,
                  const std::vector<laser_features::Pose2D>& doors_in_place) {
    entry_.roomMapped(place_id, origin_map, doors_in_place);
  }

  /// The door the robot last stopped at, as tracked.
  const DoorTrack& door() const { return door_; }
  /// Stopped at door(): the opening it is entered as; none when pomdp_topo has since taken it for
  /// a known one or for its node's explored one (it is passed, `why_passed` says so).
  std::optional<EntryOpening> enterAfterStop(const TopoView& topo, const HallwayContext& at, std::string* why_passed);

  int doorsPassed() const { return doors_passed_; }  // doors not entered
  int mappedRoomDoors() const { return mapped_room_doors_; }  // among them, doors of rooms mapped earlier

 private:
  /// A door passed or beside the end: stops to enter it (true) unless it is the door just left,
  /// another door of the room just left or of a room mapped (recorded explored) or not to be
  /// entered (DoorEntry). `what` begins the state's text.
  bool stopAt(const DoorTrack& door, const char* what, const Perception& p, const TopoView& topo,
              const HallwayContext& at, HallwayStep* step, Decision* d);
  /// `door` lies in the mouth of one of the hallways at an angle `at_angle`: within half its width
  /// (and a measured edge's error) of the way's line, not behind the way's origin. A wing's mouth is
  /// as wide as a double door and has free space behind it as a room does.
  bool inMouthOfWay(const DoorTrack& door, const std::vector<WayLine>& at_angle) const;
  /// The next door left at the end turned at last becomes the door to enter after the turn.
  void nextAtEnd();
  /// The opening `door` is entered as, if it is (DoorEntry::mayEnter, from the belief now).
  std::optional<EntryOpening> mayEnter(const TopoView& topo, const HallwayContext& at, const DoorTrack& door) const;

  const HallwayFollower& follower_;
  const RoutePolicy& route_;
  HallwayDoors doors_;  // the doors along the hallway being followed
  HallwayDoors::Walls walls_;  // the walls the doors were gated with this tick
  DoorEntry entry_;
  std::optional<DoorTrack> after_turn_;  // beside the hallway's end: entered once turned
  // The other doors beside that end (between the robot and the end wall), each offered in turn once
  // the robot is back from a room entered there: the robot leaves a hallway's end by the way it came,
  // and passes none of them on it.
  std::vector<DoorTrack> left_at_end_;
  TopoMode after_turn_mode_ = TopoMode::Frontier;  // the belief's mode when that end was reached
  double end_travel_ = 0.0;  // m, travel when the robot turned at that end or came back out of a room there
  // The door stopped at, and the opening it is entered as.
  DoorTrack door_;
  EntryOpening entering_;
  int doors_passed_ = 0, mapped_room_doors_ = 0;
};

}  // namespace exploration
