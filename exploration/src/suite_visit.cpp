#include "exploration/suite_visit.h"

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <limits>
#include <utility>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::transformPoint;
using laser_features::unitVector;

SuiteVisit::SuiteVisit(const RoomVisitParams& params, const RoomExplorerParams& room,
                       const laser_features::BuildingRules& rules, const HallwayDoorParams& doors)
    : params_(params), rules_(rules), inner_(params, room, rules, doors), peek_depth_(room.planner.robot_radius) {}

void SuiteVisit::roomCovered(const RoomVisit& room, double travel) {
  recent_rooms_.erase(std::remove_if(recent_rooms_.begin(), recent_rooms_.end(),
                                     [&](const std::pair<RoomExtent, double>& r) { return travel - r.second > kRecentTravel; }),
                      recent_rooms_.end());
  if (const std::optional<RoomExtent> e = room.extentOdom()) recent_rooms_.emplace_back(*e, travel);
}

void SuiteVisit::begin(const RoomVisit& host, double travel) {
  todo_.clear();
  for (const RoomVisit::DoorInPlace& door : host.innerDoors()) {
    const Eigen::Vector2d behind = transformPoint(host.placeOriginOdom(), door.centre - RoomVisit::kDoorPassage * unitVector(door.into));
    const bool covered = std::any_of(recent_rooms_.begin(), recent_rooms_.end(), [&](const std::pair<RoomExtent, double>& r) {
      return travel - r.second <= kRecentTravel && r.first.contains(behind, 0.0);
    });
    if (!covered) todo_.push_back(door);
  }
  inside_ = false;
  inner_doors_odom_.clear();
  unreached_.clear();
}

bool SuiteVisit::nextDoor(RoomVisit& host, const Eigen::Vector2d& robot) {
  // The nearest door by the host's grid; a door whose front no path reaches is dropped.
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_index = todo_.size();
  std::vector<Eigen::Vector2d> best_path;
  for (std::size_t i = 0; i < todo_.size(); ++i) {
    const Eigen::Vector2d front = todo_[i].centre + kFront * unitVector(todo_[i].into);
    const std::optional<Path> path = host.pathTo(robot, front);
    if (path && path->length < best) {
      best = path->length;
      best_index = i;
      best_path = path->waypoints;
    }
  }
  if (best_index == todo_.size()) {
    given_up_ += int(todo_.size());
    for (const RoomVisit::DoorInPlace& door : todo_) {
      char text[128];
      std::snprintf(text, sizeof(text), "%sno path to the front of the %.2f m inner door at (%.2f, %.2f) of the place",
                    unreached_.empty() ? "" : "; ", door.width, door.centre.x(), door.centre.y());
      unreached_ += text;
    }
    todo_.clear();
    return false;
  }
  door_ = todo_[best_index];
  todo_.erase(todo_.begin() + long(best_index));
  path_.set(std::move(best_path));
  planned_at_ = 0.0;
  peek_step_ = PeekStep::In;
  looks_ = door_sightings_ = 0;
  behind_ = Behind::Room;
  space_.clear();
  return true;
}

SuiteVisit::Drive SuiteVisit::driveToDoor(RoomVisit& host, const Perception& q, double elapsed, Decision* d) {
  if (elapsed > params_.exit_time_limit) {
    ++given_up_;
    return Drive::Failed;
  }
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const Eigen::Vector2d front = door_.centre + kFront * unitVector(door_.into);
  // The path is planned again from where the robot is every replan_period (as a mission's path in
  // a room), clear of the latest scan's returns: the host's grid loses thin obstacles (table and
  // chair legs, 2-5 cm: beams passing beside a leg mark its cell free), and a path between legs
  // leaves the robot turning to and fro before them. Where the scan leaves no way, the grid's.
  // The path followed is kept while what is left of it is clear in the new plan's snapshot: two
  // ways round a table about as long would swap as the scan changes, the robot turning between them.
  if (elapsed - planned_at_ >= params_.replan_period) {
    planned_at_ = elapsed;
    std::optional<Path> path = host.pathTo(robot, front, true);
    if (path && (path_.done() || !path_.restClear(robot, host.pathPlanner()))) path_.set(std::move(path->waypoints));
  }
  path_.advance(robot, host.pathPlanner());
  const double facing = normalizeAngle(door_.into + kPi);
  if (path_.beforeLast()) {
    host.goalInPlace(q, path_.current(), std::nullopt, d);
    return Drive::Driving;
  }
  host.goalInPlace(q, front, facing, d);
  return standsAt(q, front, facing) ? Drive::There : Drive::Driving;
}

