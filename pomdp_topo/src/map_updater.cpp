#include "pomdp_topo/map_updater.h"

#include <algorithm>
#include <cmath>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

NodeOpening sideOpening(double heading, const PassedLandmark& p) {
  NodeOpening o;
  o.bearing = normalizeAngle(heading + (p.landmark.lateral >= 0.0 ? 0.5 : -0.5) * kPi);
  o.skew = p.skew;
  o.offset = std::abs(p.landmark.lateral);
  o.width = p.landmark.width;
  return o;
}

void MapUpdater::update(const ScanRecord& scan, const MapBuilderParams& params, const DeadReckoningGate& gate,
                        const laser_features::HeadingBins& bins, double pass_lag, std::vector<TopoEvent>* events) {
  params_ = &params;
  gate_ = &gate;
  bins_ = bins;
  pass_lag_ = pass_lag;
  events_ = events;
  updateKnownEdge(scan);
}

bool MapUpdater::knownOpeningNear(const TopoEdge& e, double d, const PassedLandmark& p, const ScanRecord& scan,
                                  double bearing, double width) const {
  // Nodes within reach of d along the graph: the edge's ends, and their neighbours as far as the
  // reach goes on (short edges between doors facing each other across a hallway).
  const double reach = params_->min_node_separation + params_->match_distance;
  return knownOpeningNear({{e.source, reach - std::max(0.0, d)}, {e.target, reach - std::max(0.0, e.length - d)}}, p,
                          scan, bearing, width);
}

bool MapUpdater::knownOpeningNear(std::vector<std::pair<uint32_t, double>> todo, const PassedLandmark& p,
                                  const ScanRecord& scan, double bearing, double width) const {
  // The nodes near the opening by the dead reckoning too: the belief may lag or lead by a node
  // (large_floor: room_7_08's door passed in a U-turn at the node before it, 1.66 m from the node
  // that has it; room_7_14's door, 0.8 m from the junction that has it, passed with the belief
  // still on the door node 2.5 m before).
  const double reach = params_->min_node_separation + params_->match_distance;
  Eigen::Vector2d at;
  if (gate_->deadReckonedPosition(*params_, bins_, p, scan.pose, scan.travel, &at)) {
    for (const auto& [id, k] : map_->nodes()) {
      const double gap = (Eigen::Vector2d(k.pose.x, k.pose.y) - at).norm();
      if (gap >= reach) continue;
      // A node listed already by the graph (an edge's end) keeps the larger reach left.
      auto listed = std::find_if(todo.begin(), todo.end(), [&](const auto& t) { return t.first == id; });
      if (listed == todo.end()) {
        todo.push_back({id, reach - gap});
      } else {
        listed->second = std::max(listed->second, reach - gap);
      }
    }
  }
  std::vector<uint32_t> seen;
  while (!todo.empty()) {
    const auto [id, left] = todo.back();
    todo.pop_back();
    if (left < 0.0 || std::find(seen.begin(), seen.end(), id) != seen.end()) continue;
    seen.push_back(id);
    const TopoNode* n = map_->node(id);
    if (n == nullptr) continue;
    for (const NodeOpening& o : n->openings) {
      if (!map_->differentOpenings(o.width, width) && bins_.sameWay(o.bearing, bearing)) return true;
    }
    for (const EdgeExit& x : map_->exits(id)) {
      const TopoEdge* next = map_->edge(x.edge);
      if (next != nullptr) todo.push_back({x.other, left - next->length});
    }
  }
  return false;
}

void MapUpdater::addOpeningsAtNode(const PomdpLocalizer::State& st, const ScanRecord& scan) {
  // A door passed while the belief is at a node that does not know it: a door facing the node's
  // own across the hallway, seen only after a U-turn at a hallway end just past it (institute's
  // printer, 0.2 m from director's; the belief stays at the node through the turn and the first
  // metre back, where updating edges never sees it).
  TopoNode* n = map_->node(st.id);
  if (n == nullptr) return;
  const double reach = params_->min_node_separation + params_->match_distance;
  bool changed = false;
  for (const PassedLandmark& p : scan.passed) {
    if (p.landmark.type != LandmarkType::Opening || !p.landmark.door) continue;
    if (bins_.heading(p.heading_bin) != bins_.heading(bins_.bin(st.heading))) continue;
    const NodeOpening o = sideOpening(st.heading, p);
    if (knownOpeningNear({{n->id, reach}}, p, scan, o.bearing, o.width)) continue;
    if (gate_->farFromNode(*params_, bins_, *n, p, scan.pose, scan.travel)) continue;
    n->openings.push_back(o);
    changed = true;
    event(TopoEvent::Kind::OpeningAdded, "opening added to node " + std::to_string(n->id), int(n->id));
  }
  if (changed) {  // as on an edge (updateKnownEdge)
    map_->touch();
    localizer_->setMap(*map_);
  }
}

