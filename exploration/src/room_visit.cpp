#include "exploration/room_visit.h"

#include "exploration/motion_controller.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace exploration {

using laser_features::compose;
using laser_features::inverse;
using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::transformPoint;
using laser_features::unitVector;

RoomVisit::RoomVisit(const RoomVisitParams& params, const RoomExplorerParams& room,
                     const laser_features::BuildingRules& rules, const HallwayDoorParams& doors)
    : params_(params), rules_(rules), doors_(doors), explorer_(room) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("room visit: " + why);
}

bool RoomVisit::validate(const RoomVisitParams& p, std::string* error) {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (!(p.replan_period >= 0.0)) return fail("room_visit/replan_period must be >= 0");
  if (!(p.time_limit > 0.0 && p.exit_time_limit > 0.0))
    return fail("room_visit/time_limit and room_visit/exit_time_limit must be > 0");
  return true;
}

void RoomVisit::beginNewRoom(const Pose2D& robot_odom, const DoorTrack& door, double hallway_heading_odom) {
  // The place's origin is the robot's pose (it stood still): the door in the robot frame is the
  // door in the place.
  new_room_ = true;
  door_width_ = door.width;
  place_origin_odom_ = robot_odom;
  first_origin_odom_.reset();
  hallway_in_place_ = Eigen::Vector2d::Zero();
  const Eigen::Vector2d c = transformPoint(inverse(robot_odom), door.centre_odom);
  door_in_place_ = Pose2D{c.x(), c.y(), normalizeAngle(door.into_odom - robot_odom.theta)};
  exit_theta_place_ = normalizeAngle(hallway_heading_odom - robot_odom.theta);
  explorer_.start(door_in_place_, door.width);
  goal_.reset();
  door_tracked_in_place_ = c;
  door_seen_sum_ = Eigen::Vector2d::Zero();
  door_seen_count_ = 0;
  other_doors_.clear();
}

void RoomVisit::beginKnownRoom(const Perception& p, const Pose2D& hallway_stop_odom, double hallway_heading_odom,
                               const GraphOpening& door, double door_width) {
  new_room_ = false;
  door_width_ = door_width;
  // Where the robot left the hallway, in the place (it may have moved to the door since).
  const Pose2D stop = compose(p.room_pose, compose(inverse(p.odom), hallway_stop_odom));
  hallway_in_place_ = Eigen::Vector2d(stop.x, stop.y);
  exit_theta_place_ = normalizeAngle(p.room_pose.theta + hallway_heading_odom - p.odom.theta);
  place_origin_odom_ = compose(p.odom, inverse(p.room_pose));  // stands in for missing EKF poses (see inPlace())
  first_origin_odom_.reset();
  other_doors_.clear();
  door_in_place_ = Pose2D{door.door_in_place[0], door.door_in_place[1], door.door_in_place[2]};
  explorer_.start(door_in_place_, door.width > 0.0 ? door.width : door_width);
}

Perception RoomVisit::inPlace(const Perception& p) {
  Perception q = p;
  if (!p.room_pose_valid || !finitePose(p.room_pose)) {
    // No EKF pose for this scan (it comes with the place's first features; or the EKF lags):
    // the odometry since the EKF's last pose stands in (its drift over a few scans is small).
    q.room_pose = compose(inverse(place_origin_odom_), p.odom);
    q.room_pose_valid = true;
  } else {
    // The place in the odometry frame as the EKF places it now, not as at the place's creation or
    // relocation: a goal in the place moves with the EKF's corrections.
    place_origin_odom_ = compose(p.odom, inverse(p.room_pose));
    if (!first_origin_odom_) first_origin_odom_ = place_origin_odom_;
  }
  return q;
}

std::optional<Pose2D> RoomVisit::odometryDrift() const {
  // The place stands still in the building: its origin moves in the odometry frame by the odometry's
  // drift alone (the EKF's corrections).
  if (!first_origin_odom_) return std::nullopt;
  return compose(place_origin_odom_, inverse(*first_origin_odom_));
}

void RoomVisit::observe(const Perception& q, bool approaching, Decision* d) {
  const Pose2D sensor = compose(q.room_pose, q.sensor_in_robot);
  // A new room's door as seen on the way to it: the track from the hallway may lie half a metre
  // along the wall from it, and the robot would meet the jamb.
  if (approaching && new_room_ && refineDoor(q)) explorer_.start(door_in_place_, door_width_);  // nothing of the room is seen yet
  if (!q.ranges.empty()) explorer_.addScan(sensor, q.ranges, q.angle_min, q.angle_increment);
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  // Near its door the robot passes it (the door's steps lie 0.6-0.7 m either side of it): the
  // controller keeps a clearance that fits the door.
  if ((robot - Eigen::Vector2d(door_in_place_.x, door_in_place_.y)).norm() < kDoorPassage) d->passage_width = door_width_;
  if (!approaching) {
    last_position_ = robot;
    scan_in_place_.clear();
    for (const Eigen::Vector2d& p : q.points) scan_in_place_.push_back(transformPoint(q.room_pose, p));
  }
}

