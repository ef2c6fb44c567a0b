// MapBuilder in Frontier mode: the stretch being followed, the nodes made along it (side openings,
// turns, hallway ends) and the fingerprints they get. The class: map_builder.h.
#include "pomdp_topo/map_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {
// A tracked opening shows the way `bearing` (rad) when its normal lies along it, pointing either
// way (into the room or out of it), within 0.5 rad.
bool showsWay(const FrontEnd::Track& t, double bearing) {
  const double dth = std::abs(normalizeAngle(t.orientation - bearing));
  return dth <= 0.5 || std::abs(dth - kPi) <= 0.5;
}
}  // namespace

// ---- Frontier ------------------------------------------------------------------------------

void MapBuilder::processFrontier(const Scan& scan, const FrontEnd& fe) {
  if (!params_.mapping) {  // localization only: nothing to build, look for the graph again
    mode_ = Mode::Localized;
    localizer_->setUniform();
    processLocalized(scan);
    return;
  }
  const double s = s_base_ + scan.travel - travel_base_;
  travel_since_localized_ += std::abs(s - s_);  // the loop gate grows with the unlocalized travel
  s_ = s;
  frontier_pose_ = scan.pose;
  frontier_travel_ = scan.travel;
  // Landmarks passed on this stretch (all happened before the scan's turn, if any).
  for (const PassedLandmark& p : scan.passed) {
    if (mode_ != Mode::Frontier) break;  // a node created a loop hypothesis: the rest is verified
    if (p.heading_bin != frontier_bin_) continue;
    const double pos = s_base_ + (p.travel - travel_base_) + p.landmark.along;
    if (pos < -params_.match_distance) continue;  // behind the node the stretch starts at
    if (p.landmark.type == LandmarkType::Corner) {
      if (p.landmark.confidence < params_.corner_min_confidence) continue;
      EdgeLandmark l;
      l.type = LandmarkType::Corner;
      l.distance = std::max(0.0, pos);
      l.lateral = p.landmark.lateral;
      l.orientation = p.landmark.orientation;
      l.p_lmap = p.landmark.confidence;
      l.observations = 1;
      pending_.push_back(l);
      continue;
    }
    const NodeOpening o = sideOpening(binHeading(frontier_bin_), p);
    const NodeType type = p.landmark.door ? NodeType::Door : NodeType::Junction;
    createNode(type, std::max(0.0, pos), scan, fe, {o});
  }
  if (mode_ == Mode::LoopCheck) {
    // The scan's remaining content belongs to the verification (its passed landmarks were
    // scored against the hypotheses from the node on).
    Scan rest = scan;
    rest.passed.clear();
    for (const PassedLandmark& p : scan.passed) {
      if (p.travel > loop_.travel0() - 1e-9) rest.passed.push_back(p);
    }
    processLoopCheck(rest, fe);
    return;
  }
  for (const Action& a : scan.actions) {
    if (a.kind != Action::Turn) continue;
    frontierTurn(a.turn_bins, scan, fe);
    if (mode_ != Mode::Frontier) break;
  }
}

int MapBuilder::nodeBesideRobot(const NodeOpening& door, const FrontEnd& fe) {
  if (mode_ != Mode::Frontier || !params_.mapping || !std::isfinite(door.bearing)) return currentNode();
  // The robot stops at a door to enter it before the front end passes it (tracks.pass_lag beyond it); a
  // door taken for a node's farther back would be unexplored at the node its passing makes later,
  // and the room behind it mapped again.
  Scan here;
  here.pose = frontier_pose_;
  here.travel = frontier_travel_;
  here.heading_bin = frontier_bin_;
  // It opens into a room: a door by the width rules with a room behind, a junction only if wider.
  const NodeType type = params_.rules.opensAsDoor(door.width, true) ? NodeType::Door : NodeType::Junction;
  return int(createNode(type, s_ + trackedAlong(door, fe), here, fe, {door}));
}

