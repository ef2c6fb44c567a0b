#include "exploration/coordinator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace exploration {

using laser_features::inverse;
using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::transformPoint;
using laser_features::unitVector;

namespace {

// m: the robot is at a node when the belief puts it this close (pomdp_topo's node_radius).
constexpr double kAtNodeDistance = 1.0;

}  // namespace

const char* toString(CoordinatorMode mode) {
  switch (mode) {
    case CoordinatorMode::Topological: return "TOPOLOGICAL";
    case CoordinatorMode::Metric: return "METRIC";
    case CoordinatorMode::Switching: return "SWITCHING";
    case CoordinatorMode::Done: return "DONE";
  }
  return "?";
}

bool Coordinator::validate(const CoordinatorParams& p, std::string* error) {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (!(p.lookahead > 0.3)) return fail("lookahead must be > 0.3 m");
  if (!(p.end_distance > 0.5)) return fail("end_distance must be > 0.5 m");
  if (!p.rules.valid(error)) return false;
  if (!(p.doors.min_confidence >= 0.0 && p.doors.min_confidence <= 1.0)) return fail("door_min_confidence must be in [0, 1]");
  if (!(p.doors.max_lateral > 0.0 && p.doors.side_angle > 0.0 && p.doors.pass_distance >= 0.0 && p.doors.same_distance > 0.0 &&
        p.doors.wall_tolerance > 0.0 && p.doors.wall_memory >= 0.0))
    return fail("door_max_lateral, door_side_angle, door_same_distance and door_wall_tolerance must be > 0, "
                "door_pass_distance and door_wall_memory >= 0");
  if (!RoomVisit::validate(p.room_visit, error)) return false;
  if (!(p.settle_time >= 0.0 && p.max_time >= 0.0)) return fail("settle_time and max_time must be >= 0");
  if (p.max_route_attempts < 1) return fail("max_route_attempts must be >= 1");
  if (!(p.goal_pass_distance > 0.0)) return fail("goal_pass_distance must be > 0");
  if (!(p.jump_tolerance >= 0.0 && p.jump_hold_distance >= 0.0)) return fail("jump_tolerance and jump_hold_distance must be >= 0");
  if (!(p.branch_record_distance >= 0.0 && p.u_turn_cost >= 0.0 && p.goal_refresh_distance > 0.0))
    return fail("branch_record_distance and u_turn_cost must be >= 0, goal_refresh_distance > 0");
  if (!MissionRunner::validate(p.mission, error)) return false;
  if (!(p.follow_stall_time > 0.0)) return fail("follow_stall_time must be > 0");
  return RoomExplorer::validate(p.room, error);
}

Coordinator::Coordinator(const CoordinatorParams& params)
    : params_(params),
      visit_(params.room_visit, params.room, params.rules, params.doors),
      mission_(params.mission),
      doors_(params.doors, params.rules) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("exploration coordinator: " + why);
  // The hallway view's derived sizes: the robot's footprint and the building's narrowest hallway.
  params_.hallway.clearance = params.room.planner.robot_radius + params.room.planner.safety_margin;
  params_.hallway.min_mouth = params.rules.hallway_min_width - params.rules.width_tolerance;
}

void Coordinator::setState(State s, const std::string& text) {
  state_ = s;
  state_since_ = now_;
  state_text_ = text;
  stall_since_ = -1.0;  // the stall window starts again in the next state
  lane_valid_ = false;
}

double Coordinator::binHeading(int bin) const { return bins_.heading(bin); }

int Coordinator::binOf(double map_heading) const { return bins_.bin(map_heading); }

std::optional<int> Coordinator::startHallwayAxis(const Perception& p, const TopoView& topo) const {
  // The hallway the robot starts in runs between the nearest walls beside it: of the two axes, the
  // one whose parallel wall lines enclose the robot most narrowly, within a hallway's width
  // (BuildingRules::hallway_max_width, the robot anywhere across it). Beside: a wall reaches within
  // half the widest door of the robot along the axis (a door's wall does, on both sides of the door
  // the robot may stand in front of). A view through a door ahead is no hallway however deep: the
  // room's side walls begin beyond the hallway's wall, its far wall and the hallway's wall behind
  // the robot are farther apart than a hallway is wide.
  const HallwayViewParams& hp = params_.hallway;
  const int quarter = bins_.bins / 4;
  std::optional<int> best;
  double best_width = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 2; ++axis) {
    const double dir = normalizeAngle(odomHeadingOfBin(bin_ + axis * quarter, topo) - p.odom.theta);  // robot frame
    const Eigen::Vector2d u = unitVector(dir), n = unitVector(dir + 0.5 * kPi);
    double left = std::numeric_limits<double>::infinity(), right = left;
    for (const laser_features::LineSegment& l : p.lines) {
      const Eigen::Vector2d d = l.end - l.start;
      if (d.norm() < hp.wall_min_length) continue;
      if (std::abs(laser_features::cross2(u, d.normalized())) > std::sin(hp.wall_parallel_tolerance)) continue;
      const double beside = 0.5 * params_.rules.door_max_width + params_.rules.width_tolerance;
      const double a0 = u.dot(l.start), a1 = u.dot(l.end);
      if (std::min(a0, a1) > beside || std::max(a0, a1) < -beside) continue;
      const double offset = n.dot(0.5 * (l.start + l.end));
      (offset > 0.0 ? left : right) = std::min(offset > 0.0 ? left : right, std::abs(offset));
    }
    if (left + right <= params_.rules.hallway_max_width + params_.rules.width_tolerance && left + right < best_width) {
      best_width = left + right;
      best = axis;
    }
  }
  return best;
}

int Coordinator::startBin(const Perception& p, const TopoView& topo) const {
  // The robot may start facing any way: it sets off along the hallway it stands in (above), along
  // its own bin if that is one of the two, else along the one whose way is free the farthest. With
  // no walls on both sides of it: a hallway is longer than it is wide, so when the way ahead is
  // shorter than a way to the side, the robot stands across the hallway.
  const auto free = [&](int bin) {
    return freeDistance(p.points, normalizeAngle(odomHeadingOfBin(bin, topo) - p.odom.theta), params_.hallway.ahead_sector,
                        15.0);
  };
  const int quarter = bins_.bins / 4;
  if (const std::optional<int> axis = startHallwayAxis(p, topo)) {
    if (*axis == 0) return bin_;
    return free(bin_ + quarter) >= free(bin_ - quarter) ? bins_.wrap(bin_ + quarter) : bins_.wrap(bin_ - quarter);
  }
  if (free(bin_) >= std::max(free(bin_ + quarter), free(bin_ - quarter))) return bin_;
  int best = bin_;
  for (int k = 1; k < bins_.bins; ++k) {
    if (free(bin_ + k) > free(best)) best = bins_.wrap(bin_ + k);
  }
  return best;
}