std::optional<RoomVisit::DoorSighting> RoomVisit::seeDoor(const Perception& q, const Eigen::Vector2d& near,
                                                          double facing) const {
  double nearest = doors_.same_distance;
  std::optional<DoorSighting> seen;
  for (const laser_features::Opening& o : q.openings) {
    if (!(o.width >= rules_.door_min_width && rules_.mayBeDoor(o.width))) continue;
    if (std::abs(normalizeAngle(o.theta + q.room_pose.theta - facing)) > doors_.tracks.side_angle) continue;
    const Eigen::Vector2d c = transformPoint(q.room_pose, o.center);
    const double off = (c - near).norm();
    if (off < nearest) {
      nearest = off;
      seen = DoorSighting{c, o.width};
    }
  }
  return seen;
}

bool RoomVisit::refineDoor(const Perception& q) {
  // The door seen now, facing the way the tracked one does; the mean of its sightings on the
  // approach replaces the door (its direction, the hallway's normal, is kept) once it differs by
  // more than 5 cm.
  const std::optional<DoorSighting> seen = seeDoor(q, door_tracked_in_place_, door_in_place_.theta);
  if (!seen) return false;
  door_seen_sum_ += seen->centre;
  ++door_seen_count_;
  const Eigen::Vector2d mean = door_seen_sum_ / double(door_seen_count_);
  if ((mean - Eigen::Vector2d(door_in_place_.x, door_in_place_.y)).norm() <= 0.05) return false;
  door_in_place_.x = mean.x();
  door_in_place_.y = mean.y();
  return true;
}

bool RoomVisit::approachDoor(const Perception& q, double elapsed, Decision* d) {
  // In front of the door on its axis, facing in, before going through.
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const Eigen::Vector2d a = Eigen::Vector2d(door_in_place_.x, door_in_place_.y) - 0.6 * unitVector(door_in_place_.theta);
  goalInPlace(q, a, door_in_place_.theta, d);
  return (robot - a).norm() < kArrived || elapsed > 30.0;
}

double RoomVisit::doorRefinement() const {
  // The place's door in the EKF stays the door as tracked from the hallway: a mission's relocation
  // measures the robot from the door tracked the same way, so their biases cancel. The door as seen
  // is what the graph links: the way in.
  return (Eigen::Vector2d(door_in_place_.x, door_in_place_.y) - door_tracked_in_place_).norm();
}

RoomVisit::Coverage RoomVisit::coverRoom(const Perception& q, double now, double elapsed, Decision* d) {
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const Eigen::Vector2d door(door_in_place_.x, door_in_place_.y);
  // Other doors seen from inside the room are closed with a virtual wall: the room's map stays
  // the room's (they remain openings of the place).
  for (const auto& o : q.openings) {
    if (!rules_.isDoor(o.width, o.room_behind)) continue;
    const Eigen::Vector2d l = transformPoint(q.room_pose, o.left), r = transformPoint(q.room_pose, o.right);
    if ((0.5 * (l + r) - door).norm() < 0.8) continue;
    explorer_.blockOpening(l, r, o.in_wall);
    // The opening's normal points away from the sensor, which is inside the room.
    seeOtherDoor(0.5 * (l + r), normalizeAngle(q.room_pose.theta + o.theta + kPi), o.width, o.in_wall);
  }
  if (now - last_plan_ >= params_.replan_period || !goal_) {
    last_plan_ = now;
    goal_ = explorer_.nextGoal(robot, now);
  }
  const bool timeout = elapsed > params_.time_limit;
  if (timeout) return Coverage::TimedOut;
  if (explorer_.status() == RoomStatus::Done || explorer_.status() == RoomStatus::Invalid) return Coverage::Done;
  if (goal_) goalInPlace(q, *goal_, std::nullopt, d);
  else d->stop = true;
  return Coverage::Covering;
}

void RoomVisit::seeOtherDoor(const Eigen::Vector2d& centre, double into, double width, bool in_wall) {
  // Sightings of one door lie within half the span the hallway's tracker tells two doors apart by.
  const double same = 0.5 * HallwayDoors::kSameDoorSpan;
  for (SeenDoor& s : other_doors_) {
    if ((s.centre() - centre).norm() >= same) continue;
    s.centre_sum += centre;
    s.into_sum += unitVector(into);
    s.width_sum += width;
    ++s.count;
    if (in_wall) ++s.in_wall;
    return;
  }
  other_doors_.push_back(SeenDoor{centre, unitVector(into), width, 1, in_wall ? 1 : 0});
}

