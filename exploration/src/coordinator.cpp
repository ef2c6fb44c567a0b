#include "exploration/coordinator.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace exploration {

using laser_features::Pose2D;

const char* toString(CoordinatorMode mode) {
  switch (mode) {
    case CoordinatorMode::Topological: return "TOPOLOGICAL";
    case CoordinatorMode::Metric: return "METRIC";
    case CoordinatorMode::Switching: return "SWITCHING";
    case CoordinatorMode::Done: return "DONE";
  }
  return "?";
}

Coordinator::Coordinator(const CoordinatorParams& params)
    : params_(params),
      hallway_(params.follow, params.hallway, params.rules, params.room.planner, params.doors, params.route,
               params.branch_record_distance),
      room_(params.room_visit, params.room, params.rules, params.doors),
      mission_(params.mission),
      progress_(params.route.max_route_attempts) {
  std::string why;
  if (!params.valid(&why)) throw std::invalid_argument("exploration coordinator: " + why);
  params_.hallway = hallway_.viewParams();  // with its derived sizes
}

CoordinatorStats Coordinator::stats() const {
  CoordinatorStats s = stats_;
  const HallwayStats& hallway = hallway_.stats();
  s.doors_passed = hallway.doors_passed;
  s.mapped_room_doors = hallway.mapped_room_doors;
  s.turns = hallway.turns;
  s.u_turns = hallway.u_turns;
  const RouteStats& route = hallway_.routeStats();
  s.openings_given_up = route.openings_given_up;
  s.openings_set_aside = route.openings_set_aside;
  s.belief_jumps = route.belief_jumps;
  s.branch_turns_refused = route.branch_turns_refused;
  const RoomSequence::Stats& rooms = room_.stats();
  s.places += rooms.inner_rooms;
  s.rooms_left_early = rooms.rooms_left_early;
  s.inner_rooms = rooms.inner_rooms;
  s.inner_doors_left = rooms.inner_doors_left;
  s.inner_doors_given_up = room_.suite().doorsGivenUp();
  s.room_free_area = rooms.room_free_area;
  s.peak_room_bytes = rooms.peak_room_bytes;
  return s;
}

void Coordinator::setState(State s, const std::string& text) {
  state_ = s;
  state_since_ = now_;
  state_text_ = text;
  hallway_.restart();
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
    if (step < 1.0 && (state_ == State::Follow || state_ == State::Turn)) hallway_travel_ += step;
  }
  last_odom_ = p.odom;
  have_last_odom_ = true;
  stats_.travel = travel_;
  hallway_.observe(topo, travel_);

  if (!idle() && !mission_.active() && params_.max_time > 0.0 && now_ - start_time_ > params_.max_time) {
    finish(false, "time limit reached before the exploration was complete", &d);
  }
  if (!idle() && !mission_.active()) stalled(topo, &d);
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
    case State::Room:
    case State::GoToGoal:
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
  if (topo.valid && topo.heading_valid && topo.mode != TopoMode::Unknown) {
    hallway_.faceRobotsBin(p, topo);
    if (!params_.explore) {
      setState(State::Idle, "waiting for a mission");
      return;
    }
    if (hallway_.setOff(p, topo, d)) setState(State::Turn, "turning");
    else setState(State::Follow, "following the hallway");
  }
}

void Coordinator::turn(const Perception& p, bool motion_reached, bool motion_blocked, Decision* d) {
  if (hallway_.turn(p, motion_reached, motion_blocked, travel_, d)) setState(State::Follow, "following the hallway");
}

void Coordinator::stopForDoor(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  mode_ = CoordinatorMode::Switching;
  if (now_ - state_since_ < params_.settle_time) return;
  if (mission_.active()) return beginRelocation(p, d);
  std::string why_passed;
  const std::optional<EntryOpening> entering = hallway_.enterAfterStop(topo, hallwayContext(), &why_passed);
  if (!entering) {
    mode_ = CoordinatorMode::Topological;
    setState(State::Follow, why_passed);
    return;
  }
  // The topological map stands still from here on. A new door has no node yet on a new stretch
  // (the robot stopped before passing it): pomdp_topo makes it where the robot stands.
  mode_ = CoordinatorMode::Metric;
  hallway_pose_odom_ = p.odom;
  entry_hallway_ = hallway_.direction();
  door_bearing_map_ = entering->bearing;
  Request rec;
  rec.kind = Request::RecordOpening;
  rec.node = entering->node;
  rec.bearing = door_bearing_map_;
  rec.width = hallway_.door().width;
  rec.beside_robot = true;
  d->requests.push_back(rec);
  Request create;
  create.kind = Request::CreatePlace;
  d->requests.push_back(create);
  places_.place_ok = false;
  door_node_ = -1;
  setState(State::EnterRoom, "creating a place for the room");
}

