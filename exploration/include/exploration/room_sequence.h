// A room's visit as the coordinator's METRIC states run it (Tomatis, Nourbakhsh & Siegwart 2001,
// section 3.1): in through the door the robot stopped at, the room covered (RoomVisit), the rooms
// behind its inner doors visited from it one after the other (SuiteVisit: to the door's front, a look
// through it, a place of their own, covered, back into the host by that door), and out by the door
// the host was entered by. A mission's visit only goes in (to its goal, driven by MissionRunner) or
// out.
//
// The coordinator starts a visit (beginNewRoom, beginKnownRoom, beginExit), calls step() on every
// tick while it runs and acts on what the tick ends in (a mission's goal to drive to, the hallway
// reached, the room not left). The places are the coordinator's: step() moves the active place
// between the host and the rooms behind it and asks for new ones with the tick's requests.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/room_explorer.h"
#include "exploration/room_visit.h"
#include "exploration/suite_visit.h"
#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"

#include <cstddef>
#include <string>

namespace exploration {

class RoomSequence {
 public:
  /// The visit's steps: through the door, covering the room, to an inner door's front, the look
  /// through it, a place for the room behind, to the door out, through it.
  enum class Step { ApproachDoor, Cover, ToInnerDoor, PeekInner, InnerPlace, ExitPath, ExitDoor };
  /// What a tick of the visit ends in.
  enum class Outcome {
    Inside,      // the visit goes on
    AtDoor,      // through the door while a mission runs: its drive to the goal begins
    Out,         // back on the hallway where the robot left it, with the heading it had
    OutInexact,  // back on the hallway, that spot not reached exactly
    Stuck,       // still inside after every exit attempt (RoomVisit::kExitAttempts)
  };
  /// The place bookkeeping a tick reads and changes: the active place (the host's, or a room's
  /// behind it) and whether the last place asked for was created.
  struct Places {
    int place_id = -1;
    bool place_ok = false;
  };
  struct Stats {
    int rooms_left_early = 0;  // rooms whose exploration hit the time limit
    int inner_rooms = 0;       // rooms entered from another room, places made for them
    int inner_doors_left = 0;  // inner doors looked through and left: a hallway or a connecting room behind
    double room_free_area = 0.0;  // m^2, sum over the rooms' grids
    size_t peak_room_bytes = 0;
  };

  RoomSequence(const RoomVisitParams& params, const RoomExplorerParams& room, const laser_features::BuildingRules& rules,
               const HallwayDoorParams& doors);

  /// A new room behind the hallway door `door`: the robot stands at the place's origin on the
  /// hallway (`robot_odom`), the hallway's heading `hallway_heading_odom`.
  void beginNewRoom(const laser_features::Pose2D& robot_odom, const DoorTrack& door, double hallway_heading_odom,
                    int place_id, double now);
  /// A mission's room, relocated at its door (RoomVisit::beginKnownRoom).
  void beginKnownRoom(const Perception& p, const laser_features::Pose2D& hallway_pose_odom,
                      double hallway_heading_odom, const GraphOpening& opening, double door_width, int place_id,
                      double now);
  /// Out of the host room by its door (a mission leaving the room it stands in).
  void beginExit(const std::string& text, double now);

  /// One tick of the visit. `mission`: a mission runs (its visit ends at the door, AtDoor).
  Outcome step(const Perception& p, double now, const MotionFeedback& motion, bool mission, double travel,
               Places* places, Decision* d);
  /// The robot's pose in the active place's frame, the visit's sightings of it taken (every tick
  /// a room's state runs: step() does it, and a mission's drive to its goal); `approaching`: the
  /// robot is on its way in through the door (RoomVisit::observe).
  Perception observe(const Perception& p, bool approaching, Decision* d);

  Step current() const { return step_; }
  /// The robot stands in the host room's doorway or beyond it: on its way in or out.
  bool atEntryDoor() const { return step_ == Step::ApproachDoor || step_ == Step::ExitPath || step_ == Step::ExitDoor; }
  const std::string& text() const { return text_; }
  /// Why the room could not be left (Outcome::Stuck).
  const std::string& why() const { return why_; }
  const Stats& stats() const { return stats_; }

  /// The room entered from the hallway.
  RoomVisit& host() { return host_; }
  const RoomVisit& host() const { return host_; }
  /// The room being visited: the room behind an inner door while one is, else the host.
  RoomVisit& visit() { return suite_.insideInner() ? suite_.inner() : host_; }
  const RoomVisit& visit() const { return suite_.insideInner() ? suite_.inner() : host_; }
  const SuiteVisit& suite() const { return suite_; }
  /// The place the robot stands in: `active`, but the host's until the robot has passed the door of
  /// a room behind it (on its way in and out).
  int placeOfRobot(int active) const { return suite_.insideInner() && !suite_.throughDoor() ? host_place_id_ : active; }

 private:
  void setStep(Step s, double now, const std::string& text);
  Outcome approachDoor(const Perception& q, bool mission, Decision* d);
  Outcome coverRoom(const Perception& q, double travel, const Places& places, Decision* d);
  Outcome leaveRoom(const Perception& q, const MotionFeedback& motion, Places* places, Decision* d);
  // The rooms behind the host's inner doors: to the next door's front (false: none is left), a
  // look through it, a place for the room behind, and back in the host from it.
  bool toNextInnerRoom(const Perception& q, const Places& places);
  void toInnerDoor(const Perception& q, const Places& places, Decision* d);
  void peekInner(const Perception& q, Places* places, Decision* d);
  void createInnerPlace(const Perception& p, Places* places, Decision* d);
  void backInHost(const Perception& q, Places* places, Decision* d);
  /// The host room's way out begins.
  void exitHost();

  bool inner_rooms_;  // RoomVisitParams::inner_rooms: the rooms behind the host are visited
  RoomVisit host_;
  SuiteVisit suite_;
  Step step_ = Step::ApproachDoor;
  double step_since_ = 0.0;  // s, stamp when the step began
  double now_ = 0.0;
  std::string text_, why_;
  int host_place_id_ = -1;  // while suite_ visits the rooms behind: the host room's place
  laser_features::Pose2D last_odom_;
  Stats stats_;
};

}  // namespace exploration