std::vector<DoorTrack> RoomVisit::otherDoorsOdom() const {
  std::vector<DoorTrack> doors;
  for (const SeenDoor& s : other_doors_) {
    DoorTrack t;
    t.centre_odom = transformPoint(place_origin_odom_, s.centre());
    t.into_odom = normalizeAngle(place_origin_odom_.theta + s.into());
    t.width = s.width_sum / s.count;
    t.sightings = s.count;
    doors.push_back(t);
  }
  return doors;
}

std::vector<Pose2D> RoomVisit::otherDoorsInPlace() const {
  std::vector<Pose2D> doors;
  for (const SeenDoor& s : other_doors_) {
    const Eigen::Vector2d c = s.centre();
    doors.push_back(Pose2D{c.x(), c.y(), s.into()});
  }
  return doors;
}

std::vector<RoomVisit::DoorInPlace> RoomVisit::innerDoors() const {
  const double min_depth = rules_.doorFromCorner();
  std::vector<DoorInPlace> doors;
  const std::optional<RoomExtent> room = explorer_.extent();
  for (const SeenDoor& s : other_doors_) {
    if (s.in_wall < 2 || explorer_.depth(s.centre()) < min_depth) continue;
    // A door of the room lies in its walls, on the edge of its free area's box (within a robot
    // radius: the wall's half thickness and a cell). A gap seen through another opening (a door
    // across the hallway, through the room's second hallway door) is none of its doors: no path
    // from the room reaches its front.
    if (!room || !room->contains(s.centre(), -explorer_.params().planner.robot_radius)) continue;
    const double into = s.into();
    // A gap between furniture and a wall is no door: the space behind it is the room's.
    if (!explorer_.leadsOutOfRoom(s.centre(), into, kDoorPassage)) continue;
    doors.push_back(DoorInPlace{s.centre(), into, s.width_sum / s.count, s.count});
  }
  return doors;
}

std::optional<RoomExtent> RoomVisit::extentOdom() const {
  std::optional<RoomExtent> e = explorer_.extent();
  if (e) e->door = compose(place_origin_odom_, e->door);
  return e;
}

DoorTrack RoomVisit::doorOdom() const {
  DoorTrack t;
  t.centre_odom = transformPoint(place_origin_odom_, Eigen::Vector2d(door_in_place_.x, door_in_place_.y));
  t.into_odom = normalizeAngle(place_origin_odom_.theta + door_in_place_.theta);
  t.width = door_width_;
  return t;
}

void RoomVisit::beginExit() {
  exit_attempts_ = 0;
  planExit();
}

void RoomVisit::planExit() {
  exit_path_.clear();
  // The first way out is the grid's: the robot came in through the grid's free space. The grid
  // can lose thin obstacles (a table's or chair's legs, 2-5 cm: the beams passing beside a leg
  // through its cell mark it free) that the scan sees and the controller keeps its clearance from;
  // a path between two such legs leaves the robot turning to and fro before them. Once a way out
  // has failed, the next ones keep clear of the latest scan's returns too (where none does, as
  // among table legs the robot drove in between, the grid's again: RoomExplorer::pathToExit).
  static const std::vector<Eigen::Vector2d> kNone;
  const std::vector<Eigen::Vector2d>& seen = exit_attempts_ > 0 ? scan_in_place_ : kNone;
  std::optional<Path> path = explorer_.pathToExit(last_position_, seen);
  // The way out has the virtual walls across furniture gaps (openings never seen as a gap in a
  // wall) that the coverage had. Where they cut the robot off from the door it came in by, they are
  // no walls between it and that door (it came from there). Without a path the steps through the
  // door start from where the robot is, which mostly gets it out (the exit point a metre or two
  // away); once that has failed, the next attempt plans with the gaps' walls taken away.
  if (!path && exit_attempts_ > 0 && explorer_.openFurnitureGaps() > 0) path = explorer_.pathToExit(last_position_, seen);
  if (path) exit_path_.set(path->waypoints);
}

bool RoomVisit::followExitPath(const Perception& q, double elapsed, Decision* d) {
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  exit_path_.advance(robot, explorer_.exitPlanner());
  if (exit_path_.done() || elapsed > params_.exit_time_limit) return true;
  goalInPlace(q, exit_path_.current(), std::nullopt, d);
  return false;
}

void RoomVisit::beginDoorExit(double now) {
  exit_step_ = 0;
  exit_step_since_ = now;
  exit_seen_sum_ = Eigen::Vector2d::Zero();
  exit_width_sum_ = 0.0;
  exit_seen_count_ = 0;
}

