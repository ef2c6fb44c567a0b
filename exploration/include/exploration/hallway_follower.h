// Following a hallway (Tomatis, Nourbakhsh & Siegwart 2001, section 3.1): the robot keeps to the
// hallway's mid-line along one of the building's headings (the heading estimator's bins), or along
// the walls of a wing that runs at an angle to them.
//
// HallwayFollower keeps the direction followed (a bin, and the hallway's offset from the bin's
// heading), the goal on the mid-line, and the lane past an obstacle ahead; it tells a stall, a way
// out at an angle at a hallway's end, and the bin to set off along at the start. HallwayNavigator
// decides the turns (at ends, for the route) and the doors, and sets the bin turned to.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/grid_planner.h"
#include "exploration/hallway_view.h"
#include "exploration/oblique_hallways.h"
#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <optional>

namespace exploration {

/// Parameters of HallwayFollower (config/exploration.yaml's lookahead, end_distance,
/// goal_refresh_distance and follow_stall_time; each with its unit and default).
struct HallwayFollowerParams {
  double lookahead = 1.5;               // m, the hallway goal lies this far ahead on the mid-line
  double end_distance = 1.3;            // m, the hallway ends when the free distance ahead is below this
  double goal_refresh_distance = 0.25;  // m, the hallway goal is re-sent when it moved this much
  double stall_time = 20.0;  // s, following a hallway without getting a robot's diameter away from where the
                             // robot was this long ago is a hallway end (the hallway goal moves with the
                             // robot, so the controller's own stuck test never fires)
};

/// The direction a hallway is followed in: a heading bin of the building's axes (map frame), and
/// the hallway's offset from the bin's heading (a wing at an angle to the axes; 0 along them).
struct HallwayDirection {
  int bin = 0;
  double offset = 0.0;  // rad
};

class HallwayFollower {
 public:
  /// `view`'s derived sizes are set from `robot` (the robot's footprint: clearance) and `rules`
  /// (the narrowest hallway: min_mouth).
  HallwayFollower(const HallwayFollowerParams& params, const HallwayViewParams& view,
                  const laser_features::BuildingRules& rules, const PlannerParams& robot);
  /// The hallway view's parameters with their derived sizes.
  const HallwayViewParams& viewParams() const { return view_; }
  /// m, how far ahead the goal lies on the mid-line.
  double lookahead() const { return params_.lookahead; }
  /// m, building/hallway_max_width: how far a way at an angle is found free (obliqueWaysAtEnd).
  double hallwayMaxWidth() const { return rules_.hallway_max_width; }
  const laser_features::BuildingRules& rules() const { return rules_; }

  /// The building's axes (pomdp_topo's building_axes): the discrete headings of the hallways.
  void setHeadingBins(const laser_features::HeadingBins& bins) { bins_ = bins; }
  const laser_features::HeadingBins& headingBins() const { return bins_; }
  double binHeading(int bin) const { return bins_.heading(bin); }  // map frame
  int binOf(double map_heading) const { return bins_.bin(map_heading); }
  double odomHeadingOfBin(int bin, const TopoView& topo) const;

  const HallwayDirection& direction() const { return direction_; }
  int bin() const { return direction_.bin; }
  void setDirection(const HallwayDirection& direction) { direction_ = direction; }
  /// Turned onto `bin`: the hallway's offset is kept.
  void setBin(int bin) { direction_.bin = bin; }
  /// Along the building's axes from here on: a wing's offset ends with the wing's walls (in an open
  /// area, say; a wall in view sets it again).
  void dropOffset() { direction_.offset = 0.0; }
  /// The heading (odometry frame) of `direction`'s hallway.
  double odomHeading(const HallwayDirection& direction, const TopoView& topo) const {
    return odomHeadingOfBin(direction.bin, topo) + direction.offset;
  }
  /// The heading (odometry frame) of `bin` at the offset of the hallway followed (a wing's crossings
  /// and U-turns are square to it).
  double odomHeadingAtOffset(int bin, const TopoView& topo) const {
    return odomHeading(HallwayDirection{bin, direction_.offset}, topo);
  }
  /// A bearing in the odometry frame (a door's, into its room) as the topological map has it: in the
  /// map frame, and square to the axes where a wing's hallway runs at its offset to them
  /// (a node's side openings are bin heading +-90 deg in pomdp_topo's map).
  double topoBearing(double odom_bearing, const TopoView& topo) const;

