#include "exploration/route_policy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {

// m: the robot is at a node when the belief puts it this close (pomdp_topo's node_radius).
constexpr double kAtNodeDistance = 1.0;

}  // namespace

RouteStep RoutePolicy::plan(const TopoGraph& graph, const GraphPosition& pos, const PlaceDoor* mission_door) const {
  RouteStep r = mission_door ? graph.routeTo(pos, mission_door->node, mission_door->opening, params_.u_turn_cost)
                             : graph.route(pos, params_.u_turn_cost,
                                           [this](uint32_t n, const GraphOpening& o) { return leftOut(n, o); });
  // A door is entered once passed beside the robot. A route that reaches the door's node heading
  // away from it -- along a branch that leaves the node beside the door, the door's way (a door
  // next to a junction's branch, both at one node) -- would never pass it: its last leg runs along
  // the door's wall instead, a turn at the node into the node's edge there (atBranch). A door
  // straight ahead is in the hallway's end wall: the turn at the end passes it.
  const bool door = mission_door || (r.goal_width > 0.0 && rules_.doorByWidth(r.goal_width));
  const bool away = std::cos(r.arrival_heading - r.goal_bearing) < -std::cos(0.25 * kPi);
  if (r.found && door && r.next_node == r.goal_node && away) {
    if (const std::optional<double> along = graph.headingAlongOpening(r.goal_node, r.goal_bearing)) {
      r.next_heading = *along;
      r.door_behind = true;
    }
  }
  return r;
}

size_t RoutePolicy::openingsLeft(const TopoGraph& graph) const {
  return graph.unexploredCount([this](uint32_t n, const GraphOpening& o) { return leftOut(n, o); });
}

bool RoutePolicy::leftOut(uint32_t node, const GraphOpening& o) const {
  // Given up is given up whether or not the map builder's record of it took: a record that marked
  // another opening of the node (one on the same side that the width does not tell apart) or was
  // refused would leave the opening to be routed to, missed and given up again, round and round
  // until the time limit.
  return named(set_aside_, node, o.bearing) || named(given_up_, node, o.bearing);
}

size_t RoutePolicy::retrySetAside() {
  const size_t n = set_aside_.size();
  retried_.insert(retried_.end(), set_aside_.begin(), set_aside_.end());
  set_aside_.clear();
  route_attempts_.clear();
  branch_turns_.clear();
  return n;
}

bool RoutePolicy::named(const std::vector<std::pair<uint32_t, double>>& list, uint32_t node, double bearing) const {
  return std::any_of(list.begin(), list.end(), [&](const std::pair<uint32_t, double>& o) {
    return o.first == node && bins_.sameWay(o.second, bearing);
  });
}

bool RoutePolicy::beliefPlausible(const TopoGraph& graph, const GraphPosition& pos, double travel) {
  // A confident belief that jumps to a node farther along the graph than the robot has travelled
  // since it adopted the last trusted one is not acted on (no room entered, no turn for the route)
  // until it has held for jump_hold_distance of travel: the map builder's belief can lock onto a
  // look-alike place after a U-turn at a hallway end.
  // Neighbours on the graph are never a jump (the nearest node changes half-way along an edge).
  const int near = graph.nearestNode(pos);
  if (near < 0) return false;
  if (trusted_node_ >= 0 && near != trusted_node_ && !graph.adjacent(uint32_t(trusted_node_), uint32_t(near))) {
    const double d = graph.distance(uint32_t(trusted_node_), uint32_t(near));
    if (d > travel - trusted_travel_ + params_.jump_tolerance) {
      distrust_until_ = travel + params_.jump_hold_distance;
      ++stats_.belief_jumps;
    }
  }
  if (near != trusted_node_) {
    trusted_node_ = near;
    trusted_travel_ = travel;
  }
  return travel >= distrust_until_;
}