double Coordinator::odomHeadingOfBin(int bin, const TopoView& topo) const {
  return normalizeAngle(binHeading(bin) - (topo.heading_valid ? topo.heading_offset : 0.0));
}

Decision Coordinator::update(const Perception& p, const TopoView& topo, bool motion_reached, bool motion_blocked) {
  Decision d;
  d.requests = std::move(pending_requests_);
  pending_requests_.clear();
  if (!finitePose(p.odom) || !std::isfinite(p.stamp)) {
    d.stop = true;
    d.mode = mode_;
    return d;
  }
  now_ = p.stamp;
  if (start_time_ < 0.0) start_time_ = now_;
  if (have_last_odom_) {
    const double step = std::hypot(p.odom.x - last_odom_.x, p.odom.y - last_odom_.y);
    if (step < 1.0) travel_ += step;  // a teleport is no travel
  }
  last_odom_ = p.odom;
  have_last_odom_ = true;
  stats_.travel = travel_;
  if (topo.mode != "frontier" || !topo.position.valid || !topo.position.at_node) {
    frontier_node_ = -1;  // a new stretch from the same node later starts counting again
  } else if (int(topo.position.id) != frontier_node_) {
    frontier_node_ = int(topo.position.id);
    frontier_node_travel_ = travel_;
  }

  if (!idle() && !mission_.active() && params_.max_time > 0.0 && now_ - start_time_ > params_.max_time) {
    finish(false, "time limit reached before the exploration was complete", &d);
  }
  if (mission_.active() && mission_.timedOut(now_)) {
    endMission(false, "the mission's time limit (" + std::to_string(int(params_.mission.time_limit)) + " s) was reached", &d);
  }
  switch (state_) {
    case State::Init:
      start(p, topo, &d);
      break;
    case State::Follow:
      follow(p, topo, motion_blocked, &d);
      break;
    case State::Turn:
      turn(p, motion_reached, motion_blocked, &d);
      break;
    case State::StopForDoor:
      stopForDoor(p, topo, &d);
      break;
    case State::EnterRoom:
      enterRoom(p, topo, &d);
      break;
    case State::Relocate:
      relocate(p, topo, &d);
      break;
    case State::ApproachDoor:
    case State::Room:
    case State::GoToGoal:
    case State::ExitPath:
    case State::ExitDoor:
      motion_ = MotionFeedback{motion_reached, motion_blocked};
      visitRoom(p, &d);
      if (state_ == State::Follow) {
        // Back on the hallway's mid-line: the room is done.
        d.requests.insert(d.requests.begin(), Request{Request::ClosePlace});
      }
      break;
    case State::Done:
      d.stop = true;
      break;
    case State::Idle:
      d.stop = true;
      mode_ = in_room_ ? CoordinatorMode::Metric : CoordinatorMode::Topological;
      break;
  }
  d.mode = mode_;
  return d;
}

void Coordinator::start(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  if (topo.valid && topo.heading_valid && !topo.mode.empty()) {
    bin_ = binOf(p.odom.theta + topo.heading_offset);
    if (!params_.explore) {
      setState(State::Idle, "waiting for a mission");
      return;
    }
    const int along = startBin(p, topo);
    const double back = normalizeAngle(odomHeadingOfBin(along + bins_.bins / 2, topo) - p.odom.theta);
    const double free_back = freeDistance(p.points, back, params_.hallway.ahead_sector, 15.0);
    if (topo.mode == "frontier" && free_back > params_.end_distance + 1.0) {
      // The robot starts mid-hallway: the way behind it is an unexplored opening of the start node.
      Request r;
      r.kind = Request::RecordOpening;
      r.bearing = binHeading(along + bins_.bins / 2);
      d->requests.push_back(r);
    }
    if (along != bin_) startTurn(along, p, topo, {});
    else setState(State::Follow, "following the hallway");
  }
}

void Coordinator::turn(const Perception& p, bool motion_reached, bool motion_blocked, Decision* d) {
  // Turn on the spot where the robot is now: a position fixed when the turn was decided lies
  // behind the robot once it has braked, and the controller would turn round to reach it.
  turnGoal(p, d);
  const double err = std::abs(normalizeAngle(turn_odom_heading_ - p.odom.theta));
  if ((motion_reached && err < 0.15) || err < 0.05 || (motion_blocked && err < 0.3)) {
    bin_ = turn_bin_;
    stall_since_ = -1.0;
    pending_branch_travel_ = travel_;
    last_turn_travel_ = travel_;
    have_goal_ = false;
    setState(State::Follow, "following the hallway");
  }
}

void Coordinator::stopForDoor(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  mode_ = CoordinatorMode::Switching;
  if (mission_.active()) {
    if (now_ - state_since_ >= params_.settle_time) beginRelocation(p, d);
    return;
  }
  if (now_ - state_since_ >= params_.settle_time && enter_node_ < 0 && topo.mode != "frontier" &&
      !mayEnter(topo, door_)) {
    // Stopped for a door on a new stretch, and pomdp_topo has since made its node and taken it
    // for a known one: a loop hypothesis (the check merges the node, the door explored, or
    // rejects it, its opening unexplored and come back to), or a loop closed in the same scan
    // (explore_restart: room_east mapped twice). Entered only as a known unexplored door
    // (mayEnter); else on along the hallway.
    mode_ = CoordinatorMode::Topological;
    ++stats_.doors_passed;
    setState(State::Follow, topo.mode == "loop_check" ? "door passed: pomdp_topo checks whether it is a known one"
                                                      : "door passed: it is a known one (pomdp_topo closed a loop at it)");
    return;
  }
  if (now_ - state_since_ >= params_.settle_time && enter_node_ < 0 && exploredAtFrontierNode(topo, door_)) {
    // On a new stretch pomdp_topo took the door for one its current node has, explored: a door
    // recorded at a junction a metre off its centre, seen again from it (large_floor: room_7_14,
    // entered from the junction at a T, entered again from a stretch leaving it 5,600 s later).
    mode_ = CoordinatorMode::Topological;
    ++stats_.doors_passed;
    setState(State::Follow, "door passed: the node's explored one");
    return;
  }
  if (now_ - state_since_ >= params_.settle_time) {
    // The door's node exists now (passed); the topological map stands still from here on.
    mode_ = CoordinatorMode::Metric;
    hallway_pose_odom_ = p.odom;
    hallway_bin_ = bin_;
    hallway_offset_ = axis_offset_;
    door_bearing_map_ = enter_bearing_;
    Request rec;
    rec.kind = Request::RecordOpening;
    rec.node = enter_node_;
    rec.bearing = door_bearing_map_;
    rec.width = door_.width;
    d->requests.push_back(rec);
    Request create;
    create.kind = Request::CreatePlace;
    d->requests.push_back(create);
    place_ok_ = false;
    door_node_ = -1;
    setState(State::EnterRoom, "creating a place for the room");
  }
}

