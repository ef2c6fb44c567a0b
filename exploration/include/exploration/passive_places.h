// PassivePlaces: when a robot that nobody steers (a replayed bag) is in a room, for the hybrid map.
//
// Nothing moves the robot during a replay, so no coordinator decides when a place (local metric map)
// starts. This core watches each scan's place classification (laser_features' HALLWAY / ROOM with
// its confidence) and the topological belief (the door node last passed) and decides:
//   - Enter: the scans say ROOM for enter_scans scans in a row over at least enter_distance of travel
//     (hysteresis: unsure scans neither count nor break the streak; a confident HALLWAY breaks it).
//     If a door node was passed within door_memory of travel before the streak began and that door
//     already leads to a place, the place is re-entered (relocation at its door); otherwise a new
//     place is created, with the door (if any) stored in it and linked to the door node.
//   - Leave: the scans say HALLWAY for leave_scans scans over leave_distance: the place is closed.
// The door's pose is the robot's odometric pose where the room streak began (about the doorway,
// heading into the room): stored in the place on creation, and the reference for relocation later.
// ROS-free: the node (replay_places_node) turns messages into Observations and Actions into calls.
#pragma once

#include <map>
#include <string>

#include "laser_features/geometry.h"

namespace exploration {

using laser_features::Pose2D;

struct PassivePlacesParams {
  double room_confidence = 0.6;         // -, a ROOM scan counts towards entering at this confidence or more
  double hallway_confidence = 0.6;      // -, a HALLWAY scan counts towards leaving at this confidence or more
  int enter_scans = 3;                  // scans, ROOM scans in a row to enter a room
  double enter_distance = 1.5;          // m, travel over the ROOM streak needed as well (not a turn at a corner)
  int leave_scans = 3;                  // scans, HALLWAY scans in a row to leave the room
  double leave_distance = 1.0;          // m, travel over the HALLWAY streak needed as well
  double door_memory = 3.0;             // m, a door node passed within this travel before the streak is the room's door
  double relocation_sigma_xy = 0.3;     // m, std. dev. of the robot's position relative to the door on re-entry
  double relocation_sigma_theta = 0.2;  // rad, std. dev. of its heading relative to the door
};

/// Visits every parameter with its name in config/replay_places.yaml (node and test share it).
template <typename Visitor>
void visitPassivePlacesParams(PassivePlacesParams* p, Visitor&& visit) {
  visit("room_confidence", &p->room_confidence);
  visit("hallway_confidence", &p->hallway_confidence);
  visit("enter_scans", &p->enter_scans);
  visit("enter_distance", &p->enter_distance);
  visit("leave_scans", &p->leave_scans);
  visit("leave_distance", &p->leave_distance);
  visit("door_memory", &p->door_memory);
  visit("relocation_sigma_xy", &p->relocation_sigma_xy);
  visit("relocation_sigma_theta", &p->relocation_sigma_theta);
}

enum class ScanPlace { Unknown, Hallway, Room };

/// What one scan tells: the robot's odometry at its stamp, its place type, and the door node the
/// confident topological belief puts the robot at (-1: none, or not a door).
struct PlaceObservation {
  Pose2D odom;
  ScanPlace type = ScanPlace::Unknown;
  double confidence = 0.0;
  int door_node = -1;
  double heading_map = 0.0;  // rad, the robot's heading in `map` (the topological heading filter)
};

struct PlaceAction {
  enum Kind { None, Enter, Leave } kind = None;
  int door_node = -1;         // Enter: the door node the robot came through, -1 if none
  int known_place = -1;       // Enter: the place behind that door when known (re-enter it), else -1
  Pose2D door_in_robot;       // Enter: the door's pose in the robot frame now (= in a place created now)
  Pose2D robot_from_door;     // Enter: the robot's pose in the door's frame (for relocation)
  double door_bearing_map = 0.0;  // Enter: rad, direction through the door in `map`
};

class PassivePlaces {
 public:
  using Params = PassivePlacesParams;

  explicit PassivePlaces(const Params& params = Params()) : params_(params) {}
  static bool validate(const Params& p, std::string* why);

  /// One scan. Returns Enter or Leave when the robot's place changes; the caller then reports
  /// entered() / left() (a failed service leaves the state as it was, and the streak restarts).
  PlaceAction update(const PlaceObservation& o);
  void entered(int place_id, int door_node);  // place_id < 0: entering failed, still in the hallway
  void left();

  /// A door node leads to a place (from this run or from the topological map's links).
  void linkDoor(int door_node, int place_id) { door_places_[door_node] = place_id; }
  int placeOfDoor(int door_node) const;

  bool inPlace() const { return place_ >= 0; }
  int place() const { return place_; }
  int placesEntered() const { return entries_; }
  double travel() const { return travel_; }

 private:
  struct Streak {
    int scans = 0;
    double start_travel = 0.0;
    Pose2D start_odom;
    double start_heading_map = 0.0;
  };
  void count(Streak* s, const PlaceObservation& o);
  bool complete(const Streak& s, int scans, double distance) const {
    return s.scans >= scans && travel_ - s.start_travel >= distance;
  }
  PlaceAction enterAction(const PlaceObservation& o) const;

  Params params_;
  bool have_odom_ = false;
  Pose2D last_odom_;
  double travel_ = 0.0;  // m, odometric path length so far
  Streak room_, hallway_;
  int last_door_ = -1;   // door node last passed, and the travel then
  double last_door_travel_ = 0.0;
  int place_door_ = -1;    // the door the current place was entered by
  int ignored_door_ = -1;  // the door just left by: not a way in until the belief has moved off it
  int place_ = -1;
  int entries_ = 0;
  std::map<int, int> door_places_;
};

}  // namespace exploration
