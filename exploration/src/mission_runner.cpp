#include "exploration/mission_runner.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace exploration {

using laser_features::compose;
using laser_features::inverse;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::unitVector;

MissionRunner::MissionRunner(const MissionParams& params) : params_(params) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("mission runner: " + why);
}

bool MissionRunner::validate(const MissionParams& p, std::string* error) {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (!(p.relocation_timeout > 0.0 && p.time_limit > 0.0 && p.stall_time > 0.0 && p.goal_tolerance > 0.0 &&
        p.heading_tolerance > 0.0 && p.accept_distance >= p.goal_tolerance && p.accept_angle >= p.heading_tolerance &&
        p.refine_attempts >= 0))
    return fail("mission/relocation_timeout, mission/time_limit, mission/stall_time and the mission tolerances must be "
                "> 0, the accepted distance and angle at least the tolerances, mission/refine_attempts >= 0");
  if (p.max_relocation_failures < 0) return fail("mission/max_relocation_failures must be >= 0");
  return true;
}

bool MissionRunner::start(int place_id, const Pose2D& goal, const TopoGraph& graph, double travel, double now,
                          std::string* why) {
  auto refuse = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!finitePose(goal)) return refuse("the goal is not finite");
  const std::optional<PlaceDoor> door = graph.placeDoor(place_id);
  if (!door) {
    std::ostringstream known;
    const std::set<int> ids = graph.placeIds();
    for (int id : ids) known << (known.tellp() > 0 ? ", " : "") << id;
    return refuse("place " + std::to_string(place_id) + " is unknown: no door of the topological map links it (known places: " +
                  (ids.empty() ? std::string("none") : known.str()) + ")");
  }
  active_ = true;
  place_ = place_id;
  goal_ = goal;
  place_door_ = *door;
  start_travel_ = travel;
  start_time_ = now;
  outcome_ = MissionOutcome();
  distance_left_ = 0.0;
  relocation_failures_ = 0;
  door_misses_ = 0;
  return true;
}

void MissionRunner::end(bool success, const std::string& why, double travel) {
  outcome_.finished = true;
  outcome_.success = success;
  outcome_.message = why;
  outcome_.path_length = travel - start_travel_;
  outcome_.relocation_failures = relocation_failures_;
  outcome_.door_misses = door_misses_;
  active_ = false;
}

void MissionRunner::updateDistanceLeft(const RouteStep& route) {
  const Eigen::Vector2d goal(goal_.x, goal_.y);
  const Eigen::Vector2d door(place_door_.opening.door_in_place[0], place_door_.opening.door_in_place[1]);
  distance_left_ = route.distance + (goal - door).norm();
}

bool MissionRunner::missDoor() { return ++door_misses_ > params_.max_relocation_failures; }

void MissionRunner::beginRelocation(const DoorTrack& door, const Pose2D& robot_odom, Decision* d) {
  askRelocation(Pose2D{door.centre_odom.x(), door.centre_odom.y(), door.into_odom}, robot_odom, d);
  relocate_step_ = 0;
  relocation_retried_ = false;
}

void MissionRunner::askRelocation(const Pose2D& door_odom, const Pose2D& robot_odom, Decision* d) {
  Request r;
  r.kind = Request::Relocate;
  r.place_id = place_;
  r.door_id = int(place_door_.node);
  r.pose = compose(inverse(door_odom), robot_odom);  // the robot in the door's frame
  d->requests.push_back(r);
  relocation_pending_ = true;
  relocation_ok_ = false;
  relocation_verdict_.clear();
}

void MissionRunner::relocationResult(bool success, const std::string& verdict) {
  relocation_pending_ = false;
  relocation_ok_ = success;
  relocation_verdict_ = verdict;
}