void Coordinator::enterRoom(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  if (!place_ok_) {
    // No place: the room cannot be mapped. Mark the door so it is not tried forever.
    Request rec;
    rec.kind = Request::RecordOpening;
    rec.node = door_node_;
    rec.bearing = door_bearing_map_;
    rec.explored = true;
    d->requests.push_back(rec);
    mode_ = CoordinatorMode::Topological;
    setState(State::Follow, "could not create a place: door skipped");
    return;
  }
  visit_.beginNewRoom(p.odom, door_, odomHeadingOfBin(hallway_bin_, topo) + hallway_offset_);
  Request add;
  add.kind = Request::AddDoor;
  add.door_id = std::max(0, door_node_);
  add.place_id = place_id_;
  add.pose = visit_.doorInPlace();
  d->requests.push_back(add);
  ++stats_.places;
  ++stats_.doors_entered;
  setState(State::ApproachDoor, "entering the room of place " + std::to_string(place_id_));
}

void Coordinator::follow(const Perception& p, const TopoView& topo, bool blocked, Decision* d) {
  mode_ = CoordinatorMode::Topological;
  HallwayView v;
  const double dir_robot = trackHallwayAxis(p, topo, &v);
  if (followStalled(p)) blocked = true;
  const bool localized = topo.mode == "localized";
  const bool sure = (topo.mode == "frontier") || (localized && topo.confident && beliefPlausible(topo));
  state_text_ = sure ? (localized ? "following the hallway on the known map" : "following a new hallway")
                     : "following the hallway until the belief is confident";

  recordWaysNotTaken(sure, d);
  RouteStep route;
  if (localized && sure && followRoute(p, topo, &route, d)) return;
  if (enterPassedDoor(p, topo, dir_robot, v, d)) return;
  if (turnIntoRouteBranch(p, topo, route, sure, dir_robot, v, d)) return;

  const std::optional<double> lane = laneAround(p, dir_robot, v, blocked);
  if ((v.free_ahead < params_.end_distance && !lane) || blocked) {
    decideAtEnd(p, topo, v, d);
    if (blocked) state_text_ = "motion blocked: " + state_text_;
    if (state_ == State::Turn) {
      turnGoal(p, d);
      return;
    }
  }

  // The goal: lookahead metres ahead on the mid-line (past an obstacle, on the lane beside it).
  const double ahead = lane ? std::max(params_.lookahead, v.free_ahead + params_.end_distance) : params_.lookahead;
  const Eigen::Vector2d g_robot = ahead * unitVector(dir_robot) + lane.value_or(v.centre_offset) * unitVector(dir_robot + 0.5 * kPi);
  const Eigen::Vector2d g = transformPoint(p.odom, g_robot);
  if (!have_goal_ || (g - last_goal_).norm() > params_.goal_refresh_distance) {
    last_goal_ = g;
    have_goal_ = true;
  }
  d->has_goal = true;
  d->x = last_goal_.x();
  d->y = last_goal_.y();
}

std::optional<double> Coordinator::laneAround(const Perception& p, double dir_robot, const HallwayView& v, bool blocked) {
  // An obstacle ahead is no hallway end where the hallway's walls go on past it and a lane beside
  // it is free as far (a pillar, a chair, a person): the robot keeps to that lane. The lane taken
  // is kept while it stays free past the obstacle: another lane as free (the other side of a pillar
  // on the mid-line) would swing the robot from side to side in front of it.
  const Eigen::Vector2d n = unitVector(dir_robot + 0.5 * kPi);
  if (lane_valid_ && transformPoint(inverse(p.odom), lane_point_odom_).dot(unitVector(dir_robot)) < -params_.end_distance)
    lane_valid_ = false;  // the obstacle is passed
  if (!(v.free_ahead < params_.end_distance) || blocked) return std::nullopt;
  const double past = v.free_ahead + params_.end_distance;
  if (!v.wallsReach(past)) return std::nullopt;
  const double clearance = params_.hallway.clearance;
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
  state_text_ = "passing an obstacle in the hallway";
  return lane;
}

void Coordinator::recordWaysNotTaken(bool sure, Decision* d) {
  // The ways not taken at the last turn, once the map builder has the turn's node.
  if (pending_branch_travel_ >= 0.0 && travel_ - pending_branch_travel_ >= params_.branch_record_distance) {
    if (sure) {
      for (int b : pending_branches_) {
        Request r;
        r.kind = Request::RecordOpening;
        r.bearing = binHeading(b);
        d->requests.push_back(r);
      }
    }
    pending_branches_.clear();
    pending_branch_travel_ = -1.0;
  }
}

bool Coordinator::followRoute(const Perception& p, const TopoView& topo, RouteStep* out, Decision* d) {
  RouteStep& route = *out;
  if (!mission_.active() && graph_.nodes().size() > 1 && graph_.unexploredCount() == 0 && pending_branches_.empty()) {
    // Complete only if nothing was given up: an opening given up unreached counts as explored,
    // and rooms behind it may be missing; a room left at its time limit is not all mapped.
    if (stats_.openings_given_up > 0 || stats_.rooms_left_early > 0) {
      finish(false, "no unexplored opening is left, but " + std::to_string(stats_.openings_given_up) +
                        " opening(s) were given up unreached and " + std::to_string(stats_.rooms_left_early) +
                        " room(s) left at their time limit", d);
    } else {
      finish(true, "no unexplored opening is left", d);
    }
    return true;
  }
  route = plan(topo.position);
  if (mission_.active()) {
    if (!route.found) {
      endMission(false, "no route on the topological map to the door of place " + std::to_string(mission_.place()), d);
      return true;
    }
    mission_.updateDistanceLeft(route);
  }
  const int near = graph_.nearestNode(topo.position);
  if (giveUpGoalPassed(topo, route, near, d)) return true;
  return turnRoundForRoute(p, topo, route, near, d);
}

