// Rooms reachable only through another room (a suite: a back room behind a front room, a room whose
// only door is in its neighbour's wall). Once a room (the host) is covered, each of its inner doors
// (RoomVisit::innerDoors: not in the wall of the door it was entered by) is visited: the robot drives
// on the host's grid to the front of the door, facing it, and looks through it from just inside
// (peek()). Behind it lies
//  - a hallway (a corner room's second door: hallwayBehindDoor): left;
//  - a room with a door of its own onto the hallway the host was entered from (a connecting room:
//    doorOntoHostHallway): left to that hallway's exploration, which enters every room by its
//    hallway door. Entered from both sides, such a room would be two places, since nothing tells
//    the robot it is the room it mapped from the hallway (odometry over a room's coverage and more
//    is no proof);
//  - else a room reachable only through the host: back at the door's front, a place is created there
//    for it (the host's place stands where the hallway stood for the host: the robot left the host's
//    floor there), and that room is visited as any room (RoomVisit: in through the door on its axis,
//    covered behind a virtual wall, out by the same door back to where the robot stood).
// Then the next inner door, and at last the host's own way out. No place is made before the look:
// a place is a room mapped, and one made for a hallway or a connecting room would map it twice.
// The doors seen from inside the rooms behind are kept for the hallway: passed a moment later, they
// are another door of a room just mapped, not a new room.
//
// One level: the rooms behind are not searched for inner doors of their own.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/room_explorer.h"
#include "exploration/room_visit.h"
#include "exploration/waypoint_follower.h"
#include "laser_features/building_rules.h"

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace exploration {

/// The space behind a door at `door_in_place` (centre, direction into the space), seen from just
/// inside it (`q`, in the same place), is a hallway, not a room (a corner room's second door into
/// another hallway): no deeper than the widest hallway (building rules: hallway_max_width +
/// width_tolerance) straight ahead, and open farther than that along the door's wall on both sides. A
/// room entered by a door in its side wall is as deep as the row it is in (3.5-14 m on office floors),
/// or its side walls lie within hallway_max_width of the door on one side (a room narrower than the
/// widest hallway and deeper than twice it, with the door near the middle of its side wall, is taken
/// for a hallway: the assumption's limit). `why`: the space's depth and its extents along the wall.
bool hallwayBehindDoor(const Perception& q, const laser_features::Pose2D& door_in_place,
                       const laser_features::BuildingRules& rules, std::string* why = nullptr);

/// The room behind an inner door in the host's side wall (`inner`: centre, `into` the host) has a
/// door of its own onto the hallway the host was entered from (`host_door`: centre on the hallway's
/// wall, direction into the host), seen from `q` (host place): an opening of a door's width
/// (BuildingRules::isDoor) centred on the hallway's near wall line -- within half the narrowest
/// hallway of it, since the hallway's far wall lies a hallway's width beyond and the room's own
/// furniture stands inside it -- and beyond the host's side wall by a door's half width and its jamb
/// (BuildingRules::doorFromCorner: the host's own doors lie on the other side). A door in the
/// host's back wall (within 45 deg of the entry's direction) leads away from that hallway: false.
/// `why`: where along the wall the door was seen, for the log.
bool doorOntoHostHallway(const Perception& q, const laser_features::Pose2D& host_door,
                         const RoomVisit::DoorInPlace& inner, const laser_features::BuildingRules& rules,
                         std::string* why = nullptr);

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
  /// path reaches are given up).
  bool nextDoor(RoomVisit& host, const Eigen::Vector2d& robot);
  /// Inner doors given up since the start: no path to the front, or driveToDoor() or peek() Failed.
  int doorsGivenUp() const { return given_up_; }
  /// The inner doors of the host since begin() that nextDoor() gave up for want of a path, as text
  /// for the log (empty if none); taken (cleared) by takeUnreached().
  std::string takeUnreached() { return std::exchange(unreached_, std::string()); }

  enum class Drive { Driving, There, Failed };
  /// Along the path to the door's front (kFront from it, on the host's side), then facing the door;
  /// the path planned again every replan_period of `elapsed` (s since the drive began), clear of
  /// the latest scan's returns (RoomVisit::pathTo). Failed after the room visit's exit_time_limit.
  Drive driveToDoor(RoomVisit& host, const Perception& q, double elapsed, Decision* d);

  /// What lies behind the door being visited, as peek() saw it.
  enum class Behind { Room, ConnectingRoom, Hallway };
  /// From the door's front through the door on its axis to peekDepth() past it (still in the
  /// host's place), kLookScans scans standing there, and back to the front facing the door: There,
  /// with behind() the verdict (a connecting room when doorOntoHostHallway held on two of the
  /// scans; a hallway when hallwayBehindDoor held on the first). Failed after the room visit's
  /// exit_time_limit of `elapsed`.
  Drive peek(const RoomVisit& host, const Perception& q, double elapsed, Decision* d);
  Behind behind() const { return behind_; }
  /// m, how far past the door's line peek() looks from: a robot radius. The robot's back is at the
  /// line: the laser, past a wall up to a radius thick, sees all of the room behind, and the host
  /// stays in view through the door behind it (a cone of 2 atan(door_min_width / 2 / radius), 110 deg
  /// for the narrowest door), so the host's EKF keeps matching the host's walls; deeper in, the room
  /// behind fills the view and its walls, parallel to the host's, can be matched to them.
  double peekDepth() const { return peek_depth_; }

  /// The room behind the door begins: its place was created with the robot at its origin, standing
  /// at the door's front (`robot_odom`).
  void beginInnerRoom(const RoomVisit& host, const laser_features::Pose2D& robot_odom);
  /// Whether an inner room's visit runs (from beginInnerRoom() to endInnerRoom()).
  bool insideInner() const { return inside_; }
  RoomVisit& inner() { return inner_; }
  const RoomVisit& inner() const { return inner_; }
  /// The inner room was left, back at the door's front: its doors seen from inside are kept.
  void endInnerRoom();
  /// Before the place of the room behind is created (the robot at its origin, the host's place still
  /// the EKF's): the host keeps the robot's pose, with the EKF's covariance, as a door of its own
  /// under an id no node names (an AddDoor request at no offset from the robot).
  Request keepOrigin(int host_place);
  /// Back in the host from the room behind (`q`: the robot in the room behind's place): the host's
  /// place relocated at the origin keepOrigin() kept, where the robot's pose in the room behind is its
  /// pose from that door (a Relocate request, with the EKF's covariance of that pose). The way out of the host may be a whole room long,
  /// through a door with a decimetre to spare: the odometry since the EKF's last pose of the host
  /// drifts more than that over the room behind's coverage and the way back (1-2 % of the distance,
  /// and the heading's error swings the host's far side); the EKF of the room behind does not.
  Request relocateHost(int host_place, const Perception& q) const;
  /// Each scan of an inner room's visit (`q`, in its place): whether the robot stands past its door.
  void observeInner(const Perception& q);
  /// The robot stands past the inner door's line (observeInner).
  bool throughDoor() const { return through_; }
  /// What peek() saw behind the door (the space's depth and extents, or where the hallway door of the
  /// room behind lies), for the log.
  const std::string& space() const { return space_; }
  /// The doors seen from inside the inner rooms visited since begin() (odometry frame).
  const std::vector<DoorTrack>& innerRoomDoorsOdom() const { return inner_doors_odom_; }

  static constexpr double kFront = 1.0;  // m, the robot stands this far in front of an inner door (RoomVisit::kDoorPassage)
  static constexpr int kLookScans = 3;   // scans peek() takes standing past the door: two sightings of a door, one spare
  // m: rooms covered within this much travel are compared in the odometry frame. Wheel odometry
  // drifts 1-2 % of the distance (0.3-0.6 m over it); the point compared lies kDoorPassage inside
  // the room behind.
  static constexpr double kRecentTravel = 30.0;

 private:
  /// The robot (`q`, host place) stands within RoomVisit::kArrived of `p` (m), facing `theta` within
  /// as many rad (as RoomVisit::approachDoor stands at a door).
  static bool standsAt(const Perception& q, const Eigen::Vector2d& p, double theta);
  RoomVisitParams params_;
  laser_features::BuildingRules rules_;
  RoomVisit inner_;
  std::vector<RoomVisit::DoorInPlace> todo_;  // the host's inner doors not visited yet (host place)
  RoomVisit::DoorInPlace door_;               // the one being visited
  WaypointFollower path_;                      // to its front, host place
  bool inside_ = false;
  bool through_ = false;   // observeInner: past the inner door's line
  enum class PeekStep { In, Look, Out };
  PeekStep peek_step_ = PeekStep::In;
  int looks_ = 0, door_sightings_ = 0;  // peek(): scans taken past the door, those that saw a hallway door behind
  Behind behind_ = Behind::Room;
  std::string space_;
  std::string unreached_;  // nextDoor(): the doors given up for want of a path (text)
  std::vector<DoorTrack> inner_doors_odom_;
  int given_up_ = 0;
  double planned_at_ = 0.0;  // s, driveToDoor()'s elapsed when its path was planned
  int origins_kept_ = 0;  // keepOrigin() calls: the door ids given
  double peek_depth_ = 0.25;  // m, peekDepth()
  std::vector<std::pair<RoomExtent, double>> recent_rooms_;  // extents (odometry frame), travel when covered
};

}  // namespace exploration
