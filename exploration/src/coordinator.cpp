#include "exploration/coordinator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace exploration {

using laser_features::inverse;
using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::transformPoint;

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
  if (!(p.follow.lookahead > 0.3)) return fail("lookahead must be > 0.3 m");
  if (!(p.follow.end_distance > 0.5)) return fail("end_distance must be > 0.5 m");
  if (!p.rules.valid(error)) return false;
  if (!(p.doors.min_confidence >= 0.0 && p.doors.min_confidence <= 1.0)) return fail("door_min_confidence must be in [0, 1]");
  if (!(p.doors.max_lateral > 0.0 && p.doors.side_angle > 0.0 && p.doors.pass_distance >= 0.0 && p.doors.same_distance > 0.0 &&
        p.doors.wall_tolerance > 0.0 && p.doors.wall_memory >= 0.0))
    return fail("door_max_lateral, door_side_angle, door_same_distance and door_wall_tolerance must be > 0, "
                "door_pass_distance and door_wall_memory >= 0");
  if (!RoomVisit::validate(p.room_visit, error)) return false;
  if (!(p.settle_time >= 0.0 && p.max_time >= 0.0)) return fail("settle_time and max_time must be >= 0");
  if (p.route.max_route_attempts < 1) return fail("max_route_attempts must be >= 1");
  if (!(p.route.goal_pass_distance > 0.0)) return fail("goal_pass_distance must be > 0");
  if (!(p.route.jump_tolerance >= 0.0 && p.route.jump_hold_distance >= 0.0))
    return fail("jump_tolerance and jump_hold_distance must be >= 0");
  if (!(p.branch_record_distance >= 0.0 && p.route.u_turn_cost >= 0.0 && p.follow.goal_refresh_distance > 0.0))
    return fail("branch_record_distance and u_turn_cost must be >= 0, goal_refresh_distance > 0");
  if (!MissionRunner::validate(p.mission, error)) return false;
  if (!(p.follow.stall_time > 0.0)) return fail("follow_stall_time must be > 0");
  return RoomExplorer::validate(p.room, error);
}

Coordinator::Coordinator(const CoordinatorParams& params)
    : params_(params),
      follower_(params.follow, params.hallway, params.rules, params.room.planner),
      door_entry_(params.doors, params.rules),
      route_(params.route, params.rules),
      visit_(params.room_visit, params.room, params.rules, params.doors),
      mission_(params.mission),
      doors_(params.doors, params.rules) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("exploration coordinator: " + why);
  params_.hallway = follower_.viewParams();  // with its derived sizes
}

CoordinatorStats Coordinator::stats() const {
  CoordinatorStats s = stats_;
  const RouteStats& route = route_.stats();
  s.openings_given_up = route.openings_given_up;
  s.openings_set_aside = route.openings_set_aside;
  s.belief_jumps = route.belief_jumps;
  s.branch_turns_refused = route.branch_turns_refused;
  return s;
}

void Coordinator::setState(State s, const std::string& text) {
  state_ = s;
  state_since_ = now_;
  state_text_ = text;
  follower_.restart();
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
  door_entry_.observe(topo, travel_);

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
    follower_.faceRobotsBin(p, topo);
    if (!params_.explore) {
      setState(State::Idle, "waiting for a mission");
      return;
    }
    const int along = follower_.startBin(p, topo);
    if (topo.mode == "frontier" && follower_.openBehind(along, p, topo)) {
      // The robot starts mid-hallway: the way behind it is an unexplored opening of the start node.
      Request r;
      r.kind = Request::RecordOpening;
      r.bearing = follower_.binHeading(along + follower_.headingBins().bins / 2);
      d->requests.push_back(r);
    }
    if (along != follower_.bin()) startTurn(along, topo, {});
    else setState(State::Follow, "following the hallway");
  }
}