bool Coordinator::giveUpGoalPassed(const TopoView& topo, const RouteStep& route, int near, Decision* d) {
  // At the goal node with its opening to a side that never opens (a door the laser does not show
  // again, a wide door taken for a branch): give it up once the robot has gone past, instead of
  // turning round for it again and again (each U-turn on a hallway weakens the belief).
  // Doors only: a hallway branch is never given up this way (the north half of institute lies
  // behind one); the robot turns into it when its side opens (below).
  const bool door_goal = route.goal_width > 0.0 && params_.rules.doorByWidth(route.goal_width);
  // Counted from within kAtNodeDistance of it: the nearest node changes half-way along an edge
  // (institute's printer door, 1.5 m before hall_north's east end: given up 3 m after the middle
  // of its 6.5 m edge, before the robot had reached it or turned round at the end to pass it).
  const bool at_goal = near >= 0 && uint32_t(near) == route.goal_node;
  const bool close = at_goal && graph_.nearestNodeDistance(topo.position) <= kAtNodeDistance;
  if (!mission_.active() && route.found && door_goal && at_goal && (goal_pass_node_ == near || close)) {
    if (goal_pass_node_ != near) {
      goal_pass_node_ = near;
      goal_pass_travel_ = travel_;
    } else if (travel_ - goal_pass_travel_ > params_.goal_pass_distance) {
      Request give_up;
      give_up.kind = Request::RecordOpening;
      give_up.node = near;
      give_up.bearing = route.goal_bearing;
      give_up.explored = true;
      d->requests.push_back(give_up);
      ++stats_.openings_given_up;
      goal_pass_node_ = -1;
      state_text_ = "passed node " + std::to_string(near) + " without finding its opening: given up";
      return true;
    }
  } else if (near != goal_pass_node_) {
    goal_pass_node_ = -1;
  }
  return false;
}

bool Coordinator::turnRoundForRoute(const Perception& p, const TopoView& topo, const RouteStep& route, int near,
                                    Decision* d) {
  // The route points back along the hallway: turn round (after a few ticks of agreement), but
  // not for the node the robot is at: its door is entered once passed, or given up (above).
  if (route.found && (near < 0 || uint32_t(near) != route.goal_node) &&
      std::abs(normalizeAngle(route.heading - binHeading(bin_))) > 0.75 * kPi) {
    // Not again soon after a turn: a belief flickering between two edges would swing the robot.
    if (++route_behind_ticks_ >= 5 && travel_ - last_turn_travel_ > 3.0) {
      route_behind_ticks_ = 0;
      // An opening the robot keeps turning round for (it passes its node without taking it:
      // the door is not seen, or the belief flickers) is given up after max_route_attempts.
      const bool missed = ++route_attempts_[route.goal_node] > params_.max_route_attempts;
      if (missed && mission_.active()) {
        const std::string why = "the door of place " + std::to_string(mission_.place()) + " was not found at node " +
                                std::to_string(route.goal_node) + " after " + std::to_string(params_.max_route_attempts) +
                                " turns towards it";
        // A confident belief that keeps missing the door is likely wrong (a look-alike stretch):
        // global localization again (a uniform belief) rather than giving up or going on lost.
        if (mission_.missDoor()) {
          endMission(false, why + ", " + std::to_string(mission_.doorMisses()) + " times", d);
          return true;
        }
        route_attempts_.clear();
        Request reset;
        reset.kind = Request::ResetBelief;
        d->requests.push_back(reset);
        state_text_ = why + ": the belief is reset";
        return true;
      }
      if (missed) {
        giveUpRouteGoal(route, d);
        return true;
      }
      ++stats_.u_turns;
      startTurn(bin_ + bins_.bins / 2, p, topo, {});
      state_text_ = "turning round towards node " + std::to_string(route.goal_node) + " (" +
                    std::to_string(route.distance) + " m, from " + (topo.position.at_node ? "node " : "edge ") +
                    std::to_string(topo.position.id) + ")";
      turnGoal(p, d);
      return true;
    }
  } else {
    route_behind_ticks_ = 0;
  }
  return false;
}

void Coordinator::giveUpRouteGoal(const RouteStep& route, Decision* d) {
  Request give_up;
  give_up.kind = Request::RecordOpening;
  give_up.node = int(route.goal_node);
  give_up.bearing = route.goal_bearing;
  give_up.explored = true;
  d->requests.push_back(give_up);
  ++stats_.openings_given_up;
  route_attempts_.erase(route.goal_node);
  for (auto it = branch_turns_.begin(); it != branch_turns_.end();) {
    it = it->first.second == route.goal_node ? branch_turns_.erase(it) : std::next(it);
  }
  state_text_ = "gave up an opening of node " + std::to_string(route.goal_node);
}

bool Coordinator::enterPassedDoor(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v,
                                  Decision* d) {
  // Doors: entered once passed, if new (frontier) or known and unexplored, and the belief is sure.
  const HallwayDoors::Walls walls = doors_.track(p.odom, p.openings, dir_robot, v, travel_);
  DoorTrack door;
  if (doors_.passed(p.odom, dir_robot, walls, &door)) {
    if (justLeft(door)) {
      ++stats_.doors_passed;
      state_text_ = "door passed: the one just left";
    } else if (mayEnter(topo, door)) {
      door_ = door;
      // Where the door was taken to be (the log tells a door tracked wrongly from a real one).
      const Eigen::Vector2d rel = transformPoint(inverse(p.odom), door.centre_odom);  // robot frame
      char where[128];
      char wall[40] = "no wall known";
      if (door.wall_lateral >= 0.0) std::snprintf(wall, sizeof(wall), "its wall %.2f m aside", door.wall_lateral);
      std::snprintf(where, sizeof(where), " (%.2f m wide, %d sightings, at %.2f m ahead, %.2f m left, %s)", door.width,
                    door.sightings, rel.x(), rel.y(), wall);
      setState(State::StopForDoor, std::string("stopping at a door to enter the room") + where);
      d->stop = true;
      return true;
    }
    ++stats_.doors_passed;
  }
  return false;
}

