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

MapBuilder::MapBuilder(TopologicalMap* map, PomdpLocalizer* localizer, const MapBuilderParams& params)
    : map_(map), localizer_(localizer), params_(params), updater_(map, localizer) {
  map_->setBuildingRules(params_.rules);
  map_->setHeadingBins(headingBins());
}

const char* MapBuilder::toString(Mode mode) {
  switch (mode) {
    case Mode::Frontier: return "frontier";
    case Mode::Localized: return "localized";
    case Mode::LoopCheck: return "loop_check";
  }
  return "unknown";
}

double MapBuilder::binHeading(int bin) const { return headingBins().heading(bin); }

int MapBuilder::binOf(double heading) const { return headingBins().bin(heading); }

void MapBuilder::refreshLocalizer() { localizer_->setMap(*map_); }

std::vector<TopoEvent> MapBuilder::takeEvents() {
  std::vector<TopoEvent> out;
  out.swap(events_);
  return out;
}

bool MapBuilder::confident() const {
  if (mode_ != Mode::Localized) return mode_ == Mode::Frontier;
  return localizer_->confident();
}

int MapBuilder::currentNode() const {
  if (mode_ != Mode::Localized) return int(from_node_);
  const int ml = localizer_->mostLikely();
  if (ml < 0) return -1;
  const auto& st = localizer_->state(size_t(ml));
  if (st.kind == PomdpLocalizer::State::Node) return int(st.id);
  const TopoEdge* e = map_->edge(st.id);
  if (e == nullptr) return -1;
  const bool near_target = st.forward ? st.offset > 0.5 * e->length : st.offset < 0.5 * e->length;
  return int(near_target == st.forward ? e->target : e->source);
}

std::string MapBuilder::loopEvidence() const { return loop_.evidence(); }

double MapBuilder::loopLogOdds() const { return loop_.logOdds(); }

void MapBuilder::start(const FrontEnd& fe) {
  fe_params_ = fe.params();
  map_->setHeadingBins(headingBins());
  loop_.clear();
  buffer_.clear();
  relocation_pending_ = false;
  relocated_ = false;
  end_beyond_.clear();
  localizer_->clearOpenWays();
  // A map built from here on is in the dead reckoning's frame; a loaded one is not (until a jump's
  // relocation moves the front end onto it).
  gate_.setTrusted(map_->empty(), map_->empty(), fe.travel());
  if (map_->empty()) {
    if (!params_.mapping) {
      mode_ = Mode::Localized;
      refreshLocalizer();
      return;
    }
    TopoNode start;
    start.type = NodeType::Start;
    start.pose = fe.pose();
    const uint32_t id = map_->addNode(start);
    event(TopoEvent::Kind::NodeCreated, "node " + std::to_string(id) + " (start) created", int(id));
    refreshLocalizer();
    startFrontier(id, fe.headingBin(), 0.0, fe.travel());
    return;
  }
  mode_ = Mode::Localized;
  refreshLocalizer();
  localizer_->setUniform();
}

void MapBuilder::startFrontier(uint32_t node, int bin, double s, double travel) {
  localizer_->clearOpenWays();  // the way left open after an odometry jump (if any) is being mapped
  mode_ = Mode::Frontier;
  from_node_ = node;
  frontier_bin_ = bin;
  s_ = s;
  s_base_ = s;
  travel_base_ = travel;
  pending_.clear();
  localizer_->resetToNode(node, binHeading(bin));
}

void MapBuilder::becomeLocalizedAt(uint32_t node, int bin) {
  mode_ = Mode::Localized;
  refreshLocalizer();
  localizer_->resetToNode(node, binHeading(bin));
  beyond_ = 0.0;
  updater_.forget();
  travel_since_localized_ = 0.0;
}