bool RoutePolicy::beliefTrusted(const TopoView& topo, double travel) const {
  return topo.mode == TopoMode::Localized && topo.confident && travel >= distrust_until_;
}

RouteAction RoutePolicy::alongRoute(const RouteContext& at, const RouteStep& route, double heading) {
  const int near = at.graph.nearestNode(at.topo.position);
  RouteAction passed = passedGoal(at, route, near);
  if (passed.kind != RouteAction::None) return passed;
  // The route points back along the hallway: turn round (after a few ticks of agreement), but
  // not for the node the robot is at: its door is entered once passed, or given up (above).
  if (!(route.found && (near < 0 || uint32_t(near) != route.goal_node) &&
        std::abs(normalizeAngle(route.heading - heading)) > 0.75 * kPi)) {
    route_behind_ticks_ = 0;
    return RouteAction{};
  }
  // Not again soon after a turn: a belief flickering between two edges would swing the robot.
  if (++route_behind_ticks_ < 5 || !(at.travel - last_turn_travel_ > kTurnRoundGap)) return RouteAction{};
  route_behind_ticks_ = 0;
  // An opening the robot keeps turning round for (it passes its node without taking it: the door
  // is not seen, or the belief flickers) is given up after max_route_attempts.
  const bool missed = ++route_attempts_[route.goal_node] > params_.max_route_attempts;
  if (missed && at.mission) return RouteAction{RouteAction::MissedDoor, {}, ""};
  if (missed)
    return giveUp(route.goal_node, route.goal_bearing, route.goal_width,
                  "missed an opening of node " + std::to_string(route.goal_node));
  RouteAction turn_round{RouteAction::TurnRound, {}, ""};
  turn_round.text = "turning round towards node " + std::to_string(route.goal_node) + " (" +
                    std::to_string(route.distance) + " m, from " + (at.topo.position.at_node ? "node " : "edge ") +
                    std::to_string(at.topo.position.id) + ")";
  return turn_round;
}

RouteAction RoutePolicy::passedGoal(const RouteContext& at, const RouteStep& route, int near) {
  // At the goal node with its opening to a side that never opens (a door the laser does not show
  // again, a wide door taken for a branch): give it up once the robot has gone past, instead of
  // turning round for it again and again (each U-turn on a hallway weakens the belief).
  // Doors only: a hallway branch is never given up this way; the robot turns into it when its side
  // opens (atBranch).
  const bool door_goal = route.goal_width > 0.0 && rules_.doorByWidth(route.goal_width);
  // Counted from within kAtNodeDistance of it: the nearest node changes half-way along an edge.
  const bool at_goal = near >= 0 && uint32_t(near) == route.goal_node;
  const bool close = at_goal && at.graph.nearestNodeDistance(at.topo.position) <= kAtNodeDistance;
  if (!at.mission && route.found && door_goal && at_goal && (goal_pass_node_ == near || close)) {
    if (goal_pass_node_ != near) {
      goal_pass_node_ = near;
      goal_pass_travel_ = at.travel;
    } else if (at.travel - goal_pass_travel_ > params_.goal_pass_distance) {
      goal_pass_node_ = -1;
      return giveUp(uint32_t(near), route.goal_bearing, route.goal_width,
                    "passed node " + std::to_string(near) + " without finding its opening");
    }
  } else if (near != goal_pass_node_) {
    goal_pass_node_ = -1;
  }
  return RouteAction{};
}