bool Coordinator::turnIntoRouteBranch(const Perception& p, const TopoView& topo, const RouteStep& route, bool sure,
                                      double dir_robot, const HallwayView& v, Decision* d) {
  // A side branch the route takes at the node the robot is at now (the side must be open: the
  // branch's mouth is beside the robot).
  // A door is entered once passed (above), never turned into like a branch: a mission's goal, and
  // an exploration's goal opening as narrow as only a door is (a side sector of a narrow hallway
  // sees through a door into the room behind it and opens).
  const bool door_next = route.next_node == route.goal_node &&
                         (mission_.active() || (route.goal_width > 0.0 && params_.rules.doorByWidth(route.goal_width)));
  if (route.found && sure && !door_next) {
    const int route_bin = binOf(route.next_heading);
    const int n = bins_.bins;
    const bool left = route_bin == (bin_ + n / 4) % n, right = route_bin == (bin_ + 3 * n / 4) % n;
    const int near = graph_.nearestNode(topo.position);
    // At the node as the belief says, or within 2 m of the goal node: the belief may be off by a
    // metre, the branch's mouth opens the side sector only within a quarter metre of its centre.
    const bool here = (near >= 0 && uint32_t(near) == route.next_node) ||
                      (route.next_node == route.goal_node && route.distance < 2.0);
    // A door abeam on that side is not the branch: the belief that puts the robot at the branch's
    // node is wrong (large_floor: node 18's 2.2 m crossing taken at a 1.2 m office door 38 m east
    // of it along a hallway of look-alike doors; the robot then mapped the office as hallways for
    // 1,000 s). The robot drives on and the belief is not acted on (no turn round for the route,
    // no room entered) for jump_hold_distance, as after a jump.
    const bool side_open = (left && v.open_left) || (right && v.open_right);
    const std::optional<DoorTrack> door_abeam =
        side_open && here ? doors_.abeam(p.odom, dir_robot, left ? 1.0 : -1.0) : std::nullopt;
    if (door_abeam) {
      if (refused_branch_node_ != long(route.next_node)) {  // counted once per node in a row
        refused_branch_node_ = long(route.next_node);
        ++stats_.branch_turns_refused;
      }
      distrust_until_ = std::max(distrust_until_, travel_ + params_.jump_hold_distance);
      char why[160];
      std::snprintf(why, sizeof(why), "a %.2f m door beside the robot, not the branch of node %u: not turning",
                    door_abeam->width, route.next_node);
      state_text_ = why;
    } else if (side_open && here) {
      // A route that turns into the same branch towards the same goal again and again goes round
      // in a circle (a belief that moves back as the robot turns, look-alike junctions): the goal's
      // opening is given up after max_route_attempts such turns, as after as many U-turns.
      if (!mission_.active() &&
          ++branch_turns_[{route.next_node, route.goal_node}] > params_.max_route_attempts) {
        giveUpRouteGoal(route, d);
        return true;
      }
      startTurn(route_bin, p, topo, {});
      state_text_ = "turning into the branch of node " + std::to_string(near) + " towards node " +
                    std::to_string(route.goal_node);
      turnGoal(p, d);
      return true;
    }
  }
  return false;
}

void Coordinator::decideAtEnd(const Perception& p, const TopoView& topo, const HallwayView& v, Decision* d) {
  (void)d;
  const int n = bins_.bins;
  const int left = (bin_ + n / 4) % n, right = (bin_ + 3 * n / 4) % n, back = (bin_ + n / 2) % n;
  std::vector<int> open;
  if (v.end_open_left) open.push_back(left);
  if (v.end_open_right) open.push_back(right);
  char why[160];
  std::snprintf(why, sizeof(why), " (free ahead %.2f m, left %s, right %s, at %.2f %.2f odom)", v.free_ahead,
                v.end_open_left ? "open" : "closed", v.end_open_right ? "open" : "closed", p.odom.x, p.odom.y);
  const bool localized = topo.mode == "localized";
  const bool sure = topo.mode == "frontier" || (localized && topo.confident);
  if (open.empty()) {
    const double dir_robot = normalizeAngle(odomHallwayHeading(topo) - p.odom.theta);
    if (const std::optional<double> way = obliqueWayAtEnd(p, dir_robot, v)) {
      // A wing: its heading is the hallway's from here on, as bin and offset.
      const double map_heading = normalizeAngle(*way + p.odom.theta + (topo.heading_valid ? topo.heading_offset : 0.0));
      const int way_bin = binOf(map_heading);
      axis_offset_ = normalizeAngle(map_heading - binHeading(way_bin));
      ++stats_.turns;
      startTurn(way_bin, p, topo, {});
      char angle[64];
      std::snprintf(angle, sizeof(angle), "hallway end: turning %.0f deg into a hallway at an angle", *way * 180.0 / kPi);
      state_text_ = angle + std::string(why);
      return;
    }
    ++stats_.u_turns;
    startTurn(back, p, topo, {});
    state_text_ = "hallway end: turning round" + std::string(why);
    return;
  }
  int choice = open.front();  // left first (depth-first, one fixed order)
  if (localized && topo.confident && travel_ >= distrust_until_) {
    const RouteStep r = plan(topo.position);
    if (r.found) {
      const int near = graph_.nearestNode(topo.position);
      const int rb = binOf(near >= 0 && uint32_t(near) == r.next_node ? r.next_heading : r.heading);
      if (std::find(open.begin(), open.end(), rb) != open.end()) choice = rb;
    }
  }
  std::vector<int> not_taken;
  if (sure && topo.mode == "frontier" && !mission_.active()) {
    for (int b : open) {
      if (b != choice) not_taken.push_back(b);
    }
  }
  ++stats_.turns;
  startTurn(choice, p, topo, not_taken);
  state_text_ = "hallway end: turning " + std::string(choice == left ? "left" : "right") + why;
}

double Coordinator::topoBearing(double odom_bearing, const TopoView& topo) const {
  return normalizeAngle(odom_bearing + topo.heading_offset - axis_offset_);
}