void MapBuilder::odometryJump(const FrontEnd& fe) {
  if (mode_ == Mode::LoopCheck) decideLoop(false, fe);  // its evidence is void; the new node stays
  if (mode_ == Mode::Frontier && params_.mapping) {
    // Reopen the way the frontier went (a branch taken was recorded explored when the robot turned).
    const double bearing = binHeading(frontier_bin_);
    TopoNode* n = map_->node(from_node_);
    if (n != nullptr) {
      bool found = false;
      for (NodeOpening& o : n->openings) {
        if (headingBins().sameWay(o.bearing, bearing)) {
          o.explored = false;
          found = true;
        }
      }
      NodeOpening o;
      o.bearing = bearing;
      if (!found) map_->recordOpening(from_node_, o);
      n->explored = false;
      localizer_->addOpenWay(from_node_, bearing);
      event(TopoEvent::Kind::OdometryJump,
            "odometry jump on the frontier from node " + std::to_string(from_node_) + ": that way is left unexplored",
            int(from_node_));
    }
  }
  mode_ = Mode::Localized;
  gate_.lose();  // the dead reckoning no longer says where the robot is on the map
  refreshLocalizer();
  localizer_->setUniform();
  beyond_ = 0.0;
  updater_.forget();
  travel_since_localized_ = 0.0;
  relocation_pending_ = true;
  relocated_ = false;
  event(TopoEvent::Kind::OdometryJump, "odometry jump: the robot was moved; belief uniform over the known graph");
}

bool MapBuilder::takeRelocatedPosition(Eigen::Vector2d* position) {
  if (!relocated_) return false;
  relocated_ = false;
  *position = relocated_position_;
  return true;
}

void MapBuilder::skipTravel(double metres) {
  if (!std::isfinite(metres)) return;
  travel_base_ += metres;
  loop_.skipTravel(metres);
}

void MapBuilder::process(const std::vector<Action>& actions, const Observation& observation,
                         const std::vector<PassedLandmark>& passed, const FrontEnd& fe) {
  Scan scan{actions, observation, passed, fe.travel(), fe.pose(), fe.headingBin()};
  dispatch(scan, fe);
}

void MapBuilder::dispatch(const Scan& scan, const FrontEnd& fe) {
  switch (mode_) {
    case Mode::Frontier: processFrontier(scan, fe); break;
    case Mode::Localized: processLocalized(scan); break;
    case Mode::LoopCheck: processLoopCheck(scan, fe); break;
  }
}

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

// ---- Loop closing (Tapus & Siegwart: two belief peaks tracked until one remains) -------------

bool MapBuilder::startLoopCheck(uint32_t new_node, uint32_t previous_node, const Scan& scan) {
  const int go_bin = departure_bin_ >= 0 ? departure_bin_ : frontier_bin_;
  const double gate = params_.loop_gate_base + params_.loop_gate_per_m * travel_since_localized_;
  // scan.travel - s_: the travel when the robot was at the new node.
  if (!loop_.begin(*map_, params_, headingBins(), new_node, previous_node, binHeading(frontier_bin_), go_bin, gate,
                   scan.travel - s_)) {
    return false;
  }
  mode_ = Mode::LoopCheck;
  buffer_.clear();
  std::string names;
  for (const uint32_t c : loop_.candidates()) names += " " + std::to_string(c);
  event(TopoEvent::Kind::LoopHypothesis,
        "loop hypothesis: node " + std::to_string(new_node) + " may be node(s)" + names + "; map building paused",
        int(new_node));
  return true;
}

void MapBuilder::processLoopCheck(const Scan& scan, const FrontEnd& fe) {
  buffer_.push_back(scan);
  const bool turned =
      loop_.observe(*map_, params_, headingBins(), fe_params_.tracks.pass_lag, scan.passed, scan.actions, scan.travel);
  const double u = scan.travel - loop_.travel0();
  const double odds = loopLogOdds();
  if (odds >= params_.loop_decision_log_odds) {
    decideLoop(true, fe);
  } else if (-odds >= params_.loop_decision_log_odds) {
    decideLoop(false, fe);
  } else if (turned || u >= params_.loop_verify_distance) {
    decideLoop(odds > 0.0, fe);
  }
}

