// The doors along the hallway the robot follows, tracked from laser_features' openings in the
// odometry frame (odometry is good over a hallway's stretch): which openings are doors of this
// hallway (on the wall beside the robot, facing across the travel), their running mean position and
// width and the scans that saw a room behind them, and which door the robot has just passed (then
// HallwayNavigator decides whether to enter). The walls it gates with are remembered for a few metres
// where the scan does not see them (doors break them into short pieces).
//
// ROS-free: Eigen and laser_features' geometry.
#pragma once

#include "exploration/hallway_view.h"
#include "laser_features/building_rules.h"
#include "laser_features/opening_tracks.h"
#include "laser_features/geometry.h"
#include "laser_features/opening_extractor.h"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <vector>

namespace exploration {

/// Parameters of HallwayDoors (config/exploration.yaml's door_* keys; each with its unit and default).
struct HallwayDoorParams {
  double min_confidence = 0.5;   // -, laser_features' opening confidence a door needs (not in a dead end's end wall, nor in the side wall followed)
  double wall_tolerance = 0.35;  // m, a door lies on its side's wall: one farther behind the wall seen is not tracked
  double wall_memory = 3.0;      // m of travel, a side's wall line is kept where the scan no longer sees it
  double same_distance = 1.0;    // m, a door this close to one already decided on is the same door
  laser_features::OpeningTracks tracks;  // side openings, sightings, keep distance, enter_lag (config/opening_tracks.yaml)
};

struct DoorTrack {
  Eigen::Vector2d centre_odom = Eigen::Vector2d::Zero();
  double into_odom = 0.0;   // rad, odometry frame, direction into the room
  double width = 0.0;       // m
  int sightings = 0;
  int located_sightings = 0;  // confident ones (door_min_confidence): they alone place it once there is one
  int room_sightings = 0;   // scans that saw a room behind it (BuildingRules::isDoorTracked)
  bool decided = false;     // entered or passed: never again on this pass
  bool taken = false;       // passed and offered for entering (entered, or refused as known)
  double wall_lateral = -1.0;  // m, its side's wall line from the robot when last seen (-1: no wall known)
  // Its centre known to within its half-width in the odometry frame now: seen within 45 deg of
  // abeam (HallwayDoors::kAbeam), and the odometry's drift in each room visited since measured
  // (HallwayDoors::roomVisited).
  bool located = false;
};

class HallwayDoors {
 public:
  // m, two tracks of one door: sightings from afar (grazing) lie up to about 1 m off the later ones
  // (ADoorTrackedTwiceIsEnteredOnce), and tracks from before a room's visit lie off by the
  // odometry's drift inside it where that was not measured (TheDoorJustLeftIsNotEnteredAgain).
  // Two tracks both located (DoorTrack::located) are one door only where their spans overlap (two
  // doors in one wall cannot): doors 1.2 m apart on one wall, where two share a divider, are two.
  static constexpr double kSameDoorSpan = 1.3;
  // An opening seen within 45 deg of abeam (|along| <= |lateral|) has both jambs in view: its
  // centre is found to within its half-width. At a grazing angle the near jamb hides the far one.
  static constexpr double kAbeam = 1.0;  // |along| / |lateral| at most
  using Walls = std::array<std::optional<double>, 2>;  // wallLateral of the left and the right side

  HallwayDoors(const HallwayDoorParams& params, const laser_features::BuildingRules& rules)
      : params_(params), rules_(rules) {}

  /// One scan: `odom` the robot's pose, `openings` in the robot frame, `dir_robot` the travel
  /// direction in the robot frame, `travel` (m) the total travel. Returns the walls it gated with.
  Walls track(const laser_features::Pose2D& odom, const std::vector<laser_features::Opening>& openings,
              double dir_robot, const HallwayView& v, double travel);
  /// A door passed (tracks.enter_lag behind), not behind its side's wall in `walls`.
  bool passed(const laser_features::Pose2D& odom, double dir_robot, const Walls& walls, DoorTrack* door);
  /// At a hallway's end (its end wall `free_ahead` away): a door tracked beside the robot on a side
  /// closed there (`closed`: left, right) and not passed yet, no farther ahead than the end wall.
  /// The robot goes no farther along this hallway, so the door is passed now; offered as `passed`
  /// offers one. The turn that follows would forget it. `turning_round`: a door within
  /// tracks.enter_lag of abeam lies on the robot's way back and is passed on it as any door (track()
  /// takes a door first seen more than enter_lag behind for passed before); it is left to that.
  bool besideEnd(const laser_features::Pose2D& odom, double dir_robot, const Walls& walls, double free_ahead,
                 const std::array<bool, 2>& closed, bool turning_round, DoorTrack* door);
  /// A tracked door beside the robot (within kSameDoorSpan along) on the side `side` (+1 left, -1 right):
  /// a door by BuildingRules::isDoorTracked, seen twice at least.
  std::optional<DoorTrack> abeam(const laser_features::Pose2D& odom, double dir_robot, double side) const;
  /// At a hallway's end (`v`), a door in the end wall in this scan: ahead of the robot no farther
  /// than the wall (wall_tolerance beyond free_ahead), within half the hallway's width of its mid-line, across the travel direction (its
  /// normal within side_angle of it); the one nearest the mid-line. One sighting, in odometry. Of
  /// min_confidence where it is not on the end wall itself (both walls seen, free_ahead away within
  /// wall_tolerance): there the wall supports it.
  std::optional<DoorTrack> inEndWall(const laser_features::Pose2D& odom,
                                     const std::vector<laser_features::Opening>& openings, double dir_robot,
                                     const HallwayView& v) const;
  /// Back from a room, where the odometry drifted: by `drift` as the EKF measured it in the room's
  /// place (RoomVisit::odometryDrift), the doors tracked before are moved by it and stay located;
  /// unmeasured, they lie off by an unknown drift and none is located any more.
  void roomVisited(const std::optional<laser_features::Pose2D>& drift);
  /// Forgets the doors and the walls: they belong to the hallway being left.
  void clear() {
    tracks_.clear();
    wall_seen_odom_ = {};
  }

 private:
  /// `t` (at `lateral` from the robot, + left) is decided now: offered as a door to enter (true,
  /// copied to `door`) when it is a door by the building rules, on its side's wall in `walls`, and
  /// not taken already on this stretch.
  bool offer(DoorTrack& t, double lateral, const Walls& walls, const Eigen::Vector2d& robot, DoorTrack* door);
 public:
  /// A door opens away from a robot at `robot` (odometry frame): the robot is on its near side.
  static bool opensAwayFrom(const DoorTrack& t, const Eigen::Vector2d& robot);

 private:
  /// The lateral distance (m) of the wall line on `side` (0 left, 1 right): seen in `v`, or seen
  /// within wall_memory of travel on this stretch; none if neither.
  std::optional<double> wallLateral(const laser_features::Pose2D& odom, double dir_robot, const HallwayView& v,
                                    int side, double travel);

  HallwayDoorParams params_;
  laser_features::BuildingRules rules_;
  std::vector<DoorTrack> tracks_;
  std::array<std::optional<Eigen::Vector2d>, 2> wall_seen_odom_;
  std::array<double, 2> wall_seen_travel_{{0.0, 0.0}};
};

}  // namespace exploration