double Coordinator::trackHallwayAxis(const Perception& p, const TopoView& topo, HallwayView* v) {
  double dir_robot = normalizeAngle(odomHallwayHeading(topo) - p.odom.theta);
  *v = viewHallway(p.points, p.lines, dir_robot, params_.hallway);
  const double half_bin = kPi / bins_.bins;
  if (!v->wall_direction_valid) {
    // No wall along the way followed: the walls of the hallway around the robot, up to half a bin
    // and the wall tolerance from it (every way a wing can run: 30-60 deg to the axes).
    laser_features::HallwayWallsParams walls;
    walls.min_length = params_.hallway.wall_min_length;
    walls.parallel_tolerance = params_.hallway.wall_parallel_tolerance;
    walls.max_width = params_.rules.hallway_max_width + params_.rules.width_tolerance;
    if (const std::optional<double> around = laser_features::hallwayWallsDirection(p.lines, dir_robot, half_bin + walls.parallel_tolerance, walls))
      *v = viewHallway(p.points, p.lines, *around, params_.hallway);
  }
  if (!v->wall_direction_valid) return dir_robot;
  dir_robot = v->wall_direction;
  const double map_heading = normalizeAngle(dir_robot + p.odom.theta + (topo.heading_valid ? topo.heading_offset : 0.0));
  axis_offset_ = normalizeAngle(map_heading - binHeading(bin_));
  // Walls within the wall tolerance of the bin are the building's axis (the heading filter's
  // residue): no offset is kept, the direction is refined from them tick by tick. Past half a bin
  // (and the tolerance, against flicker at exactly half) the nearer bin is the hallway's.
  if (std::abs(axis_offset_) <= params_.hallway.wall_parallel_tolerance) axis_offset_ = 0.0;
  if (std::abs(axis_offset_) > half_bin + 0.5 * params_.hallway.wall_parallel_tolerance) {
    bin_ = binOf(map_heading);
    axis_offset_ = normalizeAngle(map_heading - binHeading(bin_));
  }
  return dir_robot;
}

std::optional<double> Coordinator::obliqueWayAtEnd(const Perception& p, double dir_robot, const HallwayView& v) const {
  // The robot's corridor free for a hallway's width is a way out; its walls within a hallway's
  // width make it a hallway.
  return obliqueHallway(p.points, p.lines, v, dir_robot, params_.hallway, params_.rules.hallway_max_width,
                        params_.rules.hallway_max_width + params_.rules.width_tolerance);
}

bool Coordinator::followStalled(const Perception& p) {
  const Eigen::Vector2d here(p.odom.x, p.odom.y);
  const double diameter = 2.0 * params_.room.planner.robot_radius;
  if (stall_since_ < 0.0 || (here - stall_anchor_).norm() > diameter) {
    stall_anchor_ = here;
    stall_since_ = now_;
    return false;
  }
  if (now_ - stall_since_ < params_.follow_stall_time) return false;
  stall_anchor_ = here;
  stall_since_ = now_;
  return true;
}

void Coordinator::turnGoal(const Perception& p, Decision* d) const {
  d->has_goal = true;
  d->x = p.odom.x;
  d->y = p.odom.y;
  d->theta = turn_odom_heading_;
}

void Coordinator::startTurn(int bin, const Perception& p, const TopoView& topo, std::vector<int> not_taken) {
  // Turns keep the hallway's offset from the axes: a wing's crossings and U-turns are square to it.
  turn_bin_ = bins_.wrap(bin);
  turn_odom_heading_ = normalizeAngle(odomHeadingOfBin(turn_bin_, topo) + axis_offset_);
  pending_branches_ = std::move(not_taken);
  pending_branch_travel_ = -1.0;
  last_goal_ = Eigen::Vector2d(p.odom.x, p.odom.y);
  have_goal_ = true;
  doors_.clear();  // the doors and walls seen so far belong to the hallway being left
  setState(State::Turn, "turning");
}

bool Coordinator::justLeft(const DoorTrack& door) const {
  // Within kLeftDoorsTravel of travel the odometry has not drifted by a door's spacing; twice the
  // tracks' same-door distance, as the door seen again from beside it is seen at a grazing angle.
  return std::any_of(left_doors_.begin(), left_doors_.end(), [&](const std::pair<DoorTrack, double>& left) {
    return travel_ - left.second <= kLeftDoorsTravel &&
           (door.centre_odom - left.first.centre_odom).norm() < 2.0 * params_.doors.same_distance &&
           std::abs(normalizeAngle(door.into_odom - left.first.into_odom)) < 0.5;
  });
}

bool Coordinator::beliefPlausible(const TopoView& topo) {
  // A confident belief that jumps to a node farther along the graph than the robot has travelled
  // since it adopted the last trusted one is not acted on (no room entered, no turn for the route)
  // until it has held for jump_hold_distance of travel: the map builder's belief can lock onto a
  // look-alike place after a U-turn at a hallway end (institute's two dead ends of hall_south).
  // Neighbours on the graph are never a jump (the nearest node changes half-way along an edge).
  const int near = graph_.nearestNode(topo.position);
  if (near < 0) return false;
  if (trusted_node_ >= 0 && near != trusted_node_ && !graph_.adjacent(uint32_t(trusted_node_), uint32_t(near))) {
    const double d = graph_.distance(uint32_t(trusted_node_), uint32_t(near));
    if (d > travel_ - trusted_travel_ + params_.jump_tolerance) {
      distrust_until_ = travel_ + params_.jump_hold_distance;
      ++stats_.belief_jumps;
    }
  }
  if (near != trusted_node_) {
    trusted_node_ = near;
    trusted_travel_ = travel_;
  }
  return travel_ >= distrust_until_;
}

bool Coordinator::mayEnter(const TopoView& topo, const DoorTrack& door) {
  enter_node_ = -1;
  enter_bearing_ = topoBearing(door.into_odom, topo);
  if (mission_.active()) {
    // Only the mission's door, at its node as a confident belief says, on its side.
    if (topo.mode != "localized" || !topo.confident || travel_ < distrust_until_) return false;
    const int n = graph_.nearestNode(topo.position);
    if (n < 0 || uint32_t(n) != mission_.door().node) return false;
    if (std::abs(normalizeAngle(mission_.door().opening.bearing - enter_bearing_)) > 0.5) return false;
    enter_node_ = n;
    enter_bearing_ = mission_.door().opening.bearing;
    return true;
  }
  if (topo.mode == "frontier") return true;  // a door on a new stretch is new: its node is pomdp_topo's current one
  if (topo.mode != "localized" || !topo.confident || travel_ < distrust_until_) return false;
  const int n = graph_.nearestNode(topo.position);
  if (n < 0) return false;
  for (const GraphOpening& o : graph_.unexplored(uint32_t(n))) {
    if (sameOpening(o, enter_bearing_, door.width)) {
      // A known door not explored yet: the records go to that node and that opening.
      enter_node_ = n;
      enter_bearing_ = o.bearing;
      return true;
    }
  }
  return false;
}