void MapBuilder::decideLoop(bool old_wins, const FrontEnd& fe) {
  std::vector<Scan> scans;
  scans.swap(buffer_);
  if (old_wins) {
    const uint32_t keep = loop_.bestNode();
    const double odds = loopLogOdds();
    const std::string evidence = loopEvidence();
    loop_.clear();
    std::vector<std::pair<uint32_t, uint32_t>> zipped;
    // Zips only within the position gate (when on): positions share the dead reckoning's frame.
    map_->mergeNodes(keep, loop_.newNode(), &zipped,
                     params_.position_gate > 0.0 ? params_.position_gate : std::numeric_limits<double>::infinity());
    loops_.emplace_back(keep, loop_.newNode());
    event(TopoEvent::Kind::LoopClosed,
          "loop closed: node " + std::to_string(loop_.newNode()) + " merged into node " + std::to_string(keep) +
              " (log odds " + std::to_string(odds) + "; " + evidence + ")",
          int(loop_.newNode()), int(keep));
    for (const auto& [kept, dropped] : zipped) {
      event(TopoEvent::Kind::NodesMerged,
            "node " + std::to_string(dropped) + " merged into node " + std::to_string(kept) +
                ": the same place, on the stretch the loop closed along",
            int(dropped), int(kept));
    }
    // Continue on the known graph from the old node, replaying the motion since.
    becomeLocalizedAt(keep, loop_.bin());
    for (const Scan& s : scans) {
      for (const Action& a : s.actions) localizer_->predict(a);
    }
    if (!scans.empty()) localizer_->update(scans.back().observation);
    pending_.clear();
    return;
  }
  ++loops_rejected_;
  event(TopoEvent::Kind::LoopRejected,
        "loop hypothesis rejected: node " + std::to_string(loop_.newNode()) + " is a new place (log odds " +
            std::to_string(loopLogOdds()) + "; " + loopEvidence() + ")",
        int(loop_.newNode()));
  loop_.clear();
  if (loop_.bin() != frontier_bin_) {
    // Turned at the new junction: the new stretch starts there, along the branch taken.
    startFrontier(loop_.newNode(), loop_.bin(), 0.0, loop_.travel0());
  } else {
    mode_ = Mode::Frontier;
  }
  for (const Scan& s : scans) dispatch(s, fe);
}

// ---- Localized ---------------------------------------------------------------------------------

void MapBuilder::processLocalized(const Scan& scan) {
  double travelled = 0.0;
  for (const Action& a : scan.actions) {
    const bool was_sure = localizer_->confident();
    localizer_->predict(a);
    if (a.kind == Action::Travel) travelled += a.distance;
    const BeyondStep step = was_sure && params_.mapping ? stepBeyondGraph(a, scan) : BeyondStep::OnGraph;
    if (step == BeyondStep::LeftGraph) return;
    if (step == BeyondStep::SkipObservation) continue;
    if (step == BeyondStep::OnGraph) beyond_ = 0.0;  // at an end (ObserveAtEnd) beyond_ keeps counting
    localizer_->update(scan.observation);
  }
  if (const std::string said = gate_.gate(*map_, localizer_, params_, headingBins(), scan.pose, scan.travel,
                                        scan.heading_bin);
      !said.empty()) {
    event(TopoEvent::Kind::BeliefGated, said);
  }
  const int ml = localizer_->mostLikely();
  if (ml < 0) return;
  const bool sure = localizer_->confident();
  travel_since_localized_ = sure ? 0.0 : travel_since_localized_ + std::abs(travelled);
  // Relocalized after an odometry jump: the map's position of the most likely state, once it
  // holds at least half the belief (a merely low entropy over a few states is not enough to move
  // the map builder's position).
  if (sure && relocation_pending_ && localizer_->belief()[size_t(ml)] >= 0.5) {
    Eigen::Vector2d p;
    if (statePosition(*map_, localizer_->state(size_t(ml)), &p)) {
      relocation_pending_ = false;
      relocated_ = true;
      relocated_position_ = p;
      gate_.relocated(scan.travel);  // the caller moves the front end there (takeRelocatedPosition)
      event(TopoEvent::Kind::Relocalized, "relocalized after the odometry jump");
    }
  }
  if (sure && params_.mapping && beyond_ == 0.0) updater_.update(scan, params_, gate_, headingBins(), fe_params_.tracks.pass_lag, &events_);
}