void MapUpdater::updateKnownEdge(const ScanRecord& scan) {
  const int ml = localizer_->mostLikely();
  const PomdpLocalizer::State st = localizer_->state(size_t(ml));
  if (st.kind != PomdpLocalizer::State::Edge) {
    last_edge_ = -1;
    if (st.kind == PomdpLocalizer::State::Node) addOpeningsAtNode(st, scan);
    return;
  }
  TopoEdge* e = map_->edge(st.id);
  if (e == nullptr) return;
  if (last_edge_ != int(st.id) || last_forward_ != st.forward) {
    matched_recently_.clear();
    last_offset_ = st.offset;
  }
  bool changed = false;
  for (const PassedLandmark& p : scan.passed) {
    const Passed passed = passedOnEdge(e, st, p, scan);
    if (passed == Passed::Split) return;  // the edge is gone: the next scan starts afresh
    if (passed == Passed::Changed) changed = true;
  }
  if (missedOnEdge(e, st)) changed = true;
  last_edge_ = int(st.id);
  last_forward_ = st.forward;
  last_offset_ = st.offset;
  if (changed) {
    map_->touch();
    localizer_->setMap(*map_);
  }
}

MapUpdater::Passed MapUpdater::passedOnEdge(TopoEdge* e, const PomdpLocalizer::State& st, const PassedLandmark& p,
                                             const ScanRecord& scan) {
  const double dir = st.forward ? 1.0 : -1.0;
  if (bins_.heading(p.heading_bin) != bins_.heading(bins_.bin(st.heading))) return Passed::Nothing;
  if (p.landmark.type == LandmarkType::Corner && p.landmark.confidence < params_->corner_min_confidence)
    return Passed::Nothing;
  // Where on the edge it was passed.
  const double along = p.landmark.along - (scan.travel - p.travel);
  const double d = st.offset + dir * along;
  const double lateral = dir * p.landmark.lateral;
  if (d < -params_->match_distance || d > e->length + params_->match_distance) return Passed::Nothing;
  EdgeLandmark* best = nullptr;
  double best_gap = params_->match_distance;
  for (EdgeLandmark& l : e->landmarks) {
    if (l.type != p.landmark.type || sideOf(l.lateral) != sideOf(lateral)) continue;
    const double gap = std::abs(l.distance - d);
    if (gap <= best_gap) {
      best_gap = gap;
      best = &l;
    }
  }
  if (best != nullptr) {
    // Eq. 4: p_lmap is the running average of the confidences it was observed with.
    best->p_lmap = (best->p_lmap * best->observations + std::min(1.0, p.landmark.confidence)) / (best->observations + 1);
    best->observations += 1;
    matched_recently_.push_back(uint32_t(std::lround(best->distance * 1000.0)));
    return Passed::Nothing;
  }
  const bool near_end = d < params_->min_node_separation || d > e->length - params_->min_node_separation;
  if (p.landmark.type == LandmarkType::Corner) {
    if (p.landmark.confidence < params_->landmark_add_confidence) return Passed::Nothing;
    EdgeLandmark l;
    l.type = LandmarkType::Corner;
    l.distance = std::min(std::max(d, 0.0), e->length);
    l.lateral = lateral;
    l.orientation = normalizeAngle(p.landmark.orientation + (st.forward ? 0.0 : kPi));
    l.p_lmap = std::min(1.0, p.landmark.confidence);
    l.observations = 1;
    e->landmarks.push_back(l);
    e->sortLandmarks();
    matched_recently_.push_back(uint32_t(std::lround(l.distance * 1000.0)));
    event(TopoEvent::Kind::LandmarkAdded, "corner landmark added to edge " + std::to_string(e->id), -1, -1, int(e->id));
    return Passed::Changed;
  } else if (!near_end && !p.landmark.door) {
    // A wide opening in the middle of a known stretch: a junction the first pass did not see is
    // unlikely (hallway branches are seen from afar); a gap beside a pillar or a wide view into
    // a room is not. Not a node.
    return Passed::Nothing;
  } else if (knownOpeningNear(*e, d, p, scan, sideOpening(st.heading, p).bearing, p.landmark.width)) {
    // A door a node near here already has: the belief is a little off along the edge (institute:
    // office_10's door, 0.84 m from seminar's across the hallway, was added to seminar's node as
    // a second, unexplored opening, and the room was explored twice).
    return Passed::Nothing;
  } else if (!near_end) {
    // A new opening creates a new node (an unknown door on a known stretch), where the dead
    // reckoning agrees.
    Eigen::Vector2d believed;
    if (map_->pointOnEdge(*e, d, &believed) &&
        gate_->farFromDeadReckoning(*params_, bins_, believed, p, scan.pose, scan.travel)) {
      return Passed::Nothing;
    }
    const double heading = st.heading;
    splitEdgeWithDoor(e->id, d, sideOpening(heading, p), p.landmark.door);
    return Passed::Split;
  } else {
    // An opening at an end node that the node does not know yet.
    const uint32_t nid = d < 0.5 * e->length ? e->source : e->target;
    TopoNode* n = map_->node(nid);
    // A wide one at a door node is a view into a room or a gap beside furniture (as in the middle
    // of a stretch, above), not a branch: institute's hall_north got 1.8-2.1 m "openings" at two
    // door nodes, which the exploration turned round for five times before giving them up.
    if (n->type != NodeType::Junction && !p.landmark.door) return Passed::Nothing;
    const NodeOpening o = sideOpening(st.heading, p);
    if (!map_->hasOpeningToward(nid, o.bearing) && !gate_->farFromNode(*params_, bins_, *n, p, scan.pose, scan.travel)) {
      n->openings.push_back(o);
      event(TopoEvent::Kind::OpeningAdded, "opening added to node " + std::to_string(nid), int(nid));
      return Passed::Changed;
    }
  }
  return Passed::Nothing;
}