void Coordinator::enterRoom(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  if (!places_.place_ok) {
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
  room_.beginNewRoom(p.odom, hallway_.door(), hallway_.odomHeading(entry_hallway_, topo), places_.place_id, now_);
  // The place's origin is the robot's pose (it stands still since it stopped in the hallway).
  place_origin_map_.reset();
  if (topo.heading_valid) place_origin_map_ = laser_features::compose(topo.map_from_odom, p.odom);
  Request add;
  add.kind = Request::AddDoor;
  add.door_id = std::max(0, door_node_);
  add.place_id = places_.place_id;
  add.pose = room_.host().doorInPlace();
  d->requests.push_back(add);
  ++stats_.places;
  ++stats_.doors_entered;
  setState(State::Room, room_.text());
}

void Coordinator::follow(const Perception& p, const TopoView& topo, bool blocked, Decision* d) {
  mode_ = CoordinatorMode::Topological;
  const HallwayStep step = hallway_.follow(p, topo, blocked, hallwayContext(), d);
  // A mission's distance left: along the route planned this tick.
  if (mission_.active() && step.route.found) mission_.updateDistanceLeft(step.route);
  switch (step.kind) {
    case HallwayStep::Following:
      state_text_ = step.text;
      return;
    case HallwayStep::Turning:
      return setState(State::Turn, step.text);
    case HallwayStep::StopForDoor:
      return setState(State::StopForDoor, step.text);
    case HallwayStep::Complete:
      return noOpeningLeft(d);
    case HallwayStep::NoRoute:
      return endMission(false,
                        "no route on the topological map to the door of place " + std::to_string(mission_.place()), d);
    case HallwayStep::MissedDoor:
      return missedMissionDoor(step.route, d);
  }
}

void Coordinator::noOpeningLeft(Decision* d) {
  // Complete only if nothing was given up: an opening given up unreached counts as explored,
  // and rooms behind it may be missing; a room left at its time limit is not all mapped.
  const int given_up = hallway_.routeStats().openings_given_up, inner_given_up = room_.suite().doorsGivenUp();
  const int left_early = room_.stats().rooms_left_early;
  if (given_up > 0 || left_early > 0 || inner_given_up > 0) {
    finish(false, "no unexplored opening is left, but " + std::to_string(given_up) +
                      " opening(s) were given up unreached, " + std::to_string(inner_given_up) +
                      " door(s) into rooms behind rooms given up and " + std::to_string(left_early) +
                      " room(s) left at their time limit", d);
  } else {
    finish(true, "no unexplored opening is left", d);
  }
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
  hallway_.clearRouteAttempts();
  Request reset;
  reset.kind = Request::ResetBelief;
  d->requests.push_back(reset);
  state_text_ = why + ": the belief is reset";
}

void Coordinator::placeCreated(bool ok, int place_id) {
  places_.place_ok = ok;
  places_.place_id = ok ? place_id : -1;
}

void Coordinator::openingRecorded(bool ok, int node) {
  if (ok && state_ == State::EnterRoom && door_node_ < 0) door_node_ = node;
}

void Coordinator::visitRoom(const Perception& p, Decision* d) {
  mode_ = CoordinatorMode::Metric;
  if (state_ == State::GoToGoal) {
    const Perception q = room_.observe(p, false, d);
    if (const std::optional<MissionEnd> end =
            mission_.driveToGoal(q, room_.host(), now_, now_ - state_since_, motion_, d))
      endMission(end->success, end->why, d);
    return;
  }
  switch (room_.step(p, now_, motion_, mission_.active(), travel_, &places_, d)) {
    case RoomSequence::Outcome::Inside:
      return;
    case RoomSequence::Outcome::AtDoor:
      return beginGoToGoal("driving to the mission's goal in place " + std::to_string(places_.place_id), false);
    case RoomSequence::Outcome::Stuck:
      return mission_.active() ? endMission(false, room_.why(), d) : finish(false, room_.why(), d);
    case RoomSequence::Outcome::Out:
      return backOnHallway(true, d);
    case RoomSequence::Outcome::OutInexact:
      return backOnHallway(false, d);
  }
}

void Coordinator::backOnHallway(bool exact, Decision* d) {
  // A mission's visit does not cover the room: no other door of it was looked for.
  // The room's other doors, and those of the rooms behind it (a connecting room's own hallway door).
  std::vector<DoorTrack> others;
  if (!mission_.active()) {
    others = room_.host().otherDoorsOdom();
    const std::vector<DoorTrack>& inner = room_.suite().innerRoomDoorsOdom();
    others.insert(others.end(), inner.begin(), inner.end());
    if (place_origin_map_ && places_.place_id >= 0) {
      std::vector<Pose2D> doors = room_.host().otherDoorsInPlace();
      doors.push_back(room_.host().doorInPlace());
      hallway_.roomMapped(places_.place_id, *place_origin_map_, doors);
    }
  }
  place_origin_map_.reset();
  hallway_.backFromRoom(entry_hallway_, room_.host().doorOdom(), others, travel_, room_.host().odometryDrift());
  mode_ = CoordinatorMode::Topological;
  if (mission_.active()) {
    // A mission leaving a room: back on the hallway, on to the goal's door (nothing to record).
    places_.place_id = -1;
    in_room_ = false;
    setState(State::Follow, "mission to place " + std::to_string(mission_.place()) + ": following the hallway");
    return;
  }
  Request rec;
  rec.kind = Request::RecordOpening;
  rec.node = door_node_;
  rec.bearing = door_bearing_map_;
  rec.width = hallway_.door().width;
  rec.explored = true;
  rec.place_id = places_.place_id;
  rec.pose = room_.host().doorInPlace();
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
  hallway_.clearRouteAttempts();
  const std::string to = "mission to place " + std::to_string(place_id);
  if (in_room_ && places_.place_id == place_id) {
    beginGoToGoal(to + ": driving to the goal in the room", true);
    mode_ = CoordinatorMode::Metric;
  } else if (in_room_) {
    leaveRoomForMission(to + ": leaving place " + std::to_string(places_.place_id) + " by its door");
    mode_ = CoordinatorMode::Metric;
  } else {
    hallway_.beginMission(travel_);
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
  at_door.heading = hallway_.headingBins().heading(entry_hallway_.bin);
  const PlaceDoor& goal_door = mission_.door();
  const RouteStep r = graph_.routeTo(at_door, goal_door.node, goal_door.opening, params_.route.u_turn_cost);
  const int n = hallway_.headingBins().bins;
  if (r.found && door_node_ >= 0 && uint32_t(door_node_) != goal_door.node) {
    const int rb = hallway_.headingBins().bin(r.heading);
    if (rb == (entry_hallway_.bin + n / 2) % n) {
      room_.host().turnExitHeadingRound();
      entry_hallway_.bin = rb;
    }
  }
  room_.beginExit(text, now_);
  setState(State::Room, text);
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
  in_room_ = places_.place_id >= 0 &&
             (state_ == State::GoToGoal || (state_ == State::Room && room_.atEntryDoor()));
  if (!in_room_ && places_.place_id >= 0) {
    d->requests.push_back(Request{Request::ClosePlace});
    places_.place_id = -1;
  }
  mode_ = in_room_ ? CoordinatorMode::Metric : CoordinatorMode::Topological;
  setState(State::Idle, std::string(success ? "mission done: " : "mission failed: ") + why);
  d->stop = true;
  d->has_goal = false;
}

void Coordinator::relocationResult(int place_id, bool success, const std::string& verdict) {
  if (state_ != State::Relocate || place_id != places_.place_id) return;
  mission_.relocationResult(success, verdict);
}

void Coordinator::beginRelocation(const Perception& p, Decision* d) {
  // Stopped past the mission's door (Tomatis et al. 2001, section 3.2): the place's map is
  // matched from here, the robot's pose given by the door as the laser sees it.
  d->stop = true;
  mode_ = CoordinatorMode::Metric;
  hallway_pose_odom_ = p.odom;
  entry_hallway_ = hallway_.direction();
  places_.place_id = mission_.place();
  door_node_ = int(mission_.door().node);
  mission_.beginRelocation(hallway_.door(), p.odom, d);
  setState(State::Relocate, "relocating in place " + std::to_string(mission_.place()) + " at its door");
}

void Coordinator::relocate(const Perception& p, const TopoView& topo, Decision* d) {
  d->stop = true;
  mode_ = CoordinatorMode::Metric;
  const RelocationStep step = mission_.relocate(p, hallway_.door(), now_, now_ - state_since_, motion_, d);
  switch (step.kind) {
    case RelocationStep::Pending:
      if (!step.text.empty()) state_text_ = step.text;
      return;
    case RelocationStep::Relocated:
      room_.beginKnownRoom(p, hallway_pose_odom_, hallway_.odomHeading(entry_hallway_, topo),
                           mission_.door().opening, hallway_.door().width, places_.place_id, now_);
      setState(State::Room, room_.text());
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
  places_.place_id = -1;
  if (step.kind == RelocationStep::GaveUp) {
    endMission(false, step.text, d);
    return;
  }
  Request reset;
  reset.kind = Request::ResetBelief;
  d->requests.push_back(reset);
  mode_ = CoordinatorMode::Topological;
  hallway_.forgetGoal();
  setState(State::Follow, step.text);
}

bool Coordinator::stalled(const TopoView& topo, Decision* d) {
  if (state_ != State::Follow && state_ != State::Turn) return false;
  if (!progress_.stalled(hallway_travel_, topo.mode == TopoMode::Frontier, hallway_.routeStats().openings_given_up))
    return false;
  finish(false, progress_.why(), d);
  return true;
}

void Coordinator::finish(bool success, const std::string& why, Decision* d) {
  mode_ = CoordinatorMode::Done;
  setState(State::Done, success ? "exploration complete" : "exploration stopped: " + why);
  std::ostringstream s;
  s << (success ? "exploration complete: " : "exploration incomplete: ") << why << "; " << graph_.placeCount()
    << " places (" << stats().places << " entered by this run), " << graph_.nodes().size() << " nodes, " << graph_.edges().size() << " edges, "
    << graph_.exploredCount() << " openings explored, " << graph_.unexploredCount() << " unexplored, "
    << stats_.travel << " m travelled";
  // Given-up openings count as explored: rooms behind them may be missing (large_floor: 26 given
  // up, 58 rooms never seen).
  const int given_up = hallway_.routeStats().openings_given_up;
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