// Predicted to be at a node heading where no edge leads: an unexplored branch (the map cannot
// predict what the robot sees, so the observation is not used; past leave_graph_distance a new
// stretch starts there), or a hallway's end (a hallway-end node, a node the robot turned round just
// past, the start with start_node_closed; no opening that way). At an end the map predicts the
// wall: the observation is used, and travel through the wall means the belief is wrong (not using
// it there let a belief stand at a hallway's far end while the robot turned round at the other).
MapBuilder::BeyondStep MapBuilder::stepBeyondGraph(const Action& a, const Scan& scan) {
  const int ml = localizer_->mostLikely();
  if (ml < 0) return BeyondStep::OnGraph;
  const PomdpLocalizer::State st = localizer_->state(size_t(ml));
  EdgeExit x;
  if (st.kind != PomdpLocalizer::State::Node || map_->wayOn(st.id, st.heading, 0.25 * kPi, &x) ||
      !(localizer_->belief()[size_t(ml)] > 0.5))
    return BeyondStep::OnGraph;
  const TopoNode* at = map_->node(st.id);
  const auto end = end_beyond_.find({st.id, binOf(st.heading)});
  const bool opening = map_->hasOpeningToward(st.id, st.heading);
  const bool closed = !opening && (at->type == NodeType::HallwayEnd || end != end_beyond_.end() ||
                                   (at->type == NodeType::Start && params_.start_node_closed));
  // The travel counts for this state only: another one the belief moves to starts at 0.
  if (beyond_state_ != ml) beyond_ = 0.0;
  beyond_state_ = ml;
  if (a.kind == Action::Travel) beyond_ = std::max(0.0, beyond_ + a.distance);
  const double limit = params_.leave_graph_distance + (end != end_beyond_.end() ? end->second : 0.0);
  if (closed) {
    if (beyond_ < limit) return BeyondStep::ObserveAtEnd;
    event(TopoEvent::Kind::BeliefReset,
          "the belief puts the robot past the end of the hallway at node " + std::to_string(st.id) +
              ": it is wrong; reset to uniform",
          int(st.id));
    localizer_->setUniform();
    beyond_ = 0.0;
    return BeyondStep::SkipObservation;
  }
  if (beyond_ < limit) return BeyondStep::SkipObservation;
  if (mergeTwin(st)) return BeyondStep::SkipObservation;
  double s = beyond_;
  const Departure where = departure(*at, st.heading, scan.pose, &s);
  if (where == Departure::NotYet) {  // the belief leads the robot out: on when it is there
    beyond_ = s;
    return BeyondStep::SkipObservation;
  }
  if (where == Departure::Elsewhere) {
    event(TopoEvent::Kind::BeliefReset,
          "the belief would leave the known graph at node " + std::to_string(st.id) +
              ", where the dead reckoning does not put the robot: it is wrong; reset to uniform",
          int(st.id));
    localizer_->setUniform();
    beyond_ = 0.0;
    return BeyondStep::SkipObservation;
  }
  event(TopoEvent::Kind::NewStretch, "leaving the known graph at node " + std::to_string(st.id) + ": new stretch", int(st.id));
  startFrontier(st.id, binOf(st.heading), s, scan.travel);
  beyond_ = 0.0;
  return BeyondStep::LeftGraph;
}

// A node the belief would leave the graph at, though a known node at its place by the dead
// reckoning has the way on, is that node recorded twice (a crossing reached down a stem that goes
// on into an unexplored one starts no loop check): merged, and on along the twin's edge.
bool MapBuilder::mergeTwin(const PomdpLocalizer::State& st) {
  const int twin = gate_.twinWithWay(*map_, params_, st.id, st.heading);
  if (twin < 0) return false;
  std::vector<std::pair<uint32_t, uint32_t>> zipped;
  map_->mergeNodes(uint32_t(twin), st.id, &zipped, params_.position_gate);
  event(TopoEvent::Kind::NodesMerged,
        "node " + std::to_string(st.id) + " merged into node " + std::to_string(twin) +
            ": the same place by the dead reckoning, and it has the way on",
        int(st.id), twin);
  for (const auto& [kept, dropped] : zipped) {
    event(TopoEvent::Kind::NodesMerged,
          "node " + std::to_string(dropped) + " merged into node " + std::to_string(kept) +
              ": the same place, on the stretch beyond",
          int(dropped), int(kept));
  }
  Action on;
  on.kind = Action::Travel;
  on.distance = beyond_;
  becomeLocalizedAt(uint32_t(twin), binOf(st.heading));
  localizer_->predict(on);
  return true;
}

MapBuilder::Departure MapBuilder::departure(const TopoNode& n, double heading, const Pose2D& robot, double* s) const {
  return gate_.departure(params_, n, heading, robot, s);
}

}  // namespace pomdp_topo