RoomVisit::DoorSighting RoomVisit::doorOnTheWayOut(const Perception& q) {
  // A narrow door leaves the controller a few centimetres a side (MotionController::
  // setPassageWidth: 5 cm for a 0.7 m door), less than the door as placed in the place may be off
  // by (the track from the hallway, the EKF's corrections since). From inside, both jambs in view
  // before the robot's body reaches the door line, the door is seen to a centimetre: the way
  // through is on the mean of this attempt's sightings.
  const Eigen::Vector2d placed(door_in_place_.x, door_in_place_.y);
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const bool inside = (robot - placed).dot(unitVector(door_in_place_.theta)) > explorer_.params().planner.robot_radius;
  if (inside && exit_step_ < 2) {
    if (const std::optional<DoorSighting> seen = seeDoor(q, placed, door_in_place_.theta + kPi)) {
      exit_seen_sum_ += seen->centre;
      exit_width_sum_ += seen->width;
      ++exit_seen_count_;
    }
  }
  if (exit_seen_count_ == 0) return DoorSighting{placed, door_width_};
  return DoorSighting{exit_seen_sum_ / double(exit_seen_count_), exit_width_sum_ / exit_seen_count_};
}

RoomVisit::Exit RoomVisit::exitThroughDoor(const Perception& q, double now, double elapsed, const MotionFeedback& motion,
                                           Decision* d) {
  // Each step through the door ends when reached, when the controller is blocked, or after a third
  // of exit_time_limit.
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const DoorSighting seen = doorOnTheWayOut(q);
  const Eigen::Vector2d door = seen.centre;
  const Eigen::Vector2d into = unitVector(door_in_place_.theta);
  if ((robot - door).norm() < kDoorPassage) d->passage_width = seen.width;
  const double inside = explorer_.params().exit_depth;  // where the grid path out ended
  const Eigen::Vector2d steps[2] = {door + inside * into, door - 0.7 * into};
  const bool step_timeout = now - exit_step_since_ > params_.exit_time_limit / 3.0;
  if (exit_step_ < 2) {
    // The way through starts on the door's axis facing out, as the way in did (approachDoor): in a
    // narrow door the controller has no room to steer onto the axis (passageSteering: 5 cm a side
    // in a 0.7 m door), nor to turn onto it (an arc drifts aside), on the way through. Facing out
    // within the angle that drifts that far before the door; already in the door, it goes on.
    const double out = normalizeAngle(door_in_place_.theta + kPi);
    const double depth = (robot - door).dot(into);
    const double radius = explorer_.params().planner.robot_radius;
    const double steer = passageSteering(seen.width, radius);
    const bool on_axis = std::abs(laser_features::cross2(into, robot - door)) <= steer &&
                         std::abs(normalizeAngle(q.room_pose.theta - out)) <= std::atan2(steer, inside);
    const bool done = exit_step_ == 0 ? (on_axis && depth < inside + 0.25) || depth < radius
                                      : (robot - steps[1]).norm() < 0.25;
    if (done || motion.blocked || step_timeout) {
      ++exit_step_;
      exit_step_since_ = now;
    }
    if (exit_step_ < 2) {
      goalInPlace(q, steps[exit_step_], exit_step_ == 0 ? std::optional<double>(out) : std::nullopt, d);
      return Exit::Passing;
    }
  }
  goalInPlace(q, hallway_in_place_, exit_theta_place_, d);
  const double err = std::abs(normalizeAngle(exit_theta_place_ - q.room_pose.theta));
  const bool back = ((robot - hallway_in_place_).norm() < 0.2 && err < 0.15) || (motion.reached && err < 0.2);
  if (!(back || step_timeout || elapsed > params_.exit_time_limit)) return Exit::Passing;
  // Out only once past the door line: a robot that did not get through (blocked at a narrow door,
  // the door placed off) and went on as on a hallway would take the room for hallways. It tries
  // again from where it is, kExitAttempts times in all.
  if ((robot - door).dot(into) > 0.0) {
    if (++exit_attempts_ < kExitAttempts) {
      planExit();
      return Exit::TryAgain;
    }
    return Exit::Stuck;
  }
  return back ? Exit::Back : Exit::NearlyBack;
}

void RoomVisit::turnExitHeadingRound() { exit_theta_place_ = normalizeAngle(exit_theta_place_ + laser_features::kPi); }

void RoomVisit::goalInPlace(const Perception& q, const Eigen::Vector2d& g, std::optional<double> theta,
                            Decision* d) const {
  // odom <- place: the robot's pose in both frames at the same stamp.
  const Pose2D odom_from_place = compose(q.odom, inverse(q.room_pose));
  const Eigen::Vector2d go = transformPoint(odom_from_place, g);
  d->has_goal = true;
  d->x = go.x();
  d->y = go.y();
  if (theta) d->theta = normalizeAngle(*theta + odom_from_place.theta);
}

}  // namespace exploration
