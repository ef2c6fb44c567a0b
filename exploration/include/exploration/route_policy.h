// The route on the known map (Tomatis, Nourbakhsh & Siegwart 2001, section 3.1): the robot travels
// along the graph to the nearest node with an unexplored opening (or to a mission's door) and takes
// it. RoutePolicy plans the route and says when the robot acts on it: a turn round towards a goal
// behind it, a turn into the route's branch beside it, or the goal set aside when the robot keeps
// missing it (tried once more when every other opening is explored, then given up); and whether a confident belief is trusted (one that jumped along the graph is not acted
// on for a while).
//
// HallwayNavigator turns the robot, the coordinator ends missions; RoutePolicy keeps the counts its
// rules need.
//
// ROS-free: laser_features and the standard library only.
#pragma once

#include "exploration/coordinator_io.h"
#include "exploration/hallway_doors.h"
#include "exploration/topo_route.h"
#include "laser_features/building_axes.h"
#include "laser_features/building_rules.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace exploration {

/// Parameters of RoutePolicy (config/exploration.yaml's u_turn_cost, max_route_attempts,
/// jump_tolerance, jump_hold_distance and goal_pass_distance; each with its unit and default).
struct RoutePolicyParams {
  double u_turn_cost = 2.0;          // m, route cost of turning back on an edge
  int max_route_attempts = 3;        // -, turns round towards one node's opening, or into one branch towards it, before it is given up
  double jump_tolerance = 4.0;       // m, a belief whose node is farther along the graph from the last
                                     // trusted one than the travel since plus this has jumped ...
  double jump_hold_distance = 6.0;   // m, ... and is not acted on until it held for this much travel
  double goal_pass_distance = 3.0;   // m, travel at the goal node (as the belief says) without finding
                                     // its opening before the opening is given up
};

/// The robot on the hallway this tick, as the route's rules see it.
struct RouteContext {
  const TopoGraph& graph;
  const TopoView& topo;  // the belief
  double travel;         // m, odometric
  bool mission;          // a mission runs: the route's goal is its door
};

/// What the route asks of the robot this tick.
struct RouteAction {
  enum Kind {
    None,            // nothing for the route: on along the hallway
    TurnRound,       // turn round towards the route's goal
    TurnIntoBranch,  // turn into the route's branch beside the robot (RouteStep::next_heading)
    SetAside,        // the route's goal opening is set aside unreached until the others are explored
    GiveUp,          // the route's goal opening is given up unreached: `record` marks it explored
    MissedDoor,      // a mission's door was not found after max_route_attempts turns (round or into a branch) towards it
  };
  Kind kind = None;
  Request record;    // GiveUp
  std::string text;  // the state text ("": as it is)
};

/// The counts of RoutePolicy's rules (in CoordinatorStats).
struct RouteStats {
  int openings_given_up = 0;     // openings the route kept missing, also when tried once more
  int openings_set_aside = 0;    // openings the route kept missing the first time
  int belief_jumps = 0;          // implausible jumps of the belief
  int branch_turns_refused = 0;  // route turns into a branch not made: a door was beside the robot
};

class RoutePolicy {
 public:
  /// `rules`: a goal opening of a door's width (BuildingRules::doorByWidth) is given up once passed.
  RoutePolicy(const RoutePolicyParams& params, const laser_features::BuildingRules& rules)
      : params_(params), rules_(rules) {}
  const RouteStats& stats() const { return stats_; }
  /// The heading bins of the topological map's bearings (the building's axes).
  void setHeadingBins(const laser_features::HeadingBins& bins) { bins_ = bins; }

  /// The route from `pos`: to `mission_door` if a mission runs, else to the nearest unexplored opening.
  RouteStep plan(const TopoGraph& graph, const GraphPosition& pos, const PlaceDoor* mission_door) const;

  /// A confident, localized belief is acted on: it has not jumped along the graph farther than the
  /// robot travelled (or it has held since for jump_hold_distance). Updates the trusted node.
  bool beliefPlausible(const TopoGraph& graph, const GraphPosition& pos, double travel);
  /// The belief is localized and confident, and not on hold after a jump.
  bool beliefTrusted(const TopoView& topo, double travel) const;