double MapBuilder::trackedAlong(const NodeOpening& door, const FrontEnd& fe) const {
  // The door's node lies where passing it would put it: at the tracked opening on the door's side,
  // facing its way, within match_distance along (the most a passed landmark lies from its match).
  const double h = binHeading(frontier_bin_);
  const Eigen::Vector2d here(frontier_pose_.x, frontier_pose_.y), along_dir = laser_features::unitVector(h);
  const double side = normalizeAngle(door.bearing - h);
  double best = std::numeric_limits<double>::infinity(), along = 0.0;
  for (const auto& t : fe.tracks()) {
    if (t.type != LandmarkType::Opening || t.sightings < fe_params_.tracks.min_sightings) continue;
    const Eigen::Vector2d d = t.position - here;
    const double a = d.dot(along_dir), lateral = along_dir.x() * d.y() - along_dir.y() * d.x();
    if (std::abs(a) > params_.match_distance || lateral * side <= 0.0 || !showsWay(t, door.bearing)) continue;
    if (std::abs(a) < best) {
      best = std::abs(a);
      along = a;
    }
  }
  return along;
}

void MapBuilder::frontierTurn(int k, const Scan& scan, const FrontEnd& fe) {
  const int bins = fe_params_.heading_bins;
  const int new_bin = ((frontier_bin_ + k) % bins + bins) % bins;
  if (2 * std::abs(k) == bins) {  // U-turn: a hallway end (or back at the node)
    uint32_t n = from_node_;
    if (s_ > params_.node_radius) {
      n = createNode(NodeType::HallwayEnd, s_, scan, fe, {});
    } else {
      double& end = end_beyond_[{n, frontier_bin_}];
      end = std::max(end, s_);
      // Still at the node, turned to where it has no way (the start node, the robot having faced a
      // wall): the stretch to map starts from the node the other way, not the known map.
      EdgeExit exit;
      if (mode_ == Mode::Frontier && !map_->wayOn(n, binHeading(new_bin), 0.25 * kPi, &exit)) {
        startFrontier(n, new_bin, 0.0, scan.travel);
        return;
      }
    }
    if (mode_ == Mode::LoopCheck) return;
    becomeLocalizedAt(n, new_bin);
    return;
  }
  NodeOpening branch;
  branch.bearing = binHeading(new_bin);
  branch.offset = 0.0;
  branch.width = 0.0;  // not measured unless a tracked opening shows it (below)
  branch.explored = true;
  {
    // The branch as the laser saw it: a tracked opening near the turn whose normal points the new way.
    const Eigen::Vector2d here(scan.pose.x, scan.pose.y);
    double best = 2.5;
    for (const auto& t : fe.tracks()) {
      if (t.type != LandmarkType::Opening || t.sightings < fe_params_.tracks.min_sightings) continue;
      const Eigen::Vector2d d = t.position - here;
      const double along = d.dot(laser_features::unitVector(branch.bearing));
      if (d.norm() > best || along < 0.3) continue;
      if (!showsWay(t, branch.bearing)) continue;
      best = d.norm();
      branch.offset = along;
      branch.width = t.width;
    }
  }
  uint32_t n = from_node_;
  if (s_ > params_.node_radius) {
    departure_bin_ = new_bin;  // a loop hypothesis is verified along the way the robot turned to
    n = createNode(NodeType::Junction, s_, scan, fe, {branch});
    departure_bin_ = -1;
    if (mode_ == Mode::LoopCheck) return;
  } else {
    TopoNode* node = map_->node(n);
    if (!map_->hasOpeningToward(n, branch.bearing)) node->openings.push_back(branch);
    if (node->type == NodeType::Start || node->type == NodeType::Door) node->type = NodeType::Junction;
  }
  EdgeExit exit;
  if (map_->wayOn(n, binHeading(new_bin), 0.25 * kPi, &exit)) {
    becomeLocalizedAt(n, new_bin);
  } else {
    startFrontier(n, new_bin, 0.0, scan.travel);
  }
}

