#include "exploration/hallway_follower.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace exploration {

using laser_features::inverse;
using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::transformPoint;
using laser_features::unitVector;

HallwayFollower::HallwayFollower(const HallwayFollowerParams& params, const HallwayViewParams& view,
                                 const laser_features::BuildingRules& rules, const PlannerParams& robot)
    : params_(params), view_(view), rules_(rules), robot_radius_(robot.robot_radius) {
  // The hallway view's derived sizes: the robot's footprint and the building's narrowest hallway.
  view_.clearance = robot.robot_radius + robot.safety_margin;
  view_.min_mouth = rules.hallway_min_width - rules.width_tolerance;
  view_.widest_hallway = rules.widestHallway();
  view_.wall_max_lateral = rules.hallwayReach();
}

double HallwayFollower::odomHeadingOfBin(int bin, const TopoView& topo) const {
  return normalizeAngle(binHeading(bin) - (topo.heading_valid ? topo.map_from_odom.theta : 0.0));
}

double HallwayFollower::topoBearing(double odom_bearing, const TopoView& topo) const {
  return normalizeAngle(odom_bearing + topo.map_from_odom.theta - direction_.offset);
}

double HallwayFollower::mapHeading(double dir_robot, const Perception& p, const TopoView& topo) {
  return normalizeAngle(dir_robot + p.odom.theta + (topo.heading_valid ? topo.map_from_odom.theta : 0.0));
}

void HallwayFollower::faceRobotsBin(const Perception& p, const TopoView& topo) {
  direction_.bin = binOf(p.odom.theta + topo.map_from_odom.theta);
}

double HallwayFollower::freeAlong(int bin, const Perception& p, const TopoView& topo) const {
  return freeDistance(p.points, normalizeAngle(odomHeadingOfBin(bin, topo) - p.odom.theta), view_.ahead_sector, 15.0);
}

std::vector<int> HallwayFollower::waysAtStart(int bin, const Perception& p, const TopoView& topo) const {
  const double beyond_end = params_.end_distance + 1.0;
  std::vector<int> ways;
  if (freeAlong(bin + bins_.bins / 2, p, topo) > beyond_end) ways.push_back(bins_.wrap(bin + bins_.bins / 2));
  const double dir = normalizeAngle(odomHeadingOfBin(bin, topo) - p.odom.theta);  // robot frame
  for (int side : {1, -1}) {
    const int side_bin = bins_.wrap(bin + side * bins_.bins / 4);
    if (freeAlong(side_bin, p, topo) > beyond_end &&
        mouthBeside(p.points, Eigen::Vector2d::Zero(), dir, side, view_.clearance, view_.min_mouth,
                    view_.side_open_distance) &&
        !doorInMouth(p.openings, Eigen::Vector2d::Zero(), dir, side, view_.clearance, view_.min_mouth,
                     view_.wall_parallel_tolerance))
      ways.push_back(side_bin);
  }
  return ways;
}

std::optional<int> HallwayFollower::startHallwayAxis(const Perception& p, const TopoView& topo) const {
  // The hallway the robot starts in runs between the nearest walls beside it: of the two axes, the
  // one whose parallel wall lines enclose the robot most narrowly, within a hallway's width
  // (BuildingRules::hallway_max_width, the robot anywhere across it). Beside: a wall reaches within
  // half the widest door of the robot along the axis (a door's wall does, on both sides of the door
  // the robot may stand in front of). A view through a door ahead is no hallway however deep: the
  // room's side walls begin beyond the hallway's wall, its far wall and the hallway's wall behind
  // the robot are farther apart than a hallway is wide.
  const int quarter = bins_.bins / 4;
  std::optional<int> best;
  double best_width = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 2; ++axis) {
    const double dir = normalizeAngle(odomHeadingOfBin(direction_.bin + axis * quarter, topo) - p.odom.theta);  // robot frame
    const Eigen::Vector2d u = unitVector(dir), n = unitVector(dir + 0.5 * kPi);
    double left = std::numeric_limits<double>::infinity(), right = left;
    for (const laser_features::LineSegment& l : p.lines) {
      const Eigen::Vector2d d = l.end - l.start;
      if (d.norm() < view_.wall_min_length) continue;
      if (std::abs(laser_features::cross2(u, d.normalized())) > std::sin(view_.wall_parallel_tolerance)) continue;
      const double beside = 0.5 * rules_.door_max_width + rules_.width_tolerance;
      const double a0 = u.dot(l.start), a1 = u.dot(l.end);
      if (std::min(a0, a1) > beside || std::max(a0, a1) < -beside) continue;
      const double offset = n.dot(0.5 * (l.start + l.end));
      (offset > 0.0 ? left : right) = std::min(offset > 0.0 ? left : right, std::abs(offset));
    }
    if (left + right <= view_.widest_hallway && left + right < best_width) {
      best_width = left + right;
      best = axis;
    }
  }
  return best;
}