void Coordinator::turn(const Perception& p, bool motion_reached, bool motion_blocked, Decision* d) {
  // Turn on the spot where the robot is now: a position fixed when the turn was decided lies
  // behind the robot once it has braked, and the controller would turn round to reach it.
  turnGoal(p, d);
  const double err = std::abs(normalizeAngle(turn_odom_heading_ - p.odom.theta));
  if ((motion_reached && err < 0.15) || err < 0.05 || (motion_blocked && err < 0.3)) {
    follower_.setBin(turn_bin_);
    pending_branch_travel_ = travel_;
    route_.turned(travel_);
    follower_.forgetGoal();
    setState(State::Follow, "following the hallway");
  }
}

void Coordinator::stopForDoor(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  mode_ = CoordinatorMode::Switching;
  if (now_ - state_since_ < params_.settle_time) return;
  if (mission_.active()) return beginRelocation(p, d);
  if (entering_.node < 0 && topo.mode != "frontier") {
    // Stopped for a door on a new stretch, and pomdp_topo has since made its node and taken it
    // for a known one: a loop hypothesis (the check merges the node, the door explored, or
    // rejects it, its opening unexplored and come back to), or a loop closed in the same scan
    // (explore_restart: room_east mapped twice). Entered only as a known unexplored door
    // (mayEnter); else on along the hallway.
    const std::optional<EntryOpening> known = mayEnter(topo, door_);
    if (!known) {
      mode_ = CoordinatorMode::Topological;
      ++stats_.doors_passed;
      setState(State::Follow, topo.mode == "loop_check" ? "door passed: pomdp_topo checks whether it is a known one"
                                                        : "door passed: it is a known one (pomdp_topo closed a loop at it)");
      return;
    }
    entering_ = *known;
  }
  if (entering_.node < 0 &&
      door_entry_.exploredAtFrontierNode(topo, graph_, door_, follower_.topoBearing(door_.into_odom, topo), travel_)) {
    // On a new stretch pomdp_topo took the door for one its current node has, explored: a door
    // recorded at a junction a metre off its centre, seen again from it (large_floor: room_7_14,
    // entered from the junction at a T, entered again from a stretch leaving it 5,600 s later).
    mode_ = CoordinatorMode::Topological;
    ++stats_.doors_passed;
    setState(State::Follow, "door passed: the node's explored one");
    return;
  }
  // The door's node exists now (passed); the topological map stands still from here on.
  mode_ = CoordinatorMode::Metric;
  hallway_pose_odom_ = p.odom;
  entry_hallway_ = follower_.direction();
  door_bearing_map_ = entering_.bearing;
  Request rec;
  rec.kind = Request::RecordOpening;
  rec.node = entering_.node;
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
  visit_.beginNewRoom(p.odom, door_, follower_.odomHeading(entry_hallway_, topo));
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
  const double dir_robot = follower_.track(p, topo, &v);
  if (follower_.stalled(p)) blocked = true;
  const bool localized = topo.mode == "localized";
  const bool sure = (topo.mode == "frontier") ||
                    (localized && topo.confident && route_.beliefPlausible(graph_, topo.position, travel_));
  state_text_ = sure ? (localized ? "following the hallway on the known map" : "following a new hallway")
                     : "following the hallway until the belief is confident";

  recordWaysNotTaken(sure, d);
  RouteStep route;
  if (localized && sure && followRoute(p, topo, &route, d)) return;
  if (enterPassedDoor(p, topo, dir_robot, v, d)) return;
  if (turnIntoRouteBranch(p, topo, route, sure, dir_robot, v, d)) return;

  if (follower_.intoOpenArea(p, dir_robot, v)) {
    decideInOpenArea(topo);
    if (state_ == State::Turn) {
      turnGoal(p, d);
      return;
    }
  }

  const std::optional<double> lane = follower_.laneAround(p, dir_robot, v, blocked);
  if (lane) state_text_ = "passing an obstacle in the hallway";
  if ((follower_.atEnd(v) && !lane) || blocked) {
    decideAtEnd(p, topo, v, d);
    if (blocked) state_text_ = "motion blocked: " + state_text_;
    if (state_ == State::Turn) {
      turnGoal(p, d);
      return;
    }
  }

  const Eigen::Vector2d goal = follower_.goal(p, dir_robot, v, lane);
  d->has_goal = true;
  d->x = goal.x();
  d->y = goal.y();
}