uint32_t MapBuilder::createNode(NodeType type, double pos, const Scan& scan, const FrontEnd& fe,
                                const std::vector<NodeOpening>& openings) {
  const double h = binHeading(frontier_bin_);
  // Two openings on the same side whose centres are nearer than half their widths' sum would
  // overlap: one opening seen twice (institute's hall_link mouth, 2.2 m wide, made two junction
  // nodes 0.97 m apart; the second's "branch" sent the robot round for 600 s and lost it).
  // A door recorded at a junction lies up to min_node_separation from the junction's centre (its
  // branch): seen again on a new stretch from that junction it is the same door (large_floor:
  // room_7_14's door, across the T where a stem meets hall_3, entered from the junction made at the
  // turn and recorded there; passed 0.98 m from it on a new stretch 5,600 s later, it became a
  // door node of its own and the room was entered again).
  double join = params_.min_node_separation;
  if (const TopoNode* last = map_->node(from_node_)) {
    const double slack = last->type == NodeType::Junction ? params_.min_node_separation : 0.0;
    for (const NodeOpening& o : openings) {
      for (const NodeOpening& k : last->openings) {
        if (!headingBins().sameWay(k.bearing, o.bearing) || o.width <= 0.0 || k.width <= 0.0) continue;
        join = std::max(join, 0.5 * (o.width + k.width) + (map_->differentOpenings(o.width, k.width) ? 0.0 : slack));
      }
    }
  }
  const double back = s_ - pos;  // the node lies this far behind the robot along the heading
  const Pose2D pose{scan.pose.x - back * std::cos(h), scan.pose.y - back * std::sin(h), h};
  // How far from the last node: the travel since the stretch left it, or, with the dead reckoning
  // in the map's frame, where it puts the node if nearer. The travel is counted from where the
  // belief reached the node, up to a node radius before it (large_floor: room_7_14's door, 0.6 m
  // from the junction that has it by the dead reckoning, was 1.77 m by the travel, made a door node
  // of its own and the room was entered again).
  double from_last = pos;
  if (const TopoNode* last = map_->node(from_node_); last != nullptr && gate_.checks(params_)) {
    from_last = std::min(pos, std::hypot(pose.x - last->pose.x, pose.y - last->pose.y));
  }
  if (from_last < join) {
    TopoNode* node = map_->node(from_node_);
    for (const NodeOpening& o : openings) {
      if (!map_->hasOpeningToward(from_node_, o.bearing)) node->openings.push_back(o);
    }
    if (node->type == NodeType::Start) node->type = type;
    if (node->type == NodeType::Door && type == NodeType::Junction) node->type = NodeType::Junction;
    map_->touch();
    return from_node_;
  }
  TopoNode node;
  node.type = type;
  node.pose = pose;
  node.openings = openings;
  node.fingerprint = fingerprintAt(Eigen::Vector2d(node.pose.x, node.pose.y), fe);
  const uint32_t id = map_->addNode(node);
  std::vector<EdgeLandmark> on_edge, rest;
  for (EdgeLandmark l : pending_) {
    if (l.distance <= pos) {
      on_edge.push_back(l);
    } else {
      l.distance -= pos;
      rest.push_back(l);
    }
  }
  pending_ = rest;
  map_->addEdge(from_node_, id, h, pos, on_edge);
  const uint32_t previous = from_node_;
  std::string why = openings.empty() ? "a hallway end" : "";
  for (const NodeOpening& o : openings) {
    why += (o.width > 0.0 ? "an opening " + std::to_string(o.width).substr(0, 4) + " m wide" : "a turn") +
           std::string(normalizeAngle(o.bearing - h) > 0.0 ? " on the left" : " on the right");
  }
  event(TopoEvent::Kind::NodeCreated,
        "node " + std::to_string(id) + " (" + pomdp_topo::toString(type) + ") created " + std::to_string(pos).substr(0, 5) +
            " m from node " + std::to_string(previous) + ": " + why,
        int(id), int(previous));
  from_node_ = id;
  s_base_ -= pos;
  s_ -= pos;
  refreshLocalizer();
  localizer_->resetToNode(id, h);
  if (type == NodeType::Door || type == NodeType::Junction) startLoopCheck(id, previous, scan);
  return id;
}

Fingerprint MapBuilder::fingerprintAt(const Eigen::Vector2d& position, const FrontEnd& fe) const {
  Fingerprint f;
  for (const auto& t : fe.tracks()) {
    if (t.sightings < fe_params_.tracks.min_sightings) continue;
    const Eigen::Vector2d d = t.position - position;
    if (d.norm() > params_.fingerprint_radius || d.norm() < 1e-6) continue;
    FingerprintEntry e;
    e.kind = t.type == LandmarkType::Corner ? FingerprintEntry::Corner : FingerprintEntry::Opening;
    e.bearing = std::atan2(d.y(), d.x());
    f.entries.push_back(e);
  }
  f.normalize();
  return f;
}

}  // namespace pomdp_topo