RelocationStep MissionRunner::relocate(const Perception& p, const DoorTrack& door, double now, double elapsed,
                                       const MotionFeedback& motion, Decision* d) {
  const bool timeout = elapsed > params_.relocation_timeout;
  const bool pose = p.room_pose_valid && finitePose(p.room_pose);
  if (relocation_ok_ && pose) return RelocationStep{RelocationStep::Relocated, ""};
  if (relocation_ok_ && !timeout) return RelocationStep{};  // the verdict came, the EKF's pose not yet
  // From the hallway the room may show too little (lines all parallel, or too few): ekf_local_map
  // keeps the relocation pending and tries again on every scan, so the robot moves in front of the
  // door, facing in, where it sees the room. A jointly incompatible match (the wrong room, or the
  // door seen off) is asked again from there once (below); a failure from there too is a failure.
  const bool wrong_room = relocation_verdict_ == "matches jointly incompatible";
  RelocationStep step;
  if (!relocation_pending_ && relocate_step_ == 0 && !timeout) {
    relocate_step_ = 1;
    relocate_step_since_ = now;
    step.text = "relocation from the hallway: " + relocation_verdict_ + "; trying again in front of the door";
  }
  if (relocate_step_ == 1 && !moveInFrontOfDoor(p, door, now, motion, d)) return step;
  // Jointly incompatible from the hallway is not yet the wrong room: the door, half a metre behind
  // the robot where it stopped, may be seen off by a few decimetres. A new relocation from in front
  // of the door, with the door as seen from there, decides (once).
  if (relocate_step_ == 2 && wrong_room && !relocation_retried_) {
    relocation_retried_ = true;
    askRelocation(doorSeen(p, door), p.odom, d);
    return RelocationStep{RelocationStep::AskedAgain,
                          "relocating again in place " + std::to_string(place_) + ", in front of its door"};
  }
  if (relocate_step_ == 2 && now - relocate_step_since_ < 3.0 && !wrong_room) return step;  // a few scans from there
  if (relocation_pending_ && !timeout) return step;
  // Not the goal's room (or no verdict): the belief was wrong.
  ++relocation_failures_;
  const std::string verdict = relocation_pending_ ? "no verdict in " + std::to_string(int(params_.relocation_timeout)) + " s"
                                                  : relocation_verdict_;
  if (relocation_failures_ > params_.max_relocation_failures) {
    return RelocationStep{RelocationStep::GaveUp, "relocation at the door of place " + std::to_string(place_) + " failed " +
                                                      std::to_string(relocation_failures_) + " times (last: " + verdict + ")"};
  }
  return RelocationStep{RelocationStep::Failed, "not the room of place " + std::to_string(place_) + " (relocation: " +
                                                    verdict + "): the belief is reset, following the hallway"};
}

bool MissionRunner::moveInFrontOfDoor(const Perception& p, const DoorTrack& door, double now, const MotionFeedback& motion,
                                      Decision* d) {
  const Eigen::Vector2d a = door.centre_odom - 0.6 * unitVector(door.into_odom);
  const bool there = (a - Eigen::Vector2d(p.odom.x, p.odom.y)).norm() < 0.1 &&
                     std::abs(normalizeAngle(door.into_odom - p.odom.theta)) < 0.1;
  if (there || (motion.reached && now - relocate_step_since_ > 1.0) || now - relocate_step_since_ > params_.relocation_timeout) {
    relocate_step_ = 2;
    relocate_step_since_ = now;
    return true;
  }
  d->stop = false;
  d->has_goal = true;
  d->x = a.x();
  d->y = a.y();
  d->theta = door.into_odom;
  return false;
}

Pose2D MissionRunner::doorSeen(const Perception& p, const DoorTrack& door) const {
  Pose2D seen_door{door.centre_odom.x(), door.centre_odom.y(), door.into_odom};
  double nearest = 0.5;  // m, the opening seen now that is the door
  for (const laser_features::Opening& o : p.openings) {
    const Pose2D seen = compose(p.odom, Pose2D{o.center.x(), o.center.y(), o.theta});
    const double off = (Eigen::Vector2d(seen.x, seen.y) - door.centre_odom).norm();
    if (off < nearest && std::abs(normalizeAngle(seen.theta - door.into_odom)) < 0.5) {
      nearest = off;
      seen_door = Pose2D{seen.x, seen.y, seen.theta};
    }
  }
  return seen_door;
}

void MissionRunner::beginGoToGoal(bool inside, double now) {
  entered_ = inside;
  goal_odom_valid_ = false;
  refines_ = 0;
  path_.clear();
  best_ = std::numeric_limits<double>::infinity();
  best_time_ = now;
  path_length_ = std::numeric_limits<double>::infinity();
  had_path_ = false;
}

