// Rooms reachable only through another room (a suite: a back room behind a front room, a room whose
// only door is in its neighbour's wall). Once a room (the host) is covered, each of its inner doors
// (RoomVisit::innerDoors: not in the wall of the door it was entered by) is visited: the robot drives
// on the host's grid to the front of the door, facing it; a place is created there for the room behind
// (the host's place stands where the hallway stood for the host: the robot left the host's floor
// there), and that room is visited as any room (RoomVisit: in through the door on its axis, covered
// behind a virtual wall, out by the same door back to where the robot stood). Then the next inner
// door, and at last the host's own way out. The doors seen from inside the rooms behind (a
// connecting room's own hallway door) are kept for the hallway: passed a moment later, they are
// another door of a room just mapped, not a new room.
//
// One level: the rooms behind are not searched for inner doors of their own.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/room_explorer.h"
#include "exploration/room_visit.h"
#include "laser_features/building_rules.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace exploration {

/// SuiteVisit::hallwayBehind's rule for a door at `door_in_place` (centre, direction into the space)
/// seen from `q` (in the same place): the space's depth ahead and its extents along the door's wall.
bool hallwayBehindDoor(const Perception& q, const laser_features::Pose2D& door_in_place,
                       const laser_features::BuildingRules& rules, std::string* why = nullptr);

class SuiteVisit {
 public:
  SuiteVisit(const RoomVisitParams& params, const RoomExplorerParams& room, const laser_features::BuildingRules& rules,
             const HallwayDoorParams& doors);

  /// A room's coverage ended, `travel` (m) into the run: its extent (odometry frame) is kept for
  /// kRecentTravel of travel.
  void roomCovered(const RoomVisit& room, double travel);
  /// The host's coverage is over, `travel` (m) into the run: its inner doors become the doors to
  /// visit, but for those into a room covered within the last kRecentTravel (the space kDoorPassage
  /// behind the door lies in its extent: a connecting room entered from the hallway a moment ago).
  void begin(const RoomVisit& host, double travel);
  /// The next inner door to visit, the nearest to the robot (`robot`, host place) on the host's
  /// grid: a path to its front is planned. False when no door is left (the doors whose front no
  /// path reaches are dropped).
  bool nextDoor(RoomVisit& host, const Eigen::Vector2d& robot);

  enum class Drive { Driving, There, Failed };
  /// Along the path to the door's front (kFront from it, on the host's side), then facing the door.
  /// Failed after the room visit's exit_time_limit of `elapsed`.
  Drive driveToDoor(const RoomVisit& host, const Perception& q, double elapsed, Decision* d);

  /// The room behind the door begins: its place was created with the robot at its origin, standing
  /// at the door's front (`robot_odom`).
  void beginInnerRoom(const RoomVisit& host, const laser_features::Pose2D& robot_odom);
  /// Whether an inner room's visit runs (from beginInnerRoom() to endInnerRoom()).
  bool insideInner() const { return inside_; }
  RoomVisit& inner() { return inner_; }
  const RoomVisit& inner() const { return inner_; }
  /// The inner room was left, back at the door's front: its doors seen from inside are kept (not
  /// when it was a hallway: the doors across a hallway are other rooms').
  void endInnerRoom();
  /// Each scan of an inner room's visit (`q`, in its place): whether the robot stands past its door,
  /// and once it got in (RoomExplorer::entered), whether the space is a hallway (hallwayBehind).
  void observeInner(const Perception& q);
  /// The robot stands past the inner door's line (observeInner).
  bool throughDoor() const { return through_; }
  /// The space behind the inner door was found to be a hallway (observeInner): the visit ends.
  bool hallway() const { return hallway_; }
  /// Once checked (observeInner): the space's depth and extents along the door's wall, for the log.
  const std::string& space() const { return space_; }
  /// The space behind the inner door, seen from just inside it (`q`, in its place), is a hallway, not
  /// a room (a corner room's second door into another hallway): no deeper than the widest hallway
  /// (building rules: hallway_max_width + width_tolerance) straight ahead, and open farther than that
  /// along the door's wall on both sides. A room entered by a door in its side wall is as deep as the
  /// row it is in (3.5-14 m on office floors), or its side walls lie within hallway_max_width of the
  /// door on one side (a room narrower than the widest hallway and deeper than twice it, with the door
  /// near the middle of its side wall, is taken for a hallway: the assumption's limit).
  /// `why`: the space's depth and its extents along the wall, for the log.
  bool hallwayBehind(const Perception& q, std::string* why = nullptr) const;
  /// The doors seen from inside the inner rooms visited since begin() (odometry frame).
  const std::vector<DoorTrack>& innerRoomDoorsOdom() const { return inner_doors_odom_; }

  static constexpr double kFront = 1.0;  // m, the robot stands this far in front of an inner door (RoomVisit::kDoorPassage)
  // m: rooms covered within this much travel are compared in the odometry frame. Wheel odometry
  // drifts 1-2 % of the distance (0.3-0.6 m over it); the point compared lies kDoorPassage inside
  // the room behind.
  static constexpr double kRecentTravel = 30.0;

 private:
  RoomVisitParams params_;
  laser_features::BuildingRules rules_;
  RoomVisit inner_;
  std::vector<RoomVisit::DoorInPlace> todo_;  // the host's inner doors not visited yet (host place)
  RoomVisit::DoorInPlace door_;               // the one being visited
  std::vector<Eigen::Vector2d> path_;          // to its front, host place
  std::size_t path_index_ = 0;
  bool inside_ = false;
  bool through_ = false;   // observeInner: past the inner door's line
  bool checked_ = false;   // ... the space behind was checked for a hallway
  bool hallway_ = false;
  std::string space_;
  std::vector<DoorTrack> inner_doors_odom_;
  std::vector<std::pair<RoomExtent, double>> recent_rooms_;  // extents (odometry frame), travel when covered
};

}  // namespace exploration
