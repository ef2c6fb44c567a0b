#include "exploration/hallway_navigator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::transformPoint;

HallwayNavigator::HallwayNavigator(const HallwayFollowerParams& follow, const HallwayViewParams& view,
                                   const laser_features::BuildingRules& rules, const PlannerParams& robot,
                                   const HallwayDoorParams& doors, const RoutePolicyParams& route,
                                   double branch_record_distance)
    : branch_record_distance_(branch_record_distance),
      follower_(follow, view, rules, robot),
      route_(route, rules),
      door_stops_(doors, rules, follower_, route_) {}

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
  door_stops_.forgetEndPassed(at.travel);
  // The door beside the end just turned at first: the route's view of the graph does not have it
  // yet (it is no opening of any node until entered), so the route would end the exploration or
  // turn the robot away from it.
  if (door_stops_.enterAfterTurn(p, topo, at, &step, d)) return step;
  if (localized && sure && followRoute(p, topo, at, &step, d)) return step;
  if (door_stops_.enterPassed(p, topo, dir_robot, v, at, &step, d)) return step;
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
  if (follower_.atEnd(v) && !lane && !blocked && door_stops_.enterInEndWall(p, topo, dir_robot, v, at, &step, d))
    return step;
  if ((follower_.atEnd(v) && !lane) || blocked) {
    // The doors beside the end are entered once turned (HallwayDoorStops::rememberAtEnd).
    HallwayDoors doors_at_end = door_stops_.tracked();  // the turn forgets the doors tracked
    const int back = follower_.headingBins().wrap(follower_.bin() + follower_.headingBins().bins / 2);
    std::vector<WayLine> at_angle;
    turnAtEnd(p, topo, v, at, &step, &at_angle);
    if (!blocked) {  // a mission's door too (mayEnter takes its own only)
      door_stops_.rememberAtEnd(std::move(doors_at_end), p, dir_robot, v, turn_bin_ == back, at_angle, topo.mode,
                                at.travel);
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
      side_open ? door_stops_.abeam(p.odom, dir_robot, left ? 1.0 : -1.0) : std::nullopt;
  const RouteContext route_at{at.graph, topo, at.travel, at.mission_door != nullptr};
  return actOnRoute(route_.atBranch(route_at, step->route, side_open, door_abeam), p, topo, step, d);
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
  door_stops_.turned();  // the doors and walls seen so far belong to the hallway being left
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

void HallwayNavigator::backFromRoom(const HallwayDirection& direction, const DoorTrack& door_left,
                                    const std::vector<DoorTrack>& other_doors, double travel,
                                    const std::optional<laser_features::Pose2D>& drift) {
  way_line_.reset();
  door_stops_.backFromRoom(door_left, other_doors, travel, drift);
  follower_.setDirection(direction);
  follower_.forgetGoal();
  route_.backOnHallway(travel);
}

}  // namespace exploration
