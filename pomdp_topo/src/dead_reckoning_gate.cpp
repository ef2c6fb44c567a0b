#include "pomdp_topo/dead_reckoning_gate.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pomdp_topo {

using laser_features::kPi;

bool statePosition(const TopologicalMap& map, const PomdpLocalizer::State& st, Eigen::Vector2d* p) {
  if (st.kind == PomdpLocalizer::State::Edge) {
    const TopoEdge* e = map.edge(st.id);
    return e != nullptr && map.pointOnEdge(*e, st.offset, p);
  }
  const TopoNode* n = map.node(st.id);
  if (n == nullptr) return false;
  *p = Eigen::Vector2d(n->pose.x, n->pose.y);
  return true;
}

std::string DeadReckoningGate::gate(const TopologicalMap& map, PomdpLocalizer* localizer,
                                    const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                                    const Pose2D& robot, double travel, int heading_bin) {
  const bool by_position = position_trusted_ && params.position_gate > 0.0;
  // The heading: a belief whose heading is not the robot's is a wrong one (large_floor: a belief
  // heading west at a T while the robot drove east left the known graph along the belief's
  // heading, and the nine doors passed going east were never made nodes: the rooms were mapped
  // again later). With a trusted heading the belief's must agree; before, the front end was turned
  // to the belief's (HeadingRealigner, now only for an untrusted heading).
  const bool by_heading = heading_trusted_ && params.heading_gate;
  if (!by_position && !by_heading) return "";
  // Heading-corrected dead reckoning drifts little in a rectilinear building, and the map's node
  // positions come from the same dead reckoning: a state far from it is a look-alike elsewhere
  // (large_floor: a belief at the start node 94 m west of the robot at the east end of the same
  // hallway started a new stretch there, and the whole hallway was mapped twice).
  const double gate = by_position
                          ? params.position_gate + params.position_gate_per_m * std::max(0.0, travel - trusted_travel_)
                          : std::numeric_limits<double>::infinity();
  const Eigen::Vector2d here(robot.x, robot.y);
  const size_t n = localizer->belief().size();
  if (state_positions_.size() != n || state_positions_revision_ != map.revision() ||
      state_positions_states_revision_ != localizer->mapRevision()) {
    state_positions_.assign(n, Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
    state_bins_.resize(n);
    state_beyond_map_.assign(n, false);
    for (size_t s = 0; s < n; ++s) {
      const PomdpLocalizer::State st = localizer->state(s);
      statePosition(map, st, &state_positions_[s]);
      state_bins_[s] = bins.bin(st.heading);
      EdgeExit x;
      state_beyond_map_[s] = st.kind == PomdpLocalizer::State::Node && !map.wayOn(st.id, st.heading, 0.25 * kPi, &x);
    }
    state_positions_revision_ = map.revision();
    state_positions_states_revision_ = localizer->mapRevision();
  }
  // A state with no position (NaN) is never gated out.
  auto within = [&](size_t s, double radius) { return !((state_positions_[s] - here).norm() > radius); };
  // A state at a node heading where no edge leads stands for a robot beyond the known map, on the
  // way out of that node, however far along it. It explains whatever lies ahead as unexplored, more
  // cheaply than an edge whose landmarks are seen a little off (the robot swerving round an
  // obstacle, a hallway offset at a crossing): it is a wrong one where the dead reckoning puts the
  // robot off that way, and a right one where it puts the robot on it, however far from the node.
  const bool by_way_out = by_position && params.update_position_tolerance > 0.0;
  auto near = [&](size_t s) {
    if (!by_way_out || !state_beyond_map_[s]) return within(s, gate);
    double along = 0.0;
    return alongWayOut(params, state_positions_[s], localizer->state(s).heading, here, &along);
  };
  gate_allowed_.resize(n);
  for (size_t s = 0; s < n; ++s) {
    gate_allowed_[s] = near(s) && (!by_heading || state_bins_[s] == heading_bin);
  }
  if (!localizer->restrictTo(gate_allowed_)) {
    return by_position ? "no belief within " + std::to_string(int(std::lround(gate))) +
                             " m of the dead-reckoned position and heading: uniform over the states there"
                       : "no belief with the dead-reckoned heading: uniform over the states with it";
  }
  if (!by_position) return "";
  // A confident belief near the dead-reckoned position: the two agree, the drift allowance restarts.
  const int ml = localizer->mostLikely();
  if (ml >= 0 && localizer->confident() && std::isfinite(state_positions_[size_t(ml)].x()) &&
      within(size_t(ml), params.position_gate)) {
    trusted_travel_ = travel;
  }
  return "";
}

bool DeadReckoningGate::deadReckonedPosition(const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                                             const PassedLandmark& p, const Pose2D& robot, double travel,
                                             Eigen::Vector2d* at) const {
  if (!checks(params)) return false;
  // The landmark lies this far behind the robot along its travel.
  const double back = travel - (p.travel + p.landmark.along);
  const double h = bins.heading(p.heading_bin);
  *at = Eigen::Vector2d(robot.x - back * std::cos(h), robot.y - back * std::sin(h));
  return true;
}

bool DeadReckoningGate::farFromDeadReckoning(const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                                             const Eigen::Vector2d& believed, const PassedLandmark& p,
                                             const Pose2D& robot, double travel) const {
  Eigen::Vector2d at;
  return deadReckonedPosition(params, bins, p, robot, travel, &at) &&
         (at - believed).norm() > params.update_position_tolerance;
}

bool DeadReckoningGate::farFromNode(const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                                    const TopoNode& n, const PassedLandmark& p, const Pose2D& robot,
                                    double travel) const {
  // An opening a node lacks lies beside it, within the reach a node's openings are looked for in
  // (min_node_separation + match_distance), not update_position_tolerance: with the belief a node
  // off, the door is the next node's (large_floor: after U-turns on a hallway of doors 2-3 m apart
  // a door was added to a node 5.7 m from it; room_7_14's door to the node 1.8-1.9 m before the
  // junction that has it; each time a known room was entered again as a new one).
  Eigen::Vector2d at;
  return deadReckonedPosition(params, bins, p, robot, travel, &at) &&
         (at - Eigen::Vector2d(n.pose.x, n.pose.y)).norm() > params.min_node_separation + params.match_distance;
}

bool DeadReckoningGate::alongWayOut(const MapBuilderParams& params, const Eigen::Vector2d& node, double heading,
                                    const Eigen::Vector2d& robot, double* along) {
  const Eigen::Vector2d u = laser_features::unitVector(heading);
  const Eigen::Vector2d v = robot - node;
  *along = v.dot(u);
  const double tolerance = params.update_position_tolerance;
  return std::abs(u.x() * v.y() - u.y() * v.x()) <= tolerance && *along >= -tolerance;
}

DeadReckoningGate::Departure DeadReckoningGate::departure(const MapBuilderParams& params, const TopoNode& n,
                                                          double heading, const Pose2D& robot, double* s) const {
  if (!checks(params)) return Departure::Here;
  // A new stretch starts where the robot is: on the way out of the node, `s` ahead of it. A belief
  // that reaches the node late (it held behind while the robot drove on) starts it as far along
  // as the robot is; one that leads the robot waits for it; one off the way out is wrong.
  double along = 0.0;
  const double tolerance = params.update_position_tolerance;
  if (!alongWayOut(params, Eigen::Vector2d(n.pose.x, n.pose.y), heading, Eigen::Vector2d(robot.x, robot.y), &along)) {
    return Departure::Elsewhere;
  }
  if (along < *s - tolerance) {
    *s = std::max(0.0, along);
    return Departure::NotYet;
  }
  if (along > *s + tolerance) *s = along;
  return Departure::Here;
}

int DeadReckoningGate::twinWithWay(const TopologicalMap& map, const MapBuilderParams& params, uint32_t id,
                                   double heading) const {
  if (!checks(params)) return -1;
  const TopoNode* n = map.node(id);
  if (n == nullptr) return -1;
  int best = -1;
  double best_d = params.update_position_tolerance;
  for (const auto& entry : map.nodes()) {
    const TopoNode& m = entry.second;
    if (m.id == id || m.type != n->type) continue;
    const double d = std::hypot(m.pose.x - n->pose.x, m.pose.y - n->pose.y);
    EdgeExit x;
    if (d <= best_d && map.exitWithHeading(m.id, heading, 0.25 * kPi, &x) && x.other != id) {
      best = int(m.id);
      best_d = d;
    }
  }
  return best;
}

}  // namespace pomdp_topo