  /// On the route with a sure, localized belief: the goal's door given up once passed, or a turn
  /// round for a goal behind the robot (`heading`: the heading of the bin followed, map frame).
  RouteAction alongRoute(const RouteContext& at, const RouteStep& route, double heading);
  /// The route's branch at the node the robot is at, with a sure belief: `side_open`, the side the
  /// branch leaves to is open; `door_abeam`, a door tracked beside the robot on that side.
  RouteAction atBranch(const RouteContext& at, const RouteStep& route, bool side_open,
                       const std::optional<DoorTrack>& door_abeam);

  /// The robot turned at `travel` (m): no turn round for the route within kTurnRoundGap after it.
  void turned(double travel) { last_turn_travel_ = travel; }
  /// The route may turn the robot round at once (a mission starts on the hallway).
  void allowTurnRound(double travel) { last_turn_travel_ = travel - kTurnRoundGap; }
  /// Back on the hallway from a room at `travel` (m): as after a turn, and the travel in the room is
  /// no travel past the route's goal node (a door facing the one just explored would be given up).
  void backOnHallway(double travel) {
    last_turn_travel_ = travel;
    goal_pass_node_ = -1;
  }
  /// The turns round and into branches towards each goal count afresh (a mission starts, its
  /// belief is reset).
  void clearAttempts() {
    route_attempts_.clear();
    branch_turns_.clear();
  }

  /// Unexplored openings the route plans for (those set aside are not, until retrySetAside).
  size_t openingsLeft(const TopoGraph& graph) const;
  /// The openings set aside are planned for again, each once more (the next miss gives it up);
  /// returns how many. A miss is most often a wrong belief: the caller resets it first.
  size_t retrySetAside();

 private:
  static constexpr double kTurnRoundGap = 3.0;  // m of travel after a turn before a turn round for the route
  /// The goal's door passed without finding it: given up (RouteAction::GiveUp), else None.
  RouteAction passedGoal(const RouteContext& at, const RouteStep& route, int near);
  /// The goal's opening set aside (the first miss) or given up (a miss after retrySetAside), its
  /// counts of turns towards it forgotten.
  RouteAction giveUp(uint32_t node, double bearing, double width, const std::string& why);
  /// The opening `o` of `node` is left out of routes and of the openings left: set aside for now,
  /// or given up.
  bool leftOut(uint32_t node, const GraphOpening& o) const;
  /// (`node`, `bearing`) names an opening of `list` (same node, the same way: HeadingBins::sameWay).
  bool named(const std::vector<std::pair<uint32_t, double>>& list, uint32_t node, double bearing) const;

  RoutePolicyParams params_;
  laser_features::BuildingRules rules_;
  laser_features::HeadingBins bins_;  // see setHeadingBins
  RouteStats stats_;
  int route_behind_ticks_ = 0;     // consecutive ticks the route pointed back (U-turn hysteresis)
  double last_turn_travel_ = -1e9;  // m, travel at the last turn
  int trusted_node_ = -1;          // the belief's node when last trusted
  double trusted_travel_ = 0.0;    // m, travel when it became the trusted node
  double distrust_until_ = 0.0;    // m, travel before which a jumped belief is not acted on
  long refused_branch_node_ = -1;  // the last node whose branch turn was refused (a door beside)
  int goal_pass_node_ = -1;        // the route's goal node the robot is at (as the belief says)
  double goal_pass_travel_ = 0.0;  // m, travel when it got there
  std::map<uint32_t, int> route_attempts_;  // U-turns towards each goal node
  std::map<std::pair<uint32_t, uint32_t>, int> branch_turns_;  // turns into (node's branch, towards goal node)
  std::vector<std::pair<uint32_t, double>> set_aside_;  // (node, bearing) of openings missed once
  std::vector<std::pair<uint32_t, double>> retried_;    // ... and tried once more
  std::vector<std::pair<uint32_t, double>> given_up_;   // ... and missed again: never routed to again
};

}  // namespace exploration