int HallwayFollower::startBin(const Perception& p, const TopoView& topo) const {
  // With no walls on both sides of the robot: a hallway is longer than it is wide, so when the way
  // ahead is shorter than a way to the side, the robot stands across the hallway.
  const auto free = [&](int bin) { return freeAlong(bin, p, topo); };
  const int own = direction_.bin;
  const int quarter = bins_.bins / 4;
  if (const std::optional<int> axis = startHallwayAxis(p, topo)) {
    if (*axis == 0) return own;
    return free(own + quarter) >= free(own - quarter) ? bins_.wrap(own + quarter) : bins_.wrap(own - quarter);
  }
  if (free(own) >= std::max(free(own + quarter), free(own - quarter))) return own;
  int best = own;
  for (int k = 1; k < bins_.bins; ++k) {
    if (free(own + k) > free(best)) best = bins_.wrap(own + k);
  }
  return best;
}

double HallwayFollower::track(const Perception& p, const TopoView& topo, HallwayView* v) {
  double dir_robot = normalizeAngle(odomHeading(direction_, topo) - p.odom.theta);
  *v = viewHallway(p.points, p.lines, dir_robot, view_);
  closeDoorMouths(p, dir_robot, v);
  const double half_bin = kPi / bins_.bins;
  if (!v->wall_direction_valid) {
    // No wall along the way followed: the walls of the hallway around the robot, up to half a bin
    // and the wall tolerance from it (every way a wing can run: 30-60 deg to the axes).
    laser_features::HallwayWallsParams walls;
    walls.min_length = view_.wall_min_length;
    walls.parallel_tolerance = view_.wall_parallel_tolerance;
    walls.max_width = view_.widest_hallway;
    if (const std::optional<double> around = laser_features::hallwayWallsDirection(p.lines, dir_robot, half_bin + walls.parallel_tolerance, walls)) {
      *v = viewHallway(p.points, p.lines, *around, view_);
      closeDoorMouths(p, *around, v);
    }
  }
  if (!v->wall_direction_valid) return dir_robot;
  dir_robot = v->wall_direction;
  // Walls along the axes leave no offset (the direction is refined from them tick by tick); a wing's
  // keep theirs; past half a bin the nearer bin is the hallway's.
  const laser_features::BinnedDirection d = laser_features::followWalls(
      bins_, {direction_.bin, direction_.offset}, mapHeading(dir_robot, p, topo), view_.wall_parallel_tolerance);
  direction_ = HallwayDirection{d.bin, d.offset};
  return dir_robot;
}

void HallwayFollower::closeDoorMouths(const Perception& p, double direction, HallwayView* v) const {
  // A side opens, and the hallway goes on ahead, at a mouth as wide as the narrowest hallway's; a
  // double door is as wide. Where laser_features sees a door there (a room behind it), the door's
  // wall crosses the hallway ahead, and a side is closed: the door is entered as a room (passed
  // beside the robot, or in a dead end's wall), not followed or turned into as a hallway. The door lies in the hallway's wall: its normal
  // within the walls' tolerance of the side.
  if (!v->wall_across) {
    if (const std::optional<double> across = doorAcross(p.openings, *v, direction, view_, rules_))
      endWallAt(p.points, p.lines, direction, view_, *across, v);
  }
  const auto door = [&](const Eigen::Vector2d& origin, int side) {
    return doorInMouth(p.openings, origin, direction, side, view_.clearance, view_.min_mouth, view_.wall_parallel_tolerance);
  };
  if (v->open_left && door(Eigen::Vector2d::Zero(), 1)) v->open_left = false;
  if (v->open_right && door(Eigen::Vector2d::Zero(), -1)) v->open_right = false;
  if (v->end_open_left && door(v->end_mouth_left, 1)) v->end_open_left = false;
  if (v->end_open_right && door(v->end_mouth_right, -1)) v->end_open_right = false;
}

