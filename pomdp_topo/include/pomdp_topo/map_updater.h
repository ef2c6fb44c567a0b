// The known map kept up to date while the belief is confident on it (Tomatis et al. 2001, section
// 3.3): the landmarks passed along the belief's edge update their p_lmap (eqs. 4-5), confident
// unknown corners are added, landmarks that fall below p_lmap_min are deleted, an unknown door in
// the middle of a known stretch splits its edge with a door node (where the dead reckoning agrees),
// and an opening a node lacks is added to it. Never while unconfident (MapBuilder calls it only then).
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "laser_features/building_axes.h"
#include "pomdp_topo/dead_reckoning_gate.h"
#include "pomdp_topo/front_end.h"
#include "pomdp_topo/map_builder_params.h"
#include "pomdp_topo/pomdp_localizer.h"
#include "pomdp_topo/scan_record.h"
#include "pomdp_topo/topo_event.h"
#include "pomdp_topo/topological_map.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pomdp_topo {

/// The node opening a side landmark passed while travelling along the bin heading `heading` (map
/// frame) stands for: across the bin, with the skew of the hallway it was passed in.
NodeOpening sideOpening(double heading, const PassedLandmark& p);

class MapUpdater {
 public:
  /// `map` and `localizer` are the map builder's (the localizer gets the map again after a change).
  MapUpdater(TopologicalMap* map, PomdpLocalizer* localizer) : map_(map), localizer_(localizer) {}

  /// One scan with a confident belief (its most likely state): the map updated from its passed
  /// landmarks by the map builder's `params`; `gate` says where the dead reckoning puts them, `bins`
  /// are the heading bins, `pass_lag` (m, OpeningTracks) how far behind the robot a landmark is
  /// passed. What changed is told in `events`.
  void update(const ScanRecord& scan, const MapBuilderParams& params, const DeadReckoningGate& gate,
              const laser_features::HeadingBins& bins, double pass_lag, std::vector<TopoEvent>* events);
  /// The belief left the edge it was on (a reset, a new stretch, a jump): the next one starts afresh.
  void forget() { last_edge_ = -1; }

 private:
  void updateKnownEdge(const ScanRecord& scan);
  /// What a landmark passed on a known edge came to: matched (Eq. 4) or dropped, the map changed (a
  /// corner landmark or an end node's opening added), or the edge split at a new door's node.
  enum class Passed { Nothing, Changed, Split };
  Passed passedOnEdge(TopoEdge* e, const PomdpLocalizer::State& st, const PassedLandmark& p, const ScanRecord& scan);
  /// Eq. 5: the landmarks of `e` passed since the last scan without being seen; true if one was deleted.
  bool missedOnEdge(TopoEdge* e, const PomdpLocalizer::State& st);
  /// A node within min_node_separation + match_distance of `d` along edge `e` (either way, through
  /// short edges), or of where the dead reckoning puts the passed opening `p`, has an opening at
  /// `bearing` (map frame) of a compatible `width`.
  bool knownOpeningNear(const TopoEdge& e, double d, const PassedLandmark& p, const ScanRecord& scan, double bearing,
                        double width) const;
  /// The same from a list of (node, reach left in m).
  bool knownOpeningNear(std::vector<std::pair<uint32_t, double>> todo, const PassedLandmark& p,
                        const ScanRecord& scan, double bearing, double width) const;
  /// Doors passed while the belief is at node `st` that no node within reach has: added to it.
  void addOpeningsAtNode(const PomdpLocalizer::State& st, const ScanRecord& scan);
  void splitEdgeWithDoor(uint32_t edge, double distance, const NodeOpening& opening, bool is_door);
  void event(TopoEvent::Kind kind, std::string text, int node = -1, int other_node = -1, int edge = -1) {
    events_->push_back(TopoEvent{kind, node, other_node, edge, std::move(text)});
  }

  TopologicalMap* map_;
  PomdpLocalizer* localizer_;
  // The current update()'s inputs.
  const MapBuilderParams* params_ = nullptr;
  const DeadReckoningGate* gate_ = nullptr;
  laser_features::HeadingBins bins_;
  double pass_lag_ = 0.0;
  std::vector<TopoEvent>* events_ = nullptr;

  int last_edge_ = -1;      // most likely edge and offset at the previous step (eq. 5 misses)
  bool last_forward_ = true;
  double last_offset_ = 0.0;
  std::vector<uint32_t> matched_recently_;  // indices of landmarks of last_edge_ matched lately
};

}  // namespace pomdp_topo
