// MapBuilder in Localized mode: the POMDP on the known graph, the map updated while it is
// confident, and where the belief leaves the graph (a new stretch, a hallway's end, a twin node).
// The class: map_builder.h.
#include "pomdp_topo/map_builder.h"

#include <algorithm>
#include <cmath>

namespace pomdp_topo {

using laser_features::kPi;

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

MapBuilder::BeyondStep MapBuilder::resetBeyondGraph(const std::string& where, uint32_t node) {
  event(TopoEvent::Kind::BeliefReset, where + ": it is wrong; reset to uniform", int(node));
  localizer_->setUniform();
  beyond_ = 0.0;
  return BeyondStep::SkipObservation;
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
    return resetBeyondGraph("the belief puts the robot past the end of the hallway at node " + std::to_string(st.id),
                            st.id);
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
    return resetBeyondGraph("the belief would leave the known graph at node " + std::to_string(st.id) +
                                ", where the dead reckoning does not put the robot",
                            st.id);
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