bool SuiteVisit::standsAt(const Perception& q, const Eigen::Vector2d& p, double theta) {
  return (Eigen::Vector2d(q.room_pose.x, q.room_pose.y) - p).norm() < RoomVisit::kArrived &&
         std::abs(normalizeAngle(q.room_pose.theta - theta)) < RoomVisit::kArrived;
}

SuiteVisit::Drive SuiteVisit::peek(const RoomVisit& host, const Perception& q, double elapsed, Decision* d) {
  if (elapsed > params_.exit_time_limit) {
    ++given_up_;
    return Drive::Failed;
  }
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const Eigen::Vector2d into = unitVector(door_.into);  // into the host
  const double through = normalizeAngle(door_.into + kPi);
  d->passage_width = door_.width;
  if (peek_step_ == PeekStep::In) {
    const Eigen::Vector2d past = door_.centre - peek_depth_ * into;
    host.goalInPlace(q, past, through, d);
    if ((robot - past).norm() < RoomVisit::kArrived) peek_step_ = PeekStep::Look;
    return Drive::Driving;
  }
  if (peek_step_ == PeekStep::Look) {
    d->stop = true;
    if (looks_ == 0) {
      const Pose2D door_into_space{door_.centre.x(), door_.centre.y(), through};
      if (hallwayBehindDoor(q, door_into_space, rules_, &space_)) behind_ = Behind::Hallway;
    }
    std::string where;
    if (doorOntoHostHallway(q, host.doorInPlace(), door_, rules_, &where)) {
      ++door_sightings_;
      if (behind_ == Behind::Room && door_sightings_ >= 2) {
        behind_ = Behind::ConnectingRoom;
        space_ = where;
      }
    }
    if (++looks_ >= kLookScans) peek_step_ = PeekStep::Out;
    return Drive::Driving;
  }
  const Eigen::Vector2d front = door_.centre + kFront * into;
  host.goalInPlace(q, front, through, d);
  return standsAt(q, front, through) ? Drive::There : Drive::Driving;
}

void SuiteVisit::beginInnerRoom(const RoomVisit& host, const Pose2D& robot_odom) {
  // The door into the room behind, in the odometry frame: the host's into direction turned round.
  const Pose2D& origin = host.placeOriginOdom();
  DoorTrack door;
  door.centre_odom = transformPoint(origin, door_.centre);
  door.into_odom = normalizeAngle(origin.theta + door_.into + kPi);
  door.width = door_.width;
  door.sightings = door_.sightings;
  // Out of the room behind, the robot faces away from its door, into the host.
  inner_.beginNewRoom(robot_odom, door, normalizeAngle(door.into_odom + kPi));
  inside_ = true;
  through_ = false;
}

void SuiteVisit::endInnerRoom() {
  for (const DoorTrack& t : inner_.otherDoorsOdom()) inner_doors_odom_.push_back(t);
  inside_ = false;
}

Request SuiteVisit::keepOrigin(int host_place) {
  Request r;
  r.kind = Request::AddDoor;
  r.place_id = host_place;
  r.door_id = kNodelessDoorIdBase + origins_kept_++;
  r.pose = Pose2D{0.0, 0.0, 0.0};
  return r;
}

Request SuiteVisit::relocateHost(int host_place, const Perception& q) const {
  Request r;
  r.kind = Request::Relocate;
  r.place_id = host_place;
  r.door_id = kNodelessDoorIdBase + origins_kept_ - 1;
  r.pose = q.room_pose;
  // The EKF's uncertainty of it, where the scan has the EKF's pose (the odometry standing in for one
  // has none: the door's sigmas then).
  if (q.room_pose_cov.trace() > 0.0) r.pose_cov = q.room_pose_cov;
  return r;
}