void Coordinator::recordWaysNotTaken(bool sure, Decision* d) {
  // The ways not taken at the last turn, once the map builder has the turn's node.
  if (pending_branch_travel_ >= 0.0 && travel_ - pending_branch_travel_ >= params_.branch_record_distance) {
    if (sure) {
      for (int b : pending_branches_) {
        Request r;
        r.kind = Request::RecordOpening;
        r.bearing = follower_.binHeading(b);
        d->requests.push_back(r);
      }
    }
    pending_branches_.clear();
    pending_branch_travel_ = -1.0;
  }
}

bool Coordinator::followRoute(const Perception& p, const TopoView& topo, RouteStep* out, Decision* d) {
  RouteStep& route = *out;
  if (!mission_.active() && graph_.nodes().size() > 1 && route_.openingsLeft(graph_) == 0 && pending_branches_.empty()) {
    if (const size_t retry = route_.retrySetAside()) {
      // The openings the route kept missing, once more, from a belief found afresh (a wrong one is
      // the likeliest reason for a miss).
      Request reset;
      reset.kind = Request::ResetBelief;
      d->requests.push_back(reset);
      state_text_ = "every other opening explored: trying the " + std::to_string(retry) +
                    " set aside once more, the belief reset";
      return true;
    }
    // Complete only if nothing was given up: an opening given up unreached counts as explored,
    // and rooms behind it may be missing; a room left at its time limit is not all mapped.
    const int given_up = route_.stats().openings_given_up;
    if (given_up > 0 || stats_.rooms_left_early > 0) {
      finish(false, "no unexplored opening is left, but " + std::to_string(given_up) +
                        " opening(s) were given up unreached and " + std::to_string(stats_.rooms_left_early) +
                        " room(s) left at their time limit", d);
    } else {
      finish(true, "no unexplored opening is left", d);
    }
    return true;
  }
  route = route_.plan(graph_, topo.position, missionDoor());
  if (mission_.active()) {
    if (!route.found) {
      endMission(false, "no route on the topological map to the door of place " + std::to_string(mission_.place()), d);
      return true;
    }
    mission_.updateDistanceLeft(route);
  }
  const RouteContext at{graph_, topo, travel_, mission_.active()};
  return actOnRoute(route_.alongRoute(at, route, follower_.binHeading(follower_.bin())), route, p, topo, d);
}

bool Coordinator::actOnRoute(const RouteAction& action, const RouteStep& route, const Perception& p, const TopoView& topo,
                             Decision* d) {
  switch (action.kind) {
    case RouteAction::None:
      if (!action.text.empty()) state_text_ = action.text;
      return false;
    case RouteAction::SetAside:
      state_text_ = action.text;
      return true;
    case RouteAction::GiveUp:
      d->requests.push_back(action.record);
      state_text_ = action.text;
      return true;
    case RouteAction::MissedDoor:
      missedMissionDoor(route, d);
      return true;
    case RouteAction::TurnRound:
      ++stats_.u_turns;
      startTurn(follower_.bin() + follower_.headingBins().bins / 2, topo, {});
      break;
    case RouteAction::TurnIntoBranch:
      startTurn(follower_.binOf(route.next_heading), topo, {});
      break;
  }
  state_text_ = action.text;
  turnGoal(p, d);
  return true;
}

void Coordinator::missedMissionDoor(const RouteStep& route, Decision* d) {
  const std::string why = "the door of place " + std::to_string(mission_.place()) + " was not found at node " +
                          std::to_string(route.goal_node) + " after " + std::to_string(params_.route.max_route_attempts) +
                          " turns towards it";
  // A confident belief that keeps missing the door is likely wrong (a look-alike stretch): global
  // localization again (a uniform belief) rather than giving up or going on lost.
  if (mission_.missDoor()) {
    endMission(false, why + ", " + std::to_string(mission_.doorMisses()) + " times", d);
    return;
  }
  route_.clearAttempts();
  Request reset;
  reset.kind = Request::ResetBelief;
  d->requests.push_back(reset);
  state_text_ = why + ": the belief is reset";
}