bool MapUpdater::missedOnEdge(TopoEdge* e, const PomdpLocalizer::State& st) {
  const double dir = st.forward ? 1.0 : -1.0;
  bool changed = false;
  // Eq. 5: expected landmarks passed without being seen: observed confidence 0.
  const double lag = pass_lag_ + params_->match_distance;
  const double from = last_offset_ - dir * lag;
  const double to = st.offset - dir * lag;
  const double lo = std::min(from, to), hi = std::max(from, to);
  if (last_edge_ == int(st.id) && last_forward_ == st.forward && hi > lo) {
    for (auto it = e->landmarks.begin(); it != e->landmarks.end();) {
      const uint32_t key = uint32_t(std::lround(it->distance * 1000.0));
      const bool seen = std::find(matched_recently_.begin(), matched_recently_.end(), key) != matched_recently_.end();
      if (it->distance > lo && it->distance <= hi && !seen) {
        it->p_lmap = it->p_lmap * it->observations / (it->observations + 1);
        it->observations += 1;
        if (it->p_lmap < params_->p_lmap_min && int(it->observations) >= params_->p_lmap_min_observations) {
          event(TopoEvent::Kind::LandmarkDeleted,
                "landmark at " + std::to_string(it->distance) + " m on edge " + std::to_string(e->id) + " deleted (p_lmap " +
                    std::to_string(it->p_lmap) + ")",
                -1, -1, int(e->id));
          it = e->landmarks.erase(it);
          changed = true;
          continue;
        }
      }
      ++it;
    }
  }
  return changed;
}

void MapUpdater::splitEdgeWithDoor(uint32_t edge_id, double distance, const NodeOpening& opening, bool is_door) {
  const TopoEdge old = *map_->edge(edge_id);
  const TopoNode& a = *map_->node(old.source);
  TopoNode door;
  door.type = is_door ? NodeType::Door : NodeType::Junction;
  door.pose = Pose2D{a.pose.x + distance * std::cos(old.heading), a.pose.y + distance * std::sin(old.heading), old.heading};
  door.openings.push_back(opening);
  const uint32_t id = map_->addNode(door);
  std::vector<EdgeLandmark> first, second;
  for (EdgeLandmark l : old.landmarks) {
    if (l.distance <= distance) {
      first.push_back(l);
    } else {
      l.distance -= distance;
      second.push_back(l);
    }
  }
  map_->removeEdge(edge_id);
  const uint32_t e1 = map_->addEdge(old.source, id, old.heading, distance, first);
  map_->addEdge(id, old.target, old.heading, std::max(0.0, old.length - distance), second);
  event(TopoEvent::Kind::NodeCreated,
        "node " + std::to_string(id) + " (" + pomdp_topo::toString(door.type) + ") created on known edge " +
            std::to_string(edge_id) + ", which is split",
        int(id), int(old.source), int(edge_id));
  // The robot is on one of the halves, where the belief was.
  const int ml = localizer_->mostLikely();
  const PomdpLocalizer::State st = localizer_->state(size_t(ml));
  localizer_->setMap(*map_);
  if (st.offset <= distance) {
    localizer_->resetToEdge(e1, st.offset, st.forward);
  } else {
    localizer_->resetToEdge(map_->nextEdgeId() - 1, st.offset - distance, st.forward);
  }
  last_edge_ = -1;
}

}  // namespace pomdp_topo