  // The start: the robot may face any way.
  /// The direction is the bin the robot faces.
  void faceRobotsBin(const Perception& p, const TopoView& topo);
  /// The bin to set off along: the hallway the robot stands in (along the robot's own bin if that
  /// is one of the two), else the bin whose way is free the farthest.
  int startBin(const Perception& p, const TopoView& topo) const;
  /// The ways other than `bin` the robot can leave its start by (bins): back, where that way is
  /// free a metre past a hallway's end (the robot stands mid-hallway), and to a side where a
  /// hallway's mouth is beside the robot (a crossing, an open area's edge; a door never is one).
  std::vector<int> waysAtStart(int bin, const Perception& p, const TopoView& topo) const;

  // Following, each tick.
  /// The hallway's direction (robot frame) from its walls: along the direction followed, else the
  /// walls of a hallway at an angle to it (a wing, a bend); the offset from the bin is kept
  /// (re-binned past half a bin). The view along the result in `v`.
  double track(const Perception& p, const TopoView& topo, HallwayView* v);
  /// Following without progress for stall_time (see there).
  bool stalled(const Perception& p);
  /// The lane (lateral offset, m, robot frame) past an obstacle ahead in the hallway, if there is one.
  std::optional<double> laneAround(const Perception& p, double dir_robot, const HallwayView& v, bool blocked);
  /// The robot has come into an open area (a hall, a lobby, the hallways around one) from a
  /// hallway: no wall is in `v` on either side, one was since the last time told, and both sides
  /// are open wider than the widest hallway (a crossing's mouths are no wider). In the area the
  /// robot keeps to its walls, one at a time. (Set off in one, the robot takes the start's way:
  /// HallwayFollower::startBin.)
  bool intoOpenArea(const Perception& p, double dir_robot, const HallwayView& v);
  /// `v` (along `direction`, robot frame) where laser_features sees a door (a double door): ended
  /// at a door across ahead (doorAcross), its sides that open at a door (doorInMouth) closed.
  void closeDoorMouths(const Perception& p, double direction, HallwayView* v) const;
  /// The free distance ahead in `v` is below end_distance.
  bool atEnd(const HallwayView& v) const { return v.free_ahead < params_.end_distance; }
  /// The goal (odometry frame): lookahead metres ahead on the mid-line (past an obstacle, on `lane`
  /// beside it); the last one while it moved less than goal_refresh_distance.
  Eigen::Vector2d goal(const Perception& p, double dir_robot, const HallwayView& v, const std::optional<double>& lane);
  /// The next goal is a new one (a new stretch).
  void forgetGoal() { have_goal_ = false; }
  /// A new state: the stall window and the lane past an obstacle start again.
  void restart() {
    stall_since_ = -1.0;
    lane_valid_ = false;
  }

  // A hallway's end.
  /// At a hallway's end: the hallways leaving it at an angle (wings), their directions in the robot
  /// frame, left first.
  std::vector<ObliqueWay> obliqueWaysAtEnd(const Perception& p, const TopoView& topo, const HallwayView& v) const;
  /// The bin of the way `way_robot` (robot frame): the bin pomdp_topo's map gives the opening, and
  /// the branch once the robot has turned into it (its turns are whole bins).
  int wayBin(double way_robot, const Perception& p, const TopoView& topo) const;
  /// The way `way_robot` (robot frame) is the hallway's from here on: its offset is kept, its bin
  /// returned (to turn to).
  int takeWay(double way_robot, const Perception& p, const TopoView& topo);
  /// m, the free distance along `bin` (the ahead sector).
  double freeAlong(int bin, const Perception& p, const TopoView& topo) const;

 private:
  /// 0: the hallway at the start runs along the robot's own bin, 1: across it; none: no walls seen
  /// on both sides of the robot.
  std::optional<int> startHallwayAxis(const Perception& p, const TopoView& topo) const;
  /// The map heading of `dir_robot` (robot frame).
  static double mapHeading(double dir_robot, const Perception& p, const TopoView& topo);

  HallwayFollowerParams params_;
  HallwayViewParams view_;
  laser_features::BuildingRules rules_;
  double robot_radius_;
  laser_features::HeadingBins bins_;  // pomdp_topo's, from building_axes
  HallwayDirection direction_;
  bool have_goal_ = false;
  Eigen::Vector2d last_goal_ = Eigen::Vector2d::Zero();
  bool lane_valid_ = false;      // a lane past an obstacle is being kept ...
  Eigen::Vector2d lane_point_odom_ = Eigen::Vector2d::Zero();  // ... through this point (odometry frame)
  Eigen::Vector2d stall_anchor_ = Eigen::Vector2d::Zero();  // odometry frame: where the stall window began
  double stall_since_ = -1.0;    // s, when (-1: not following)
  bool open_area_armed_ = false;  // a wall was in view since the last open area was told
};

}  // namespace exploration
