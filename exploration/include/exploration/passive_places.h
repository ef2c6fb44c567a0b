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
//     Also once the robot is max_place_extent from where it entered (rooms are smaller: the way out
//     was not seen).
//   - A door crossing (DoorCrossings: the recorded path went through a door laser_features saw) is
//     the boundary itself: in the hallway it enters the room behind the door at once, unless the
//     scan says HALLWAY; in a place it leaves it, and enters the space behind unless that is a
//     hallway. The door is where the path crossed it. Without a door node from the belief, a
//     crossing near the door of a known place re-enters that place: both doors in `map` (odometry
//     corrected by ekf_local_map's map -> odom: the EKF's in places, held between them), within
//     reentry_distance plus reentry_per_m of the travel outside places between the two crossings
//     (the only travel no EKF corrects), heading within 45 deg. Otherwise the new place stores the
//     crossed door under its own id (path_door_id_base + n: no node).
// The door's pose is the crossed door's, or else the robot's odometric pose where the room streak
// began (about the doorway, heading into the room): stored in the place on creation, and the
// reference for relocation later.
// ROS-free: the node (replay_places_node) turns messages into Observations and Actions into calls.
#pragma once

#include <map>
#include <optional>
#include <vector>
#include <string>

#include "exploration/coordinator_io.h"
#include "exploration/door_crossings.h"
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
  double relocation_distance = 2.0;     // m, a re-entry not relocated after this much travel in the place is refused: a new place
  double max_place_extent = 12.0;       // m, the robot this far (odometry) from where it entered a place has left it
  bool enter_by_type = true;            // -, the ROOM streak enters a room too (false: only a door crossing does)
  double reentry_distance = 1.0;        // m, a crossed door this close to a known place's door (in map) is that door ...
  double reentry_per_m = 0.03;          // m/m, ... plus this per metre travelled outside places in between (odometry's drift)
  int path_door_id_base = kNodelessDoorIdBase;  // -, ids of crossed doors that no door node names (above any node id)
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
  visit("relocation_distance", &p->relocation_distance);
  visit("max_place_extent", &p->max_place_extent);
  visit("enter_by_type", &p->enter_by_type);
  visit("reentry_distance", &p->reentry_distance);
  visit("reentry_per_m", &p->reentry_per_m);
  visit("path_door_id_base", &p->path_door_id_base);
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
  std::optional<DoorCrossing> crossing;  // the step to this scan went through this door
  Pose2D map_odom;  // ekf_local_map's map -> odom at this scan (identity until it says otherwise)
};

struct PlaceAction {
  enum Kind { None, Enter, Leave } kind = None;
  int door_node = -1;         // Enter: the door node the robot came through, -1 if none
  int door_id = -1;           // Enter: the door's id in the place (the door node, or a crossed door's own id), -1 if none
  bool leave_first = false;   // Enter: close the current place first (a door crossed from one place into another)
  int known_place = -1;       // Enter: the place behind that door when known (re-enter it), else -1
  Pose2D door_odom;           // Enter: the door's pose in the odometry frame
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
  void entered(int place_id, int door_id);  // place_id < 0: entering failed, still in the hallway
  void left();
  /// The place just re-entered was not recognized (ekf_local_map's relocation failed): a new place
  /// behind the same door instead, entered at `odom` (the robot's pose now). Returns the Enter action
  /// (leave_first: the wrong place is closed first); None if the robot did not just re-enter a place.
  PlaceAction reentryRefused(const Pose2D& odom);

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
  PlaceAction decide(const PlaceObservation& o);
  PlaceAction enterAction(const PlaceObservation& o) const;
  PlaceAction crossingAction(const PlaceObservation& o);
  struct PathDoor {
    int id = -1, place = -1;
    Pose2D door_map;              // where it was last crossed, in map
    double outside_travel = 0.0;  // m, outside_travel_ then
  };
  const PathDoor* knownPathDoor(const Pose2D& door_map) const;

  Params params_;
  bool have_odom_ = false;
  Pose2D last_odom_;
  double travel_ = 0.0;  // m, odometric path length so far
  double outside_travel_ = 0.0;  // m, the part of it outside places (no EKF corrected it)
  Streak room_, hallway_;
  int last_door_ = -1;   // door node last passed, and the travel then
  double last_door_travel_ = 0.0;
  int place_door_ = -1;    // the door the current place was entered by
  int ignored_door_ = -1;  // the door just left by: not a way in until the belief has moved off it
  int place_ = -1;
  Pose2D place_entry_odom_;  // where the current place was entered (the scan of the Enter)
  int entries_ = 0;
  std::map<int, int> door_places_;
  std::vector<PathDoor> path_doors_;  // crossed doors stored in places (no door node)
  std::optional<PathDoor> pending_path_door_;  // the crossing being entered, until entered()
  std::optional<PlaceAction> last_reentry_;    // the last Enter that named a known place, until the next one
  Pose2D reentry_door_map_;                    // its crossed door in map
};

}  // namespace exploration