void SuiteVisit::observeInner(const Perception& q) {
  through_ = inner_.explorer().depth(Eigen::Vector2d(q.room_pose.x, q.room_pose.y)) > 0.0;
}

bool doorOntoHostHallway(const Perception& q, const Pose2D& host_door, const RoomVisit::DoorInPlace& inner,
                         const laser_features::BuildingRules& rules, std::string* why) {
  // In the host door's frame: a into the host (0 on the hallway's near wall), b along that wall.
  const Eigen::Vector2d c(host_door.x, host_door.y), axis = unitVector(host_door.theta), wall(-axis.y(), axis.x());
  const double side = -unitVector(inner.into).dot(wall);  // the room behind lies this way along b
  if (std::abs(side) < std::cos(0.25 * kPi)) return false;
  const double sign = side > 0.0 ? 1.0 : -1.0;
  const double side_wall = (inner.centre - c).dot(wall) * sign;
  const double clear = rules.doorFromCorner();
  for (const laser_features::Opening& o : q.openings) {
    if (!rules.isDoor(o.width, o.room_behind)) continue;
    const Eigen::Vector2d r = transformPoint(q.room_pose, o.center) - c;
    const double a = r.dot(axis), b = r.dot(wall) * sign;
    if (std::abs(a) > 0.5 * rules.hallway_min_width || b < side_wall + clear) continue;
    if (why) {
      char text[128];
      std::snprintf(text, sizeof(text), "a %.2f m door in the hallway's wall %.2f m past the side wall", o.width,
                    b - side_wall);
      *why = text;
    }
    return true;
  }
  return false;
}

bool hallwayBehindDoor(const Perception& q, const Pose2D& door, const laser_features::BuildingRules& rules,
                       std::string* why) {
  // In the door's frame: a along its axis into the space, b along its wall (left +).
  const Eigen::Vector2d c(door.x, door.y), axis = unitVector(door.theta), wall(-axis.y(), axis.x());
  const double inf = std::numeric_limits<double>::infinity();
  // The wall ahead: the nearest wall line across the axis ahead of the robot (within 0.3 rad of the
  // door's wall, a metre long at least) that spans the axis within the widest hallway's half either
  // side; a door across the way (offset or not) leaves the wall beside it.
  double ahead = inf;
  const double half = 0.5 * rules.hallway_max_width;
  const double robot_a = (Eigen::Vector2d(q.room_pose.x, q.room_pose.y) - c).dot(axis);  // past the door's wall
  for (const laser_features::LineSegment& l : q.lines) {
    if (l.length() < 1.0) continue;
    const Eigen::Vector2d s0 = transformPoint(q.room_pose, l.start) - c, s1 = transformPoint(q.room_pose, l.end) - c;
    const Eigen::Vector2d d = (s1 - s0).normalized();
    if (std::abs(d.dot(axis)) > std::sin(0.3)) continue;
    const double b0 = std::min(s0.dot(wall), s1.dot(wall)), b1 = std::max(s0.dot(wall), s1.dot(wall));
    if (b1 < -half || b0 > half) continue;
    const double a = 0.5 * (s0 + s1).dot(axis);
    if (a > robot_a) ahead = std::min(ahead, a);
  }
  // Along the wall: the nearest scan point either side in the middle of the band between the door's
  // wall and the wall ahead (clear of both, tilted by the axis' error).
  double left = inf, right = inf;
  if (std::isfinite(ahead)) {
    for (const Eigen::Vector2d& p : q.points) {
      const Eigen::Vector2d r = transformPoint(q.room_pose, p) - c;
      const double a = r.dot(axis), b = r.dot(wall);
      if (a < 0.3 * ahead || a > 0.7 * ahead) continue;
      if (b > 0.0) left = std::min(left, b);
      else right = std::min(right, -b);
    }
  }
  if (why) {
    char text[128];
    std::snprintf(text, sizeof(text), "%.2f m deep, %.2f m left and %.2f m right along the door's wall", ahead, left,
                  right);
    *why = text;
  }
  const double widest = rules.hallway_max_width + rules.width_tolerance;
  return ahead <= widest && left > rules.hallway_max_width && right > rules.hallway_max_width;
}

}  // namespace exploration