std::optional<MissionEnd> MissionRunner::driveToGoal(const Perception& q, RoomVisit& visit, double now, double elapsed,
                                                     const MotionFeedback& motion, Decision* d) {
  const Eigen::Vector2d robot(q.room_pose.x, q.room_pose.y);
  const Eigen::Vector2d goal(goal_.x, goal_.y);
  GoalError error;
  error.distance = (goal - robot).norm();
  error.heading = std::abs(normalizeAngle(goal_.theta - q.room_pose.theta));
  distance_left_ = error.distance;
  char at[96];
  std::snprintf(at, sizeof(at), " (estimate %.3f m, %.3f rad from the goal)", error.distance, error.heading);
  error.text = at;
  // Where the controller stops (blocked) or stalls this close, the goal counts as reached.
  error.close = error.distance < params_.accept_distance && error.heading < params_.accept_angle;
  // Through the door on its axis first: the room's grid has a virtual wall across the door, so
  // no grid path leads in from the hallway, and a straight line from there meets the door's jamb.
  const Pose2D& door_pose = visit.doorInPlace();
  const Eigen::Vector2d door(door_pose.x, door_pose.y);
  const Eigen::Vector2d into = unitVector(door_pose.theta);
  const RoomExplorerParams& room = visit.explorer().params();
  // Once inside, never again (a goal just inside the door lies within entry_depth).
  if ((robot - door).dot(into) >= room.entry_depth) entered_ = true;
  const bool entering = !entered_ && (goal - door).dot(into) > 0.0;
  // Once inside, far from the goal: along a grid path in the room as seen (furniture between the
  // door and the goal); near it, or with no path, straight to it.
  if (!entering && (now - last_plan_ >= visit.params().replan_period || path_.empty()))
    planPath(visit, robot, goal, error.distance, now);
  const double left = entering ? error.distance : path_length_;
  if (left < best_ - 0.05) {
    best_ = left;
    best_time_ = now;
  }
  path_.advance(robot, visit.pathPlanner());
  const bool stalled = now - best_time_ > params_.stall_time;
  bool blocked_at_goal = false;  // the controller gave up on the final goal (sent before this tick)
  if (entering) {
    visit.goalInPlace(q, door + (room.entry_depth + room.entry_goal_extra) * into, door_pose.theta, d);
    goal_odom_valid_ = false;
  } else if (error.distance > 0.6 && path_.beforeLast()) {
    visit.goalInPlace(q, path_.current(), std::nullopt, d);
    goal_odom_valid_ = false;
  } else if (std::optional<MissionEnd> end = finalGoal(q, visit, error, motion, &blocked_at_goal, d)) {
    return end;
  }
  // The controller stopped (blocked) or the robot stalls this close: reached.
  if (error.close && (stalled || blocked_at_goal))
    return MissionEnd{true, "goal reached in place " + std::to_string(place_) + " within the accepted distance" + error.text};
  if (stalled) {
    return MissionEnd{false, "the goal is not reachable: no progress for " + std::to_string(int(params_.stall_time)) +
                                 " s, stopped at the closest reachable pose" + error.text + " (grid path of " +
                                 std::to_string(path_.size()) + " waypoints, at " + std::to_string(path_.index()) + ")"};
  }
  if (elapsed > visit.params().time_limit)
    return MissionEnd{false, "the goal was not reached in " + std::to_string(int(visit.params().time_limit)) + " s" + error.text};
  return std::nullopt;
}

void MissionRunner::planPath(RoomVisit& visit, const Eigen::Vector2d& robot, const Eigen::Vector2d& goal, double distance,
                             double now) {
  last_plan_ = now;
  path_.clear();
  const std::optional<Path> path = visit.pathTo(robot, goal);
  if (path) path_.set(path->waypoints);
  // Progress is along the way to the goal (the grid path's length), not straight at it: going
  // round furniture first leads away. A path found a metre longer than the last path (what was
  // unseen is blocked) starts the progress anew; no path (straight at the goal) never does, so a
  // goal with a path now and then (inside a wall) still stalls.
  const double length = path ? path->length : distance;
  if (path && had_path_ && length > path_length_ + 1.0) best_ = std::numeric_limits<double>::infinity();
  had_path_ = path.has_value();
  path_length_ = length;
}

std::optional<MissionEnd> MissionRunner::finalGoal(const Perception& q, const RoomVisit& visit, const GoalError& error,
                                                   const MotionFeedback& motion, bool* blocked_at_goal, Decision* d) {
  // In the odometry frame the goal moves with every EKF correction; it is re-sent only when it
  // moved by more than accept_distance (or accept_angle), so that the controller's reached and
  // blocked are about this goal, and a correction of a centimetre or two after the final turn does
  // not send a differential drive round to face a point 2 cm behind it.
  const bool sent = goal_odom_valid_;
  Decision g;
  visit.goalInPlace(q, Eigen::Vector2d(goal_.x, goal_.y), goal_.theta, &g);
  if (!sent || std::hypot(g.x - goal_odom_.x, g.y - goal_odom_.y) > params_.accept_distance ||
      std::abs(normalizeAngle(*g.theta - goal_odom_.theta)) > params_.accept_angle) {
    goal_odom_ = Pose2D{g.x, g.y, *g.theta};
    goal_odom_valid_ = true;
  }
  d->has_goal = true;
  d->x = goal_odom_.x;
  d->y = goal_odom_.y;
  d->theta = goal_odom_.theta;
  d->tolerance = std::make_pair(params_.goal_tolerance, params_.heading_tolerance);
  // Reached when the controller says so (it has stopped there; the EKF's estimate alone can pass
  // through the goal while the robot still turns) and the EKF agrees within the tolerances. Else
  // the goal is sent again from the EKF's estimate, refine_attempts times, and then accepted within
  // the accepted distance: the estimate moves by a few millimetres with every scan.
  const bool precise = error.distance <= params_.goal_tolerance && error.heading <= params_.heading_tolerance;
  if (sent && motion.reached && (precise || (error.close && refines_ >= params_.refine_attempts)))
    return MissionEnd{true, "goal reached in place " + std::to_string(place_) + error.text};
  if (sent && motion.reached) {
    ++refines_;
    goal_odom_valid_ = false;
  }
  *blocked_at_goal = sent && motion.blocked;
  if (*blocked_at_goal && !error.close)
    return MissionEnd{false, "the goal is not reachable: stopped at the closest reachable pose" + error.text};
  return std::nullopt;
}

}  // namespace exploration