bool Coordinator::enterPassedDoor(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v,
                                  Decision* d) {
  // Doors: entered once passed, if new (frontier) or known and unexplored, and the belief is sure.
  const HallwayDoors::Walls walls = doors_.track(p.odom, p.openings, dir_robot, v, travel_);
  DoorTrack door;
  if (doors_.passed(p.odom, dir_robot, walls, &door)) {
    if (door_entry_.justLeft(door, travel_)) {
      ++stats_.doors_passed;
      state_text_ = "door passed: the one just left";
    } else if (const std::optional<EntryOpening> entry = mayEnter(topo, door)) {
      entering_ = *entry;
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
  // A side branch the route takes at the node the robot is at now: the side it leaves to must be
  // open (the branch's mouth is beside the robot); a door tracked beside the robot there is no branch.
  if (!sure) return false;
  const int route_bin = follower_.binOf(route.next_heading);
  const int n = follower_.headingBins().bins, bin = follower_.bin();
  const bool left = route_bin == (bin + n / 4) % n, right = route_bin == (bin + 3 * n / 4) % n;
  const bool side_open = (left && v.open_left) || (right && v.open_right);
  const std::optional<DoorTrack> door_abeam =
      side_open ? doors_.abeam(p.odom, dir_robot, left ? 1.0 : -1.0) : std::nullopt;
  const RouteContext at{graph_, topo, travel_, mission_.active()};
  return actOnRoute(route_.atBranch(at, route, side_open, door_abeam), route, p, topo, d);
}

void Coordinator::decideAtEnd(const Perception& p, const TopoView& topo, const HallwayView& v, Decision* d) {
  (void)d;
  const int n = follower_.headingBins().bins, bin = follower_.bin();
  const int left = (bin + n / 4) % n, right = (bin + 3 * n / 4) % n, back = (bin + n / 2) % n;
  std::vector<int> open;
  if (v.end_open_left) open.push_back(left);
  if (v.end_open_right) open.push_back(right);
  char why[160];
  std::snprintf(why, sizeof(why), " (free ahead %.2f m, left %s, right %s, at %.2f %.2f odom)", v.free_ahead,
                v.end_open_left ? "open" : "closed", v.end_open_right ? "open" : "closed", p.odom.x, p.odom.y);
  const bool localized = topo.mode == "localized";
  const bool sure = topo.mode == "frontier" || (localized && topo.confident);
  if (open.empty()) {
    if (const std::optional<double> way = follower_.obliqueWayAtEnd(p, topo, v)) {
      ++stats_.turns;
      startTurn(follower_.takeWay(*way, p, topo), topo, {});
      char angle[64];
      std::snprintf(angle, sizeof(angle), "hallway end: turning %.0f deg into a hallway at an angle", *way * 180.0 / kPi);
      state_text_ = angle + std::string(why);
      return;
    }
    ++stats_.u_turns;
    startTurn(back, topo, {});
    state_text_ = "hallway end: turning round" + std::string(why);
    return;
  }
  int choice = open.front();  // left first (depth-first, one fixed order)
  if (beliefTrusted(topo)) {
    const RouteStep r = route_.plan(graph_, topo.position, missionDoor());
    if (r.found) {
      const int near = graph_.nearestNode(topo.position);
      const int rb = follower_.binOf(near >= 0 && uint32_t(near) == r.next_node ? r.next_heading : r.heading);
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
  startTurn(choice, topo, not_taken);
  state_text_ = "hallway end: turning " + std::string(choice == left ? "left" : "right") + why;
}

void Coordinator::decideInOpenArea(const TopoView& topo) {
  // The robot keeps to an open area's walls: the doors and the hallways leaving it are along them,
  // and its middle is no hallway to follow (the sector ahead sees nothing of them from there). It
  // turns along the wall the hallway came in by (left first, as at a hallway's end, or the route's
  // way), the other way along it a way not taken; a route across the area is followed across.
  const int n = follower_.headingBins().bins, bin = follower_.bin();
  const int left = (bin + n / 4) % n, right = (bin + 3 * n / 4) % n;
  int choice = left;
  if (beliefTrusted(topo) || mission_.active()) {
    const RouteStep r = route_.plan(graph_, topo.position, missionDoor());
    if (r.found) {
      const int near = graph_.nearestNode(topo.position);
      const int rb = follower_.binOf(near >= 0 && uint32_t(near) == r.next_node ? r.next_heading : r.heading);
      if (rb != left && rb != right) return;
      choice = rb;
    }
  }
  std::vector<int> not_taken;
  if (topo.mode == "frontier" && !mission_.active()) not_taken.push_back(choice == left ? right : left);
  ++stats_.turns;
  startTurn(choice, topo, not_taken);
  state_text_ = std::string("an open area: turning ") + (choice == left ? "left" : "right") + " along its wall";
}

void Coordinator::turnGoal(const Perception& p, Decision* d) const {
  d->has_goal = true;
  d->x = p.odom.x;
  d->y = p.odom.y;
  d->theta = turn_odom_heading_;
}

void Coordinator::startTurn(int bin, const TopoView& topo, std::vector<int> not_taken) {
  // Turns keep the hallway's offset from the axes: a wing's crossings and U-turns are square to it.
  turn_bin_ = follower_.headingBins().wrap(bin);
  turn_odom_heading_ = normalizeAngle(follower_.odomHeadingAtOffset(turn_bin_, topo));
  pending_branches_ = std::move(not_taken);
  pending_branch_travel_ = -1.0;
  doors_.clear();  // the doors and walls seen so far belong to the hallway being left
  setState(State::Turn, "turning");
}

bool Coordinator::beliefTrusted(const TopoView& topo) const {
  return route_.beliefTrusted(topo, travel_);
}

std::optional<EntryOpening> Coordinator::mayEnter(const TopoView& topo, const DoorTrack& door) const {
  return door_entry_.mayEnter(topo, graph_, door, follower_.topoBearing(door.into_odom, topo), beliefTrusted(topo),
                              missionDoor());
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
  follower_.setDirection(entry_hallway_);
  follower_.forgetGoal();
  mode_ = CoordinatorMode::Topological;
  door_entry_.leftBy(door_, travel_);
  route_.backOnHallway(travel_);
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

bool Coordinator::startMission(int place_id, const Pose2D& goal, std::string* why) {
  auto refuse = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (mission_.active()) return refuse("a mission is running (to place " + std::to_string(mission_.place()) + ")");
  if (!idle()) return refuse("the exploration is running: missions start once it is done");
  if (!mission_.start(place_id, goal, graph_, travel_, now_, why)) return false;
  route_.clearAttempts();
  const std::string to = "mission to place " + std::to_string(place_id);
  if (in_room_ && place_id_ == place_id) {
    beginGoToGoal(to + ": driving to the goal in the room", true);
    mode_ = CoordinatorMode::Metric;
  } else if (in_room_) {
    leaveRoomForMission(to + ": leaving place " + std::to_string(place_id_) + " by its door");
    mode_ = CoordinatorMode::Metric;
  } else {
    follower_.forgetGoal();
    route_.allowTurnRound(travel_);
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
  at_door.heading = follower_.binHeading(entry_hallway_.bin);
  const PlaceDoor& goal_door = mission_.door();
  const RouteStep r = graph_.routeTo(at_door, goal_door.node, goal_door.opening, params_.route.u_turn_cost);
  const int n = follower_.headingBins().bins;
  if (r.found && door_node_ >= 0 && uint32_t(door_node_) != goal_door.node) {
    const int rb = follower_.binOf(r.heading);
    if (rb == (entry_hallway_.bin + n / 2) % n) {
      visit_.turnExitHeadingRound();
      entry_hallway_.bin = rb;
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
  entry_hallway_ = follower_.direction();
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
      visit_.beginKnownRoom(p, hallway_pose_odom_, follower_.odomHeading(entry_hallway_, topo),
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
  follower_.forgetGoal();
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
  const int given_up = route_.stats().openings_given_up;
  if (given_up > 0) s << "; " << given_up << " opening(s) given up unreached (rooms behind them may be missing)";
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
