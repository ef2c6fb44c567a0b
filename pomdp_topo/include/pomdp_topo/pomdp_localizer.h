// Topological localization as a POMDP over graph states (Tomatis, Nourbakhsh & Siegwart, IROS 2001,
// section 3.3): the belief over edge cells and node headings is updated with
//   b'(s') = eta * OS(o, s') * sum_s T(s, a, s') b(s)     (eq. 2)
// and the robot is localized when its entropy  U = -sum_s b(s) log b(s)  (eq. 3, nats) is below U_max.
//
// States: every edge of length L is cut into n = max(1, round(L / resolution)) cells, each in both
// travel directions; every node has one state per heading bin. The transition is sparse (each state
// spreads to at most three successors), the observation model matches the observed landmarks against
// the landmarks expected in a window around each state, precomputed by setMap(). The states and
// the graph walks are GraphStates', the observation model ObservationModel's; this class holds the
// belief, the transition's probabilities and the lost-belief detection.
//
// ROS-free; predict() and update() do not allocate in the steady state.
#pragma once

#include "pomdp_topo/graph_states.h"
#include "pomdp_topo/observation.h"
#include "pomdp_topo/observation_model.h"
#include "pomdp_topo/pomdp_params.h"
#include "pomdp_topo/topological_map.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace pomdp_topo {

class PomdpLocalizer {
 public:
  using State = GraphStates::State;

  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit PomdpLocalizer(const PomdpParams& params = PomdpParams());
  static bool validate(const PomdpParams& params, std::string* error = nullptr);
  const PomdpParams& params() const { return params_; }
  /// The building's axis (rad, map frame): bin k has heading axis + k 2 pi / heading_bins. Takes
  /// effect with the next setMap (the node states' headings are made there).
  void setAxis(double axis_angle) {
    params_.axis_angle = axis_angle;
    graph_.setAxis(axis_angle);
  }

  /// Rebuilds the states (call again when map.revision() changes). The belief is carried over by
  /// (edge id, direction, offset) and (node id, bin); new states get 0; uniform if nothing carried.
  void setMap(const TopologicalMap& map);
  uint64_t mapRevision() const { return map_revision_; }

  size_t size() const { return graph_.size(); }
  const State& state(size_t index) const { return graph_.state(index); }
  const std::vector<double>& belief() const { return belief_; }

  /// The prediction sum_s T(s, a, s') b(s) of eq. 2, then uniform mixing. Travel(0) and turns by a
  /// multiple of heading_bins change nothing. False (belief unchanged) for a non-finite distance.
  bool predict(const Action& action, std::string* error = nullptr);
  /// The correction b(s) ∝ OS(o, s)^observation_weight b(s) of eq. 2. False (belief unchanged) when
  /// the observation holds a non-finite number, a landmark of unknown type or a negative heading
  /// variance (heading and variance are only checked when heading_valid).
  bool update(const Observation& observation, std::string* error = nullptr);
  /// predict() then update(); nothing changes when either input is refused.
  bool step(const Action& action, const Observation& observation, std::string* error = nullptr);

  void setUniform();
  /// Travel from `node` along `heading` (rad) is no travel into a wall although no edge leads that
  /// way: the hallway goes on unmapped there (a frontier the map builder left after an odometry
  /// jump). Kept across setMap() until clearOpenWays().
  void addOpenWay(uint32_t node, double heading);
  void clearOpenWays();
  bool setState(size_t index);
  /// Any belief (normalized here); false (no change) for a wrong size, a negative or non-finite
  /// entry, or a zero sum.
  bool setBelief(const std::vector<double>& belief);
  /// The belief outside `allowed` (one flag per state) is dropped and the rest renormalized; when
  /// nothing was inside, the belief becomes uniform over `allowed` and this returns false. Unlike
  /// setBelief the lost-belief detection goes on counting. No change for a wrong size or no state
  /// allowed (returns true).
  bool restrictTo(const std::vector<bool>& allowed);
  /// Belief all on the node state of the bin nearest `heading`; false (no change) for an unknown node.
  bool resetToNode(uint32_t node, double heading);
  /// Belief all on the cell of `edge` containing `offset` (clamped to the edge); false (no change)
  /// for an unknown edge or a non-finite offset.
  bool resetToEdge(uint32_t edge, double offset, bool forward);

  double entropy() const;   // eq. 3, nats
  bool confident() const;   // entropy() < entropy_max and not lost()
  int mostLikely() const;   // index, or -1 without states
  /// True when the last update reset the belief (lost for lost_steps updates, or degenerate).
  bool lost() const { return lost_; }
  /// How many times the belief was reset to uniform because it was lost (since construction).
  uint64_t lostResets() const { return lost_resets_; }
  /// log (sum_s b(s) L(s)^w)^(1/w) of the last update (predicted belief b, w = observation_weight;
  /// log sum_s b(s) L(s) when w = 0), compared with lost_likelihood; 0 before any update.
  double lastLogLikelihood() const { return last_log_likelihood_; }

  // Lookups and summaries.
  int headingBin(double heading) const { return graph_.headingBin(heading); }
  double binHeading(int bin) const { return graph_.binHeading(bin); }
  int edgeStateIndex(uint32_t edge, double offset, bool forward) const {  // -1 if unknown
    return graph_.edgeStateIndex(edge, offset, forward);
  }
  int nodeStateIndex(uint32_t node, double heading) const {  // -1 if unknown
    return graph_.nodeStateIndex(node, heading);
  }
  /// Mass of the node's states and of the edge states within `radius` (m) of the node.
  double probabilityNearNode(uint32_t node, double radius) const;
  double probabilityWhere(const std::function<bool(const State&)>& predicate) const;
  /// The landmarks the observation model expects at a state (empty for a bad index).
  std::vector<ExpectedLandmark> expectedLandmarks(size_t index) const { return model_.expectedLandmarks(index); }
  /// log OS(o, s) of one state (untempered, with the heading term), from its own list of expected
  /// landmarks: for inspection and tests (update() uses a faster per-edge path). NaN for a bad index
  /// or observation. The belief is not changed.
  double stateLogLikelihood(size_t index, const Observation& observation) {
    return model_.stateLogLikelihood(graph_, index, observation);
  }
  /// log OS(o, s) of every state in the last update.
  const std::vector<double>& stateLogLikelihoods() const { return log_likelihood_; }

 private:
  struct TravelTable {
    double distance = 0.0;
    bool valid = false;
    uint64_t last_use = 0;
    std::vector<int32_t> next;  // 3 successors per state: distance - cell, distance, distance + cell; ~index: blocked
  };

  const TravelTable& travelTable(double distance);
  void carryBelief(const std::vector<State>& old_states, const std::vector<double>& old_belief);
  void applyOpenWays();
  void finishPrediction();

  PomdpParams params_;
  GraphStates graph_;
  ObservationModel model_;
  uint64_t map_revision_ = 0;

  std::vector<double> belief_;
  // Per state: the factor on mass whose travel is blocked there (blocked_travel_probability, or 1
  // for a node state heading an open way, see addOpenWay).
  std::vector<double> blocked_factor_;
  std::vector<std::pair<uint32_t, int>> open_ways_;  // (node id, heading bin)

  // Step buffers (reused).
  std::array<TravelTable, 4> travel_cache_;
  uint64_t travel_uses_ = 0;
  std::vector<double> scratch_;
  std::vector<double> log_likelihood_;

  bool lost_ = false;
  uint64_t lost_resets_ = 0;
  int low_likelihood_steps_ = 0;
  double last_log_likelihood_ = 0.0;
};

}  // namespace pomdp_topo
