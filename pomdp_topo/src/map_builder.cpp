// MapBuilder: construction, start, odometry jumps, the queries, and each scan handed to its mode's
// code (map_builder_frontier.cpp, map_builder_localized.cpp, map_builder_loop_check.cpp).
#include "pomdp_topo/map_builder.h"

#include <cmath>

namespace pomdp_topo {

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

}  // namespace pomdp_topo