bool HallwayFollower::intoOpenArea(const Perception& p, double dir_robot, const HallwayView& v) {
  if (v.left_wall || v.right_wall) {
    open_area_armed_ = true;
    return false;
  }
  if (!open_area_armed_) return false;
  const double widest = view_.widest_hallway;
  const Eigen::Vector2d here = Eigen::Vector2d::Zero();
  if (!openAreaBeside(p.points, here, dir_robot, 1, view_.clearance, widest, view_.side_open_distance) ||
      !openAreaBeside(p.points, here, dir_robot, -1, view_.clearance, widest, view_.side_open_distance))
    return false;
  open_area_armed_ = false;
  return true;
}

bool HallwayFollower::stalled(const Perception& p) {
  const Eigen::Vector2d here(p.odom.x, p.odom.y);
  const double diameter = 2.0 * robot_radius_;
  if (stall_since_ < 0.0 || (here - stall_anchor_).norm() > diameter) {
    stall_anchor_ = here;
    stall_since_ = p.stamp;
    return false;
  }
  if (p.stamp - stall_since_ < params_.stall_time) return false;
  stall_anchor_ = here;
  stall_since_ = p.stamp;
  return true;
}

std::optional<double> HallwayFollower::laneAround(const Perception& p, double dir_robot, const HallwayView& v,
                                                  bool blocked) {
  // An obstacle ahead is no hallway end where the hallway's walls go on past it and a lane beside
  // it is free as far (a pillar, a chair, a person): the robot keeps to that lane. The lane taken
  // is kept while it stays free past the obstacle: another lane as free (the other side of a pillar
  // on the mid-line) would swing the robot from side to side in front of it.
  const Eigen::Vector2d n = unitVector(dir_robot + 0.5 * kPi);
  if (lane_valid_ && transformPoint(inverse(p.odom), lane_point_odom_).dot(unitVector(dir_robot)) < -params_.end_distance)
    lane_valid_ = false;  // the obstacle is passed
  if (!atEnd(v) || blocked) return std::nullopt;
  const double past = v.free_ahead + params_.end_distance;
  if (v.wall_across || !v.wallsReach(past)) return std::nullopt;
  const double clearance = view_.clearance;
  std::optional<double> lane;
  if (lane_valid_) {
    const double kept = transformPoint(inverse(p.odom), lane_point_odom_).dot(n);
    if (corridorFree(p.points, kept * n, dir_robot, clearance, 15.0) > past) lane = kept;
  }
  if (!lane) {
    const Lane l = freestLane(p.points, dir_robot, v, clearance);
    if (!(l.free > past)) return std::nullopt;
    lane = l.lateral;
    lane_point_odom_ = transformPoint(p.odom, *lane * n);
    lane_valid_ = true;
  }
  return lane;
}

Eigen::Vector2d HallwayFollower::goal(const Perception& p, double dir_robot, const HallwayView& v,
                                      const std::optional<double>& lane) {
  const double ahead = lane ? std::max(params_.lookahead, v.free_ahead + params_.end_distance) : params_.lookahead;
  const Eigen::Vector2d g_robot = ahead * unitVector(dir_robot) + lane.value_or(v.centre_offset) * unitVector(dir_robot + 0.5 * kPi);
  const Eigen::Vector2d g = transformPoint(p.odom, g_robot);
  if (!have_goal_ || (g - last_goal_).norm() > params_.goal_refresh_distance) {
    last_goal_ = g;
    have_goal_ = true;
  }
  return last_goal_;
}

std::vector<ObliqueWay> HallwayFollower::obliqueWaysAtEnd(const Perception& p, const TopoView& topo,
                                                          const HallwayView& v) const {
  // The robot's corridor free for a hallway's width is a way out; its walls within a hallway's
  // width make it a hallway.
  const double dir_robot = normalizeAngle(odomHeading(direction_, topo) - p.odom.theta);
  return obliqueHallways(p.points, p.lines, v, dir_robot, view_, rules_.hallway_max_width, view_.widest_hallway);
}

int HallwayFollower::wayBin(double way_robot, const Perception& p, const TopoView& topo) const {
  return binOf(mapHeading(way_robot, p, topo));
}

int HallwayFollower::takeWay(double way_robot, const Perception& p, const TopoView& topo) {
  // A wing: its heading is the hallway's from here on, as bin and offset.
  const double map_heading = mapHeading(way_robot, p, topo);
  const int way_bin = wayBin(way_robot, p, topo);
  direction_.offset = normalizeAngle(map_heading - binHeading(way_bin));
  return way_bin;
}

}  // namespace exploration
