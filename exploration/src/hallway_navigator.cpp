#include "exploration/hallway_navigator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>

namespace exploration {

using laser_features::Pose2D;
using laser_features::inverse;
using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::transformPoint;

HallwayNavigator::HallwayNavigator(const HallwayFollowerParams& follow, const HallwayViewParams& view,
                                   const laser_features::BuildingRules& rules, const PlannerParams& robot,
                                   const HallwayDoorParams& doors, const RoutePolicyParams& route,
                                   double branch_record_distance)
    : branch_record_distance_(branch_record_distance),
      follower_(follow, view, rules, robot),
      doors_(doors, rules),
      door_entry_(doors, rules),
      route_(route, rules) {}

bool HallwayNavigator::setOff(const Perception& p, const TopoView& topo, Decision* d) {
  const int along = follower_.startBin(p, topo);
  if (topo.mode == TopoMode::Frontier) {
    // The robot starts mid-hallway, at a crossing or at an open area's edge: the other ways are
    // unexplored openings of the start node.
    for (int way : follower_.waysAtStart(along, p, topo)) {
      Request r;
      r.kind = Request::RecordOpening;
      r.bearing = follower_.binHeading(way);
      d->requests.push_back(r);
    }
  }
  if (along == follower_.bin()) return false;
  beginTurn(along, topo, {});
  return true;
}

HallwayStep HallwayNavigator::follow(const Perception& p, const TopoView& topo, bool blocked, const HallwayContext& at,
                                     Decision* d) {
  HallwayStep step;
  HallwayView v;
  const double dir_robot = follower_.track(p, topo, &v);
  if (follower_.stalled(p)) blocked = true;
  const bool localized = topo.mode == TopoMode::Localized;
  const bool sure = (topo.mode == TopoMode::Frontier) ||
                    (localized && topo.confident && route_.beliefPlausible(at.graph, topo.position, at.travel));
  step.text = sure ? (localized ? "following the hallway on the known map" : "following a new hallway")
                   : "following the hallway until the belief is confident";

  recordWaysNotTaken(sure, at.travel, p.stamp, d);
  // Driven on from the end (beyond the span of two doors from where it turned or came back out of
  // a room): its doors are behind.
  if (at.travel - end_travel_ > 2.0 * HallwayDoors::kSameDoorSpan) doors_left_at_end_.clear();
  // The door beside the end just turned at first: the route's view of the graph does not have it
  // yet (it is no opening of any node until entered), so the route would end the exploration or
  // turn the robot away from it.
  if (enterDoorAfterTurn(p, topo, at, &step, d)) return step;
  if (localized && sure && followRoute(p, topo, at, &step, d)) return step;
  if (enterPassedDoor(p, topo, dir_robot, v, at, &step, d)) return step;
  if (turnIntoRouteBranch(p, topo, sure, dir_robot, v, at, &step, d)) return step;
  if (intoWayAtAngle(p, blocked, d)) {
    step.text = "into the hallway at an angle";
    return step;
  }
  if (follower_.intoOpenArea(p, dir_robot, v) && turnInOpenArea(topo, at, &step)) {
    turnGoal(p, d);
    return step;
  }

  const std::optional<double> lane = follower_.laneAround(p, dir_robot, v, blocked);
  if (lane) step.text = "passing an obstacle in the hallway";
  if (follower_.atEnd(v) && !lane && !blocked && enterEndWallDoor(p, topo, dir_robot, v, at, &step, d)) return step;
  if ((follower_.atEnd(v) && !lane) || blocked) {
    // A door in a side wall between the robot and the end wall is never passed: the robot turns
    // here (the outer wall of an L corner, a dead end's side walls next to its end). It is entered
    // once turned, when the map builder has the turn's node to record it at, as a door passed
    // would be.
    HallwayDoors doors_at_end = doors_;  // the turn forgets the doors tracked
    const int back = follower_.headingBins().wrap(follower_.bin() + follower_.headingBins().bins / 2);
    std::vector<WayLine> at_angle;
    turnAtEnd(p, topo, v, at, &step, &at_angle);
    const std::array<bool, 2> closed{{!v.end_open_left, !v.end_open_right}};
    DoorTrack beside;
    if (!blocked) {  // a mission's door too (mayEnter takes its own only)
      if (doors_at_end.besideEnd(p.odom, dir_robot, walls_, v.free_ahead, closed, turn_bin_ == back, &beside) &&
          !inMouthOfWay(beside, at_angle))
        door_after_turn_ = beside;
      // Every other door there, abeam ones included: one passed on the way back is entered only
      // while the stretch is new, and a room visit from the end can outlast that.
      while (doors_at_end.besideEnd(p.odom, dir_robot, walls_, v.free_ahead, closed, false, &beside)) {
        if (!inMouthOfWay(beside, at_angle)) doors_left_at_end_.push_back(beside);
      }
      door_after_turn_mode_ = topo.mode;
      end_travel_ = at.travel;
    }
    if (blocked) step.text = "motion blocked: " + step.text;
    turnGoal(p, d);
    return step;
  }

  const Eigen::Vector2d goal = follower_.goal(p, dir_robot, v, lane);
  d->has_goal = true;
  d->x = goal.x();
  d->y = goal.y();
  return step;
}

void HallwayNavigator::recordWaysNotTaken(bool sure, double travel, double stamp, Decision* d) {
  // The ways not taken at the last turn, once the map builder has the turn's node.
  if (pending_branch_travel_ >= 0.0 && travel - pending_branch_travel_ >= branch_record_distance_) {
    if (sure) {
      for (int b : pending_branches_) {
        Request r;
        r.kind = Request::RecordOpening;
        r.bearing = follower_.binHeading(b);
        d->requests.push_back(r);
        recorded_stamp_ = stamp;
      }
    }
    pending_branches_.clear();
    pending_branch_travel_ = -1.0;
  }
}

bool HallwayNavigator::followRoute(const Perception& p, const TopoView& topo, const HallwayContext& at,
                                   HallwayStep* step, Decision* d) {
  // The ways just recorded are in the graph only once pomdp_topo has published it again.
  const bool records_settled = p.stamp - recorded_stamp_ >= kRecordSettleTime;
  if (!at.mission_door && at.graph.nodes().size() > 1 && route_.openingsLeft(at.graph) == 0 && pending_branches_.empty() &&
      records_settled) {
    if (const size_t retry = route_.retrySetAside()) {
      // The openings the route kept missing, once more, from a belief found afresh (a wrong one is
      // the likeliest reason for a miss).
      Request reset;
      reset.kind = Request::ResetBelief;
      d->requests.push_back(reset);
      step->text = "every other opening explored: trying the " + std::to_string(retry) +
                   " set aside once more, the belief reset";
      return true;
    }
    step->kind = HallwayStep::Complete;
    return true;
  }
  step->route = route_.plan(at.graph, topo.position, at.mission_door);
  if (at.mission_door && !step->route.found) {
    step->kind = HallwayStep::NoRoute;
    return true;
  }
  const RouteContext route_at{at.graph, topo, at.travel, at.mission_door != nullptr};
  return actOnRoute(route_.alongRoute(route_at, step->route, follower_.binHeading(follower_.bin())), p, topo, step, d);
}

bool HallwayNavigator::actOnRoute(const RouteAction& action, const Perception& p, const TopoView& topo,
                                  HallwayStep* step, Decision* d) {
  switch (action.kind) {
    case RouteAction::None:
      if (!action.text.empty()) step->text = action.text;
      return false;
    case RouteAction::SetAside:
      step->text = action.text;
      return true;
    case RouteAction::GiveUp:
      d->requests.push_back(action.record);
      step->text = action.text;
      return true;
    case RouteAction::MissedDoor:
      step->kind = HallwayStep::MissedDoor;
      return true;
    case RouteAction::TurnRound:
      ++stats_.u_turns;
      beginTurn(follower_.bin() + follower_.headingBins().bins / 2, topo, {});
      break;
    case RouteAction::TurnIntoBranch:
      beginTurn(follower_.binOf(step->route.next_heading), topo, {});
      break;
  }
  step->kind = HallwayStep::Turning;
  step->text = action.text;
  turnGoal(p, d);
  return true;
}

bool HallwayNavigator::enterPassedDoor(const Perception& p, const TopoView& topo, double dir_robot, const HallwayView& v,
                                       const HallwayContext& at, HallwayStep* step, Decision* d) {
  // Doors: entered once passed, if new (frontier) or known and unexplored, and the belief is sure.
  walls_ = doors_.track(p.odom, p.openings, dir_robot, v, at.travel);
  DoorTrack door;
  return doors_.passed(p.odom, dir_robot, walls_, &door) &&
         stopAtDoor(door, "stopping at a door to enter the room", p, topo, at, step, d);
}

bool HallwayNavigator::enterDoorAfterTurn(const Perception& p, const TopoView& topo, const HallwayContext& at,
                                          HallwayStep* step, Decision* d) {
  if (!door_after_turn_) return false;  // most ticks: no copy of the belief's view
  // A door beside the end of a new stretch is new, as a door passed on it would be: the turn there
  // puts the robot on the stretch just made (the belief localized on its end node), where no
  // opening of the node has the door yet.
  TopoView at_end = topo;
  at_end.mode = door_after_turn_mode_;
  while (door_after_turn_) {
    const DoorTrack door = *door_after_turn_;
    door_after_turn_.reset();
    if (stopAtDoor(door, "stopping at a door beside the hallway's end turned at, to enter the room", p, at_end, at,
                   step, d)) {
      entering_.beside_end = entering_.node < 0;
      return true;
    }
    // The next door there (one refused is the room just left, or one entered on the way back).
    nextDoorAtEnd();
  }
  return false;
}

bool HallwayNavigator::stopAtDoor(const DoorTrack& door, const char* what, const Perception& p, const TopoView& topo,
                                  const HallwayContext& at, HallwayStep* step, Decision* d) {
  const bool just_left = door_entry_.justLeft(door, at.travel);
  const std::optional<EntryOpening> entry = just_left ? std::nullopt : mayEnter(topo, at, door);
  if (!entry) {
    if (just_left) step->text = "door passed: the one just left";
    ++stats_.doors_passed;
    return false;
  }
  if (!at.mission_door) {
    // A door that would be entered but is a door of a room mapped already (the room just left, or
    // any other) is an explored way into that room: recorded so at the opening it would have been
    // entered as, linked to the room's place and stored in it (a room with two doors is one place,
    // reachable by either), not entered as a new room.
    const std::optional<MappedRoomDoor> mapped = door_entry_.mappedRoomOf(door, topo.map_from_odom);
    if (mapped || door_entry_.otherDoorOfRoomLeft(door, at.travel)) {
      Request rec;
      rec.kind = Request::RecordOpening;
      rec.node = entry->node;
      rec.bearing = entry->bearing;
      rec.width = door.width;
      rec.explored = true;
      rec.beside_robot = entry->node < 0;
      if (mapped) {
        rec.place_id = mapped->place_id;
        rec.pose = mapped->door_in_place;
        rec.store_in_place = true;
        ++stats_.mapped_room_doors;
      }
      d->requests.push_back(rec);
      step->text = mapped ? "door passed: a door of the room of place " + std::to_string(mapped->place_id) +
                                ", mapped already"
                          : "door passed: another door of the room just left";
      ++stats_.doors_passed;
      return false;
    }
  }
  entering_ = *entry;
  door_ = door;
  // Where the door was taken to be (the log tells a door tracked wrongly from a real one).
  const Eigen::Vector2d rel = transformPoint(inverse(p.odom), door.centre_odom);  // robot frame
  char where[128];
  char wall[40] = "no wall known";
  if (door.wall_lateral >= 0.0) std::snprintf(wall, sizeof(wall), "its wall %.2f m aside", door.wall_lateral);
  std::snprintf(where, sizeof(where), " (%.2f m wide, %d sightings, at %.2f m ahead, %.2f m left, %s)", door.width,
                door.sightings, rel.x(), rel.y(), wall);
  step->kind = HallwayStep::StopForDoor;
  step->text = what + std::string(where);
  d->stop = true;
  return true;
}

bool HallwayNavigator::enterEndWallDoor(const Perception& p, const TopoView& topo, double dir_robot,
                                        const HallwayView& v, const HallwayContext& at, HallwayStep* step,
                                        Decision* d) {
  // A room at a hallway's end has its door in the end wall: no door passes beside the robot there.
  // At a dead end (a side open is a way on, and a door in the far wall of a crossing is passed on
  // it) the door ahead is entered as a door passed would be, unless the robot came out of it. A
  // mission's door may be that door (mayEnter takes its own only); the rooms mapped are what a
  // mission goes to.
  if (v.end_open_left || v.end_open_right) return false;
  const std::optional<DoorTrack> door = doors_.inEndWall(p.odom, p.openings, dir_robot, v);
  if (!door || door_entry_.justLeft(*door, at.travel)) return false;
  if (!at.mission_door &&
      (door_entry_.otherDoorOfRoomLeft(*door, at.travel) || door_entry_.mappedRoomOf(*door, topo.map_from_odom)))
    return false;
  const std::optional<EntryOpening> entry = mayEnter(topo, at, *door);
  if (!entry) return false;
  entering_ = *entry;
  door_ = *door;
  const Eigen::Vector2d rel = transformPoint(inverse(p.odom), door->centre_odom);
  char text[160];
  std::snprintf(text, sizeof(text), "stopping at a door in the hallway's end wall to enter the room (%.2f m wide, %.2f m ahead, %.2f m left)",
                door->width, rel.x(), rel.y());
  step->kind = HallwayStep::StopForDoor;
  step->text = text;
  d->stop = true;
  return true;
}

bool HallwayNavigator::turnIntoRouteBranch(const Perception& p, const TopoView& topo, bool sure, double dir_robot,
                                           const HallwayView& v, const HallwayContext& at, HallwayStep* step,
                                           Decision* d) {
  // A side branch the route takes at the node the robot is at now: the side it leaves to must be
  // open (the branch's mouth is beside the robot); a door tracked beside the robot there is no branch.
  if (!sure) return false;
  const int route_bin = follower_.binOf(step->route.next_heading);
  const int n = follower_.headingBins().bins, bin = follower_.bin();
  const bool left = route_bin == (bin + n / 4) % n, right = route_bin == (bin + 3 * n / 4) % n;
  const bool side_open = (left && v.open_left) || (right && v.open_right);
  const std::optional<DoorTrack> door_abeam =
      side_open ? doors_.abeam(p.odom, dir_robot, left ? 1.0 : -1.0) : std::nullopt;
  const RouteContext route_at{at.graph, topo, at.travel, at.mission_door != nullptr};
  return actOnRoute(route_.atBranch(route_at, step->route, side_open, door_abeam), p, topo, step, d);
}

bool HallwayNavigator::inMouthOfWay(const DoorTrack& door, const std::vector<WayLine>& at_angle) const {
  return std::any_of(at_angle.begin(), at_angle.end(), [&](const WayLine& way) {
    const Eigen::Vector2d u(std::cos(way.heading), std::sin(way.heading)), n(-u.y(), u.x());
    const Eigen::Vector2d c = door.centre_odom - way.origin;
    return c.dot(u) >= 0.0 && std::abs(c.dot(n)) <= 0.5 * door.width + follower_.rules().width_tolerance;
  });
}

void HallwayNavigator::turnAtEnd(const Perception& p, const TopoView& topo, const HallwayView& v,
                                 const HallwayContext& at, HallwayStep* step, std::vector<WayLine>* at_angle) {
  step->kind = HallwayStep::Turning;
  const int n = follower_.headingBins().bins, bin = follower_.bin();
  const int left = (bin + n / 4) % n, right = (bin + 3 * n / 4) % n, back = (bin + n / 2) % n;
  // The ways out: the sides open along the axes, left first, then the hallways at an angle (wings),
  // left first. A wing's bin is the one pomdp_topo gives the branch once the robot has turned into
  // it; a side open along the axes is that bin's way where both are.
  std::vector<EndWay> ways;
  if (v.end_open_left) ways.push_back({left, std::nullopt});
  if (v.end_open_right) ways.push_back({right, std::nullopt});
  for (const ObliqueWay& way : follower_.obliqueWaysAtEnd(p, topo, v)) {
    at_angle->push_back(WayLine{transformPoint(p.odom, way.origin), normalizeAngle(p.odom.theta + way.direction), 0.0});
    const int way_bin = follower_.wayBin(way.direction, p, topo);
    const bool known = std::any_of(ways.begin(), ways.end(), [&](const EndWay& w) { return w.bin == way_bin; });
    if (way_bin != back && !known) ways.push_back({way_bin, way});
  }
  char why[160];
  std::snprintf(why, sizeof(why), " (free ahead %.2f m, left %s, right %s, at %.2f %.2f odom)", v.free_ahead,
                v.end_open_left ? "open" : "closed", v.end_open_right ? "open" : "closed", p.odom.x, p.odom.y);
  if (ways.empty()) {
    // A U-turn where the robot turned round a moment ago (less than its clearance driven since)
    // would face the way it found closed a moment ago: both ways along are closed (a stub the
    // route turned it into, a lane blocked both ways). It turns to the freer side instead of round
    // and round for ever.
    const bool again = at.travel - u_turn_travel_ < follower_.viewParams().clearance;
    u_turn_travel_ = at.travel;
    if (again) {
      const bool to_left = follower_.freeAlong(left, p, topo) >= follower_.freeAlong(right, p, topo);
      ++stats_.turns;
      beginTurn(to_left ? left : right, topo, {});
      step->text = std::string("hallway end where the robot turned round: turning to the freer side, ") +
                   (to_left ? "left" : "right") + why;
      return;
    }
    ++stats_.u_turns;
    beginTurn(back, topo, {});
    step->text = "hallway end: turning round" + std::string(why);
    return;
  }
  EndWay choice = ways.front();  // depth-first, one fixed order
  if (beliefTrusted(topo, at.travel)) {
    const RouteStep r = route_.plan(at.graph, topo.position, at.mission_door);
    if (r.found) {
      const int near = at.graph.nearestNode(topo.position);
      const int rb = follower_.binOf(near >= 0 && uint32_t(near) == r.next_node ? r.next_heading : r.heading);
      const auto routed = std::find_if(ways.begin(), ways.end(), [&](const EndWay& w) { return w.bin == rb; });
      if (routed != ways.end()) choice = *routed;
    }
  }
  // The other ways are the turn's node's unexplored openings, on a new stretch.
  std::vector<int> not_taken;
  if (topo.mode == TopoMode::Frontier && !at.mission_door) {
    for (const EndWay& w : ways) {
      if (w.bin != choice.bin) not_taken.push_back(w.bin);
    }
  }
  ++stats_.turns;
  if (!choice.oblique) {
    beginTurn(choice.bin, topo, not_taken);
    step->text = "hallway end: turning " + std::string(choice.bin == left ? "left" : "right") + why;
    return;
  }
  const ObliqueWay& way = *choice.oblique;
  beginTurn(follower_.takeWay(way.direction, p, topo), topo, not_taken);
  // The way's corridor was found free for the widest hallway's width from its origin in the
  // crossing; half of it in, its walls are beside the robot (obliqueHallways' first depth).
  way_line_ = WayLine{transformPoint(p.odom, way.origin), normalizeAngle(p.odom.theta + way.direction),
                      0.5 * follower_.hallwayMaxWidth()};
  char angle[64];
  std::snprintf(angle, sizeof(angle), "hallway end: turning %.0f deg into a hallway at an angle",
                way.direction * 180.0 / kPi);
  step->text = angle + std::string(why);
}

bool HallwayNavigator::turnInOpenArea(const TopoView& topo, const HallwayContext& at, HallwayStep* step) {
  // The robot keeps to an open area's walls: the doors and the hallways leaving it are along them,
  // and its middle is no hallway to follow (the sector ahead sees nothing of them from there). It
  // turns along the wall the hallway came in by (left first, as at a hallway's end, or the route's
  // way), the other way along it a way not taken; a route across the area is followed across.
  const int n = follower_.headingBins().bins, bin = follower_.bin();
  const int left = (bin + n / 4) % n, right = (bin + 3 * n / 4) % n;
  int choice = left;
  if (beliefTrusted(topo, at.travel) || at.mission_door) {
    const RouteStep r = route_.plan(at.graph, topo.position, at.mission_door);
    if (r.found) {
      const int near = at.graph.nearestNode(topo.position);
      const int rb = follower_.binOf(near >= 0 && uint32_t(near) == r.next_node ? r.next_heading : r.heading);
      if (rb != left && rb != right) return false;
      choice = rb;
    }
  }
  std::vector<int> not_taken;
  if (topo.mode == TopoMode::Frontier && !at.mission_door) not_taken.push_back(choice == left ? right : left);
  // No wall of the hallway left is in view: a wing's offset ends with it, the area's walls are
  // taken along the axes until one is seen (then the tracking sets the offset again).
  follower_.dropOffset();
  ++stats_.turns;
  beginTurn(choice, topo, not_taken);
  step->kind = HallwayStep::Turning;
  step->text = std::string("an open area: turning ") + (choice == left ? "left" : "right") + " along its wall";
  return true;
}

bool HallwayNavigator::intoWayAtAngle(const Perception& p, bool blocked, Decision* d) {
  if (!way_line_) return false;
  const Eigen::Vector2d u(std::cos(way_line_->heading), std::sin(way_line_->heading));
  const double along = (Eigen::Vector2d(p.odom.x, p.odom.y) - way_line_->origin).dot(u);
  if (blocked || along >= way_line_->length) {
    way_line_.reset();
    return false;
  }
  const Eigen::Vector2d goal = way_line_->origin + (std::max(0.0, along) + follower_.lookahead()) * u;
  d->has_goal = true;
  d->x = goal.x();
  d->y = goal.y();
  return true;
}

void HallwayNavigator::beginTurn(int bin, const TopoView& topo, std::vector<int> not_taken) {
  way_line_.reset();
  door_after_turn_.reset();
  doors_left_at_end_.clear();
  // Turns keep the hallway's offset from the axes: a wing's crossings and U-turns are square to it.
  turn_bin_ = follower_.headingBins().wrap(bin);
  turn_odom_heading_ = normalizeAngle(follower_.odomHeadingAtOffset(turn_bin_, topo));
  // The ways not taken at the last turn and not recorded yet (a turn again within
  // branch_record_distance: a T whose way taken ends at once) stay to record: the map builder keeps
  // one node for turns within its node_radius, which branch_record_distance does not pass. The way
  // this turn takes is no longer one.
  std::vector<int> pending;
  for (int b : pending_branches_) {
    if (b != turn_bin_ && std::find(not_taken.begin(), not_taken.end(), b) == not_taken.end()) pending.push_back(b);
  }
  pending.insert(pending.end(), not_taken.begin(), not_taken.end());
  pending_branches_ = std::move(pending);
  pending_branch_travel_ = -1.0;
  doors_.clear();  // the doors and walls seen so far belong to the hallway being left
}

void HallwayNavigator::turnGoal(const Perception& p, Decision* d) const {
  d->has_goal = true;
  d->x = p.odom.x;
  d->y = p.odom.y;
  d->theta = turn_odom_heading_;
}

bool HallwayNavigator::turn(const Perception& p, bool motion_reached, bool motion_blocked, double travel, Decision* d) {
  // Turn on the spot where the robot is now: a position fixed when the turn was decided lies
  // behind the robot once it has braked, and the controller would turn round to reach it.
  turnGoal(p, d);
  const double err = std::abs(normalizeAngle(turn_odom_heading_ - p.odom.theta));
  if (!((motion_reached && err < 0.15) || err < 0.05 || (motion_blocked && err < 0.3))) return false;
  follower_.setBin(turn_bin_);
  pending_branch_travel_ = travel;
  route_.turned(travel);
  follower_.forgetGoal();
  return true;
}

std::optional<EntryOpening> HallwayNavigator::enterAfterStop(const TopoView& topo, const HallwayContext& at,
                                                             std::string* why_passed) {
  if (entering_.node < 0 && !entering_.beside_end && topo.mode != TopoMode::Frontier) {
    // Stopped for a door on a new stretch, and pomdp_topo has since made its node and taken it
    // for a known one: a loop hypothesis (the check merges the node, the door explored, or
    // rejects it, its opening unexplored and come back to), or a loop closed in the same scan
    // (explore_restart: room_east mapped twice). Entered only as a known unexplored door
    // (mayEnter); else on along the hallway. Not a door beside the end of a new stretch: the turn
    // there localizes the belief on the end's node, whose door it is (enterDoorAfterTurn).
    const std::optional<EntryOpening> known = mayEnter(topo, at, door_);
    if (!known) {
      ++stats_.doors_passed;
      *why_passed = topo.mode == TopoMode::LoopCheck ? "door passed: pomdp_topo checks whether it is a known one"
                                              : "door passed: it is a known one (pomdp_topo closed a loop at it)";
      return std::nullopt;
    }
    entering_ = *known;
  }
  if (entering_.node < 0 &&
      door_entry_.exploredAtFrontierNode(topo, at.graph, door_, follower_.topoBearing(door_.into_odom, topo), at.travel)) {
    // On a new stretch pomdp_topo took the door for one its current node has, explored: a door
    // recorded at a junction a metre off its centre, seen again from it (large_floor: room_7_14,
    // entered from the junction at a T, entered again from a stretch leaving it 5,600 s later).
    ++stats_.doors_passed;
    *why_passed = "door passed: the node's explored one";
    return std::nullopt;
  }
  return entering_;
}

void HallwayNavigator::roomMapped(int place_id, const Pose2D& origin_map, const std::vector<Pose2D>& doors_in_place) {
  door_entry_.roomMapped(place_id, origin_map, doors_in_place);
}

void HallwayNavigator::nextDoorAtEnd() {
  if (doors_left_at_end_.empty()) return;
  door_after_turn_ = doors_left_at_end_.front();
  doors_left_at_end_.erase(doors_left_at_end_.begin());
}

void HallwayNavigator::backFromRoom(const HallwayDirection& direction, const DoorTrack& door_left,
                                    const std::vector<DoorTrack>& other_doors, double travel) {
  way_line_.reset();
  door_after_turn_.reset();
  end_travel_ = travel;
  nextDoorAtEnd();
  follower_.setDirection(direction);
  follower_.forgetGoal();
  door_entry_.leftBy(door_left, other_doors, travel);
  doors_.roomVisited();
  route_.backOnHallway(travel);
}

std::optional<EntryOpening> HallwayNavigator::mayEnter(const TopoView& topo, const HallwayContext& at,
                                                       const DoorTrack& door) const {
  return door_entry_.mayEnter(topo, at.graph, door, follower_.topoBearing(door.into_odom, topo),
                              beliefTrusted(topo, at.travel), at.mission_door);
}

}  // namespace exploration