RouteAction RoutePolicy::atBranch(const RouteContext& at, const RouteStep& route, bool side_open,
                                  const std::optional<DoorTrack>& door_abeam) {
  // A door is entered once passed, never turned into like a branch: a mission's goal, an
  // exploration's goal opening as narrow as only a door is (a side sector of a narrow hallway sees
  // through a door into the room behind it and opens), and a goal opening as wide as a hallway's
  // mouth where laser_features sees a door of its width beside the robot: a double door, which the
  // map builder's sightings took for a branch (a room behind it seen in fewer of them).
  const bool goal_is_door =
      route.goal_width > 0.0 &&
      (rules_.doorByWidth(route.goal_width) || (door_abeam && rules_.sameWidth(door_abeam->width, route.goal_width)));
  const bool door_next = route.next_node == route.goal_node && (at.mission || goal_is_door) && !route.door_behind;
  if (!route.found || door_next) return RouteAction{};
  const int near = at.graph.nearestNode(at.topo.position);
  // At the node as the belief says, or within 2 m of the goal node: the belief may be off by a
  // metre, the branch's mouth opens the side sector only within a quarter metre of its centre.
  const bool here = (near >= 0 && uint32_t(near) == route.next_node) ||
                    (route.next_node == route.goal_node && route.distance < 2.0);
  if (!side_open || !here) return RouteAction{};
  if (door_abeam) {
    // A door abeam on that side is not the branch: the belief that puts the robot at the branch's
    // node is wrong. The robot drives on and the belief is not acted on (no turn round for the
    // route, no room entered) for jump_hold_distance, as after a jump.
    if (refused_branch_node_ != long(route.next_node)) {  // counted once per node in a row
      refused_branch_node_ = long(route.next_node);
      ++stats_.branch_turns_refused;
    }
    distrust_until_ = std::max(distrust_until_, at.travel + params_.jump_hold_distance);
    char why[160];
    std::snprintf(why, sizeof(why), "a %.2f m door beside the robot, not the branch of node %u: not turning",
                  door_abeam->width, route.next_node);
    return RouteAction{RouteAction::None, {}, why};
  }
  // A route that turns into the same branch towards the same goal again and again goes round in a
  // circle (a belief that moves back as the robot turns, look-alike junctions): after
  // max_route_attempts such turns the goal's opening is given up, or a mission's door counts as
  // missed, as after as many U-turns.
  if (++branch_turns_[{route.next_node, route.goal_node}] > params_.max_route_attempts) {
    if (at.mission) return RouteAction{RouteAction::MissedDoor, {}, ""};
    return giveUp(route.goal_node, route.goal_bearing, route.goal_width,
                  "missed an opening of node " + std::to_string(route.goal_node));
  }
  if (route.door_behind)
    return RouteAction{RouteAction::TurnIntoBranch, {},
                       "turning at node " + std::to_string(route.goal_node) +
                           " into the hallway along its door's wall (the door is behind the robot)"};
  return RouteAction{RouteAction::TurnIntoBranch, {},
                     "turning into the branch of node " + std::to_string(near) + " towards node " +
                         std::to_string(route.goal_node)};
}

RouteAction RoutePolicy::giveUp(uint32_t node, double bearing, double width, const std::string& why) {
  route_attempts_.erase(node);
  for (auto it = branch_turns_.begin(); it != branch_turns_.end();) {
    it = it->first.second == node ? branch_turns_.erase(it) : std::next(it);
  }
  if (!named(retried_, node, bearing)) {
    // The first miss: most often a wrong belief, not an opening that is not there. The other
    // openings first; this one once more when they are all explored.
    set_aside_.emplace_back(node, bearing);
    ++stats_.openings_set_aside;
    return RouteAction{RouteAction::SetAside, {}, why + ": set aside until the others are explored"};
  }
  given_up_.emplace_back(node, bearing);
  RouteAction give_up{RouteAction::GiveUp, {}, why + ": given up"};
  give_up.record.kind = Request::RecordOpening;
  give_up.record.node = int(node);
  give_up.record.bearing = bearing;
  // Its width names the opening where the node has two on that side (a door and a hallway's mouth
  // beside it: pomdp_topo keeps them apart by width, BuildingRules::differentOpenings).
  give_up.record.width = width;
  give_up.record.explored = true;
  ++stats_.openings_given_up;
  return give_up;
}

}  // namespace exploration