bool Coordinator::sameOpening(const GraphOpening& o, double bearing, double width) const {
  // A door beside a junction's branch on the same side is not that branch; a door measured
  // another width is that door (as pomdp_topo's TopologicalMap::differentOpenings).
  if (params_.rules.differentOpenings(o.width, width)) return false;
  return std::abs(normalizeAngle(o.bearing - bearing)) < 0.5;
}

bool Coordinator::exploredAtFrontierNode(const TopoView& topo, const DoorTrack& door) const {
  if (topo.mode != "frontier" || !topo.position.valid || !topo.position.at_node) return false;
  // Only near the node (a door joined to it lies within a door's spacing): a new door on the same
  // side farther on, whose node pomdp_topo has not made yet, is not this one.
  if (int(topo.position.id) != frontier_node_ || travel_ - frontier_node_travel_ > 2.0 * params_.doors.same_distance)
    return false;
  const GraphNode* n = graph_.node(topo.position.id);
  if (n == nullptr) return false;  // a node made for this door, not in the graph received yet
  const double bearing = topoBearing(door.into_odom, topo);
  return std::any_of(n->openings.begin(), n->openings.end(),
                     [&](const GraphOpening& o) { return o.explored && sameOpening(o, bearing, door.width); });
}

void Coordinator::placeCreated(bool ok, int place_id) {
  place_ok_ = ok;
  place_id_ = ok ? place_id : -1;
}

void Coordinator::openingRecorded(bool ok, int node) {
  if (ok && state_ == State::EnterRoom && door_node_ < 0) door_node_ = node;
}

void Coordinator::visitRoom(const Perception& p, Decision* d) {
  mode_ = CoordinatorMode::Metric;
  const Perception q = visit_.inPlace(p);
  visit_.observe(q, state_ == State::ApproachDoor, d);
  switch (state_) {
    case State::ApproachDoor:
      return approachDoor(q, d);
    case State::GoToGoal:
      if (const std::optional<MissionEnd> end = mission_.driveToGoal(q, visit_, now_, now_ - state_since_, motion_, d))
        endMission(end->success, end->why, d);
      return;
    case State::Room:
      return coverRoom(q, d);
    default:
      return leaveRoom(q, d);
  }
}

void Coordinator::approachDoor(const Perception& q, Decision* d) {
  if (!visit_.approachDoor(q, now_ - state_since_, d)) return;
  if (mission_.active()) {
    beginGoToGoal("driving to the mission's goal in place " + std::to_string(place_id_), false);
    return;
  }
  const double shift = visit_.doorRefinement();
  char text[96];
  std::snprintf(text, sizeof(text), "exploring the room (its door refined by %.2f m)", shift);
  setState(State::Room, shift > 0.0 ? text : "exploring the room");
}

void Coordinator::coverRoom(const Perception& q, Decision* d) {
  const RoomVisit::Coverage coverage = visit_.coverRoom(q, now_, now_ - state_since_, d);
  if (coverage == RoomVisit::Coverage::Covering) return;
  if (coverage == RoomVisit::Coverage::TimedOut) ++stats_.rooms_left_early;
  stats_.room_free_area += visit_.explorer().freeArea();
  stats_.peak_room_bytes = std::max(stats_.peak_room_bytes, visit_.explorer().bytes());
  visit_.beginExit();
  setState(State::ExitPath, "leaving the room by its door");
}

void Coordinator::leaveRoom(const Perception& q, Decision* d) {
  if (state_ == State::ExitPath) {
    if (!visit_.followExitPath(q, now_ - state_since_, d)) return;
    setState(State::ExitDoor, "through the door back to the hallway");
    visit_.beginDoorExit(now_);
  }
  const RoomVisit::Exit exit = visit_.exitThroughDoor(q, now_, now_ - state_since_, motion_, d);
  if (exit == RoomVisit::Exit::Passing) return;
  if (exit == RoomVisit::Exit::TryAgain) {
    setState(State::ExitPath, "still inside: leaving the room by its door again (attempt " +
                                  std::to_string(visit_.exitAttempts() + 1) + ")");
    return;
  }
  // Still inside after every attempt: the exploration stops rather than map the room as a hallway;
  // a mission goes on from where the robot is.
  if (exit == RoomVisit::Exit::Stuck && !mission_.active()) {
    finish(false, "could not leave place " + std::to_string(place_id_) + " through its door (" +
                      std::to_string(RoomVisit::kExitAttempts) + " attempts)", d);
    return;
  }
  backOnHallway(exit == RoomVisit::Exit::Back, d);
}

void Coordinator::backOnHallway(bool exact, Decision* d) {
  bin_ = hallway_bin_;
  axis_offset_ = hallway_offset_;
  have_goal_ = false;
  mode_ = CoordinatorMode::Topological;
  left_doors_.erase(std::remove_if(left_doors_.begin(), left_doors_.end(),
                                   [&](const std::pair<DoorTrack, double>& left) {
                                     return travel_ - left.second > kLeftDoorsTravel;
                                   }),
                    left_doors_.end());
  left_doors_.emplace_back(door_, travel_);
  last_turn_travel_ = travel_;
  // The travel in the room is not travel past the route's goal node: a door facing the one just
  // explored across the hallway would be given up at once.
  goal_pass_node_ = -1;
  if (mission_.active()) {
    // A mission leaving a room: back on the hallway, on to the goal's door (nothing to record).
    place_id_ = -1;
    in_room_ = false;
    setState(State::Follow, "mission to place " + std::to_string(mission_.place()) + ": following the hallway");
    return;
  }
  Request rec;
  rec.kind = Request::RecordOpening;
  rec.node = door_node_;
  rec.bearing = door_bearing_map_;
  rec.width = door_.width;
  rec.explored = true;
  rec.place_id = place_id_;
  rec.pose = visit_.doorInPlace();
  d->requests.push_back(rec);
  setState(State::Follow, exact ? "following the hallway" : "following the hallway (the way back was not reached exactly)");
}

RouteStep Coordinator::plan(const GraphPosition& pos) const {
  if (mission_.active()) return graph_.routeTo(pos, mission_.door().node, mission_.door().opening, params_.u_turn_cost);
  return graph_.route(pos, params_.u_turn_cost);
}

bool Coordinator::startMission(int place_id, const Pose2D& goal, std::string* why) {
  auto refuse = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (mission_.active()) return refuse("a mission is running (to place " + std::to_string(mission_.place()) + ")");
  if (!idle()) return refuse("the exploration is running: missions start once it is done");
  if (!mission_.start(place_id, goal, graph_, travel_, now_, why)) return false;
  route_attempts_.clear();
  const std::string to = "mission to place " + std::to_string(place_id);
  if (in_room_ && place_id_ == place_id) {
    beginGoToGoal(to + ": driving to the goal in the room", true);
    mode_ = CoordinatorMode::Metric;
  } else if (in_room_) {
    leaveRoomForMission(to + ": leaving place " + std::to_string(place_id_) + " by its door");
    mode_ = CoordinatorMode::Metric;
  } else {
    have_goal_ = false;
    last_turn_travel_ = travel_ - 3.0;  // the route may turn the robot round at once
    setState(State::Follow, to + ": following the hallway");
    mode_ = CoordinatorMode::Topological;
  }
  return true;
}

void Coordinator::leaveRoomForMission(const std::string& text) {
  // Out of this room by its door first. The hallway heading to leave by: towards the goal's door.
  GraphPosition at_door;
  at_door.valid = true;
  at_door.at_node = true;
  at_door.id = uint32_t(std::max(0, door_node_));
  at_door.heading = binHeading(hallway_bin_);
  const PlaceDoor& goal_door = mission_.door();
  const RouteStep r = graph_.routeTo(at_door, goal_door.node, goal_door.opening, params_.u_turn_cost);
  const int n = bins_.bins;
  if (r.found && door_node_ >= 0 && uint32_t(door_node_) != goal_door.node) {
    const int rb = binOf(r.heading);
    if (rb == (hallway_bin_ + n / 2) % n) {
      visit_.turnExitHeadingRound();
      hallway_bin_ = rb;
    }
  }
  visit_.beginExit();
  setState(State::ExitPath, text);
}

void Coordinator::beginGoToGoal(const std::string& text, bool inside) {
  setState(State::GoToGoal, text);
  mission_.beginGoToGoal(inside, now_);
}

void Coordinator::cancelMission(const std::string& why) {
  if (!mission_.active()) return;
  Decision d;
  endMission(false, why, &d);
  // Its requests (closing a place relocated in) go out with the next update.
  pending_requests_.insert(pending_requests_.end(), d.requests.begin(), d.requests.end());
}

void Coordinator::endMission(bool success, const std::string& why, Decision* d) {
  mission_.end(success, why, travel_);
  // In a room when the place is active and the robot is past the hallway stop (metric states).
  in_room_ = place_id_ >= 0 && (state_ == State::GoToGoal || state_ == State::ApproachDoor ||
                                state_ == State::ExitPath || state_ == State::ExitDoor);
  if (!in_room_ && place_id_ >= 0) {
    d->requests.push_back(Request{Request::ClosePlace});
    place_id_ = -1;
  }
  mode_ = in_room_ ? CoordinatorMode::Metric : CoordinatorMode::Topological;
  setState(State::Idle, std::string(success ? "mission done: " : "mission failed: ") + why);
  d->stop = true;
  d->has_goal = false;
}

void Coordinator::relocationResult(int place_id, bool success, const std::string& verdict) {
  if (state_ != State::Relocate || place_id != place_id_) return;
  mission_.relocationResult(success, verdict);
}

void Coordinator::beginRelocation(const Perception& p, Decision* d) {
  // Stopped past the mission's door (Tomatis et al. 2001, section 3.2): the place's map is
  // matched from here, the robot's pose given by the door as the laser sees it.
  d->stop = true;
  mode_ = CoordinatorMode::Metric;
  hallway_pose_odom_ = p.odom;
  hallway_bin_ = bin_;
  hallway_offset_ = axis_offset_;
  place_id_ = mission_.place();
  door_node_ = int(mission_.door().node);
  mission_.beginRelocation(door_, p.odom, d);
  setState(State::Relocate, "relocating in place " + std::to_string(mission_.place()) + " at its door");
}

void Coordinator::relocate(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  mode_ = CoordinatorMode::Metric;
  const RelocationStep step = mission_.relocate(p, door_, now_, now_ - state_since_, motion_, d);
  switch (step.kind) {
    case RelocationStep::Pending:
      if (!step.text.empty()) state_text_ = step.text;
      return;
    case RelocationStep::Relocated:
      visit_.beginKnownRoom(p, hallway_pose_odom_, odomHeadingOfBin(hallway_bin_, topo) + hallway_offset_,
                            mission_.door().opening, door_.width);
      setState(State::ApproachDoor, "relocated in place " + std::to_string(place_id_) + ": entering");
      return;
    case RelocationStep::AskedAgain:
      setState(State::Relocate, step.text);
      return;
    case RelocationStep::Failed:
    case RelocationStep::GaveUp:
      break;
  }
  // Not the goal's room: the mission fails, or back to the hallway with a uniform belief (global
  // localization) rather than going on lost.
  d->requests.push_back(Request{Request::ClosePlace});
  place_id_ = -1;
  if (step.kind == RelocationStep::GaveUp) {
    endMission(false, step.text, d);
    return;
  }
  Request reset;
  reset.kind = Request::ResetBelief;
  d->requests.push_back(reset);
  mode_ = CoordinatorMode::Topological;
  have_goal_ = false;
  setState(State::Follow, step.text);
}

void Coordinator::finish(bool success, const std::string& why, Decision* d) {
  mode_ = CoordinatorMode::Done;
  setState(State::Done, success ? "exploration complete" : "exploration stopped: " + why);
  std::ostringstream s;
  s << (success ? "exploration complete: " : "exploration incomplete: ") << why << "; " << graph_.placeCount()
    << " places (" << stats_.places << " entered by this run), " << graph_.nodes().size() << " nodes, " << graph_.edges().size() << " edges, "
    << graph_.exploredCount() << " openings explored, " << graph_.unexploredCount() << " unexplored, "
    << stats_.travel << " m travelled";
  // Given-up openings count as explored: rooms behind them may be missing (large_floor: 26 given
  // up, 58 rooms never seen).
  if (stats_.openings_given_up > 0)
    s << "; " << stats_.openings_given_up << " opening(s) given up unreached (rooms behind them may be missing)";
  Request save;
  save.kind = Request::SaveMaps;
  d->requests.push_back(save);
  Request fin;
  fin.kind = Request::Finish;
  fin.success = success;
  fin.text = s.str();
  d->requests.push_back(fin);
  d->stop = true;
  d->has_goal = false;
}

}  // namespace exploration
