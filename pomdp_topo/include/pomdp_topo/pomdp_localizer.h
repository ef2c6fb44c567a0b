// Topological localization as a POMDP over graph states (Tomatis, Nourbakhsh & Siegwart, IROS 2001,
// section 3.3): the belief over edge cells and node headings is updated with
//   b'(s') = eta * OS(o, s') * sum_s T(s, a, s') b(s)     (eq. 2)
// and the robot is localized when its entropy  U = -sum_s b(s) log b(s)  (eq. 3, nats) is below U_max.
//
// States: every edge of length L is cut into n = max(1, round(L / resolution)) cells, each in both
// travel directions; every node has one state per heading bin. The transition is sparse (each state
// spreads to at most three successors), the observation model matches the observed landmarks against
// the landmarks expected in a window around each state, precomputed by setMap().
//
// ROS-free; predict() and update() do not allocate in the steady state.
#pragma once

#include "laser_features/building_axes.h"
#include "pomdp_topo/observation.h"
#include "pomdp_topo/topological_map.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

namespace pomdp_topo {

struct PomdpParams {
  double resolution = 0.5;                  // m, cell length along edges
  int heading_bins = 4;                     // -, discrete headings at nodes (4 = N/E/S/W)
  double axis_angle = 0.0;                  // rad, building axis: bin k has heading axis_angle + k*2pi/heading_bins
  double travel_spread = 0.15;              // -, per metre travelled: probability of undershooting by one cell, and separately of overshooting (each capped at 0.45)
  double node_radius = 1.0;                 // m, an edge state this close to a node turns there
  double turn_mid_edge_probability = 0.05;  // -, a non-180-degree turn away from nodes: the mass stays, times this
  double turn_lost_mass = 0.02;             // -, a 90-degree turn with less belief than this at (or near) nodes: lost, reset to uniform
  double blocked_travel_probability = 0.1;  // -, a travel ending >= one cell past a node without a way on (into a wall): the mass stays at the node, times this (1 along an open way, see addOpenWay)
  double window_ahead = 2.0;                // m, landmarks this far ahead along the travel heading are expected (side openings farther ahead are often not seen yet)
  double window_behind = 3.0;               // m, landmarks this far behind are expected
  double window_lateral = 3.0;              // m, and at most this far to the side
  double match_sigma_along = 0.5;           // m, association / likelihood width along the travel heading
  double match_sigma_lateral = 0.4;         // m, association / likelihood width across it
  double match_orientation_tolerance = 0.6; // rad, largest orientation difference of a match
  double false_landmark_probability = 0.1;  // -, likelihood factor of an observed landmark the map does not explain
  double opening_p_lmap = 0.9;              // -, p_lmap of a node opening (door, junction branch)
  double observation_weight = 0.35;         // -, exponent tempering the likelihood (landmarks are seen in several consecutive steps)
  double heading_sigma = 0.3;               // rad, heading likelihood width
  double heading_floor = 0.02;              // -, floor of the heading likelihood (a wrong heading estimate can be recovered from)
  double uniform_mixing = 1e-4;             // -, share of uniform probability mixed in after each prediction (kidnap recovery)
  double entropy_max = 2.0;                 // nats, U_max: confident below it
  double unexplored_landmark_probability = 0.3;  // -, likelihood factor of an observed landmark beyond the known map's end at a node with no way on that is no hallway end (unexplored: neither explained nor false)
  double lost_likelihood = 1e-3;            // -, lost when the observation's likelihood under the predicted belief, (sum_s b(s) L(s)^w)^(1/w) (w = observation_weight: the normalizer of eq. 2 on the scale of one L), relative to its likelihood with nothing expected (every landmark false), stays below this ...
  int lost_steps = 3;                       // -, ... for this many consecutive updates: then reset to uniform
  int max_cells_per_edge = 10000;           // -, cap on n per edge (a corrupt length cannot exhaust memory)
};

/// A landmark the map predicts around a state, in the state's travel frame (as ObservedLandmark).
struct ExpectedLandmark {
  LandmarkType type = LandmarkType::Corner;
  double along = 0.0;        // m, + ahead
  double lateral = 0.0;      // m, + left
  double orientation = 0.0;  // rad, relative to the state's heading
  double p_lmap = 0.5;       // probability of seeing it (clamped to [0.01, 0.99])
};

class PomdpLocalizer {
 public:
  struct State {
    enum Kind : uint8_t { Edge = 0, Node = 1 };
    Kind kind = Edge;
    uint32_t id = 0;       // edge id (Edge) or node id (Node)
    bool forward = true;   // Edge: travel source -> target; Node: true
    double offset = 0.0;   // m, cell centre from the edge's source; 0 for nodes
    double heading = 0.0;  // rad, map frame, direction of travel
    uint32_t cell = 0;     // Edge: cell index counted from the source; Node: heading bin
  };

  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit PomdpLocalizer(const PomdpParams& params = PomdpParams());
  static bool validate(const PomdpParams& params, std::string* error = nullptr);
  const PomdpParams& params() const { return params_; }
  /// The building's axis (rad, map frame): bin k has heading axis + k 2 pi / heading_bins. Takes
  /// effect with the next setMap (the node states' headings are made there).
  void setAxis(double axis_angle) { params_.axis_angle = axis_angle; }

  /// Rebuilds the states (call again when map.revision() changes). The belief is carried over by
  /// (edge id, direction, offset) and (node id, bin); new states get 0; uniform if nothing carried.
  void setMap(const TopologicalMap& map);
  uint64_t mapRevision() const { return map_revision_; }

  size_t size() const { return states_.size(); }
  const State& state(size_t index) const { return states_[index]; }
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
  int headingBin(double heading) const;
  double binHeading(int bin) const;
  int edgeStateIndex(uint32_t edge, double offset, bool forward) const;  // -1 if unknown
  int nodeStateIndex(uint32_t node, double heading) const;               // -1 if unknown
  /// Mass of the node's states and of the edge states within `radius` (m) of the node.
  double probabilityNearNode(uint32_t node, double radius) const;
  double probabilityWhere(const std::function<bool(const State&)>& predicate) const;
  /// The landmarks the observation model expects at a state (empty for a bad index).
  std::vector<ExpectedLandmark> expectedLandmarks(size_t index) const;
  /// log OS(o, s) of one state (untempered, with the heading term), from its own list of expected
  /// landmarks: for inspection and tests (update() uses a faster per-edge path). NaN for a bad index
  /// or observation. The belief is not changed.
  double stateLogLikelihood(size_t index, const Observation& observation);
  /// log OS(o, s) of every state in the last update.
  const std::vector<double>& stateLogLikelihoods() const { return log_likelihood_; }

 private:
  // A travel direction of an edge: 2 * edge index + (0 forward, 1 backward).
  struct DirEdge {
    double length = 0.0;
    double cell = 0.0;      // m, cell length L / n
    double inv_cell = 0.0;  // 1/m, n / L (0 for a zero length)
    double heading = 0.0;   // rad, travel heading
    int32_t cells = 1;
    int32_t base = 0;       // state index of cell 0 (counted from the edge's source)
    int32_t start = 0;      // node index where the travel starts
    int32_t end = 0;        // node index where it ends
    int32_t next = -1;      // straight continuation at `end` (directed edge, heading within 45 deg), -1 if none
    int32_t bin = 0;        // heading bin of `heading`
    int32_t bin_reversed = 0;  // heading bin of heading + pi
  };
  struct Expected {  // compact ExpectedLandmark (build only)
    float along, lateral, orientation, gain;  // gain = log p_lmap - log(1 - p_lmap)
    float p_lmap;
    LandmarkType type;
    uint64_t key;  // which edge landmark / node opening
  };
  struct EdgeExpected {  // a landmark expected by cells [kmin, kmax] (travel order) of a directed edge
    double t;              // m, travel coordinate on the directed edge: along = t - cell position
    float lateral, cos, sin, gain;
    LandmarkType type;
    int32_t kmin, kmax;
    uint64_t key;
  };
  struct PoolCandidate {
    float d2;
    uint32_t e, o;
    int32_t next;  // next candidate of the same cell, -1 at the end
  };
  struct Obs {
    LandmarkType type;
    float along, lateral, cos, sin;  // orientation as a unit vector
    double match_bonus;  // log confidence - log false_landmark_probability
  };
  struct Candidate {
    float d2;
    uint32_t e, o;  // index among the state's expected landmarks, observed index
  };
  struct TravelTable {
    double distance = 0.0;
    bool valid = false;
    uint64_t last_use = 0;
    std::vector<int32_t> next;  // 3 successors per state: distance - cell, distance, distance + cell; ~index: blocked
  };

  int32_t nodeState(int32_t node_index, int bin) const { return node_base_ + node_index * bins_ + bin; }
  int32_t cellState(int32_t dir_edge, double s, bool reversed) const;
  int32_t walk(int32_t dir_edge, double s, double distance, bool reversed) const;
  int32_t travelFrom(size_t state, double distance) const;
  int32_t turnFrom(size_t state, int k, bool* mid_edge) const;
  const TravelTable& travelTable(double distance);
  void indexNodes(const TopologicalMap& map);
  std::vector<uint32_t> buildDirectedEdges(const TopologicalMap& map, std::vector<std::vector<int32_t>>* exits);
  void linkWays(const TopologicalMap& map, const std::vector<std::vector<int32_t>>& exits);
  void buildStates(const std::vector<uint32_t>& edge_ids);
  void carryBelief(const std::vector<State>& old_states, const std::vector<double>& old_belief);
  void buildExpected();
  void expectStateLandmarks();
  void expectEdgeLandmarks();
  void addEdgeLandmarks(int32_t dir_edge, double a0);
  void addNodeOpenings(int32_t node_index, double along, double heading);
  void walkForward(int32_t dir_edge, double a0, double heading);
  void walkBackward(int32_t motion_edge, double a_end, double heading);
  static bool checkObservation(const Observation& observation, std::string* error);
  void prepareObservation(const Observation& observation);
  double headingTerm(double heading) const;
  double observationLogLikelihood(size_t state);
  void edgeLogLikelihoods(int32_t dir_edge, double heading_term);
  double greedyMatch(uint32_t count, const float* gains);
  void finishPrediction();

  PomdpParams params_;
  int bins_ = 4;
  double bin_width_ = 0.0;
  uint64_t map_revision_ = 0;

  std::vector<State> states_;
  std::vector<double> belief_;
  std::vector<DirEdge> dir_edges_;
  int32_t node_base_ = 0;
  std::vector<uint32_t> node_ids_;
  std::unordered_map<uint32_t, int32_t> node_index_;
  std::unordered_map<uint32_t, int32_t> edge_index_;
  std::vector<int32_t> node_exit_;       // [node * bins + b]: directed edge leaving with heading ~ bin b
  std::vector<int32_t> node_exit_back_;  // [node * bins + b]: leaving with heading ~ bin b + pi
  std::vector<std::vector<NodeOpening>> node_openings_;
  std::vector<char> node_closed_;        // per node: a hallway end (nothing beyond it)
  // Per state: the factor on mass whose travel is blocked there (blocked_travel_probability, or 1
  // for a node state heading an open way, see addOpenWay).
  std::vector<double> blocked_factor_;
  std::vector<std::pair<uint32_t, int>> open_ways_;  // (node id, heading bin)
  void applyOpenWays();
  // Per state: along distances where the known map ends ahead / behind at a node with no way on
  // that is not a hallway end (observed landmarks beyond are unexplored, not false).
  std::vector<float> unknown_ahead_, unknown_behind_;
  float cur_unknown_ahead_ = 0.0f, cur_unknown_behind_ = 0.0f;
  std::vector<float> obs_along_sorted_;
  double unknown_gain_ = 0.0;            // log unexplored_landmark_probability - log false_landmark_probability
  double unknownCorrection(size_t state) const;
  std::vector<std::vector<EdgeLandmark>> edge_landmarks_;
  std::vector<int32_t> near_node_;       // per edge state: node index within node_radius, -1 if none
  std::vector<int32_t> state_dir_edge_;  // per edge state: its directed edge

  // Expected landmarks per state (CSR; built in expected_, then kept as arrays; corners first, then
  // openings, each by along) and their sum of log(1 - p_lmap).
  std::vector<uint32_t> expected_begin_;
  std::vector<uint32_t> expected_split_;  // first opening
  std::vector<float> expected_base_;
  size_t max_expected_ = 0;
  std::vector<Expected> expected_;
  std::vector<float> ex_along_, ex_lateral_, ex_cos_, ex_sin_, ex_gain_;
  // The same per directed edge (update's fast path).
  std::vector<uint32_t> de_expected_begin_;
  std::vector<EdgeExpected> edge_expected_;
  std::vector<float> x_gain_;
  std::vector<char> de_regular_;
  size_t max_edge_members_ = 0;  // largest sum over a directed edge's cells of their expected counts

  // Build scratch.
  std::vector<uint32_t> visited_edges_;
  std::vector<int32_t> visited_nodes_;

  // Step buffers (reused).
  std::array<TravelTable, 4> travel_cache_;
  uint64_t travel_uses_ = 0;
  std::vector<double> scratch_;
  std::vector<double> log_likelihood_;
  std::vector<Obs> obs_;
  double obs_log_false_ = 0.0;  // number of observed landmarks * log false_landmark_probability
  bool heading_valid_ = false;
  double heading_ = 0.0, heading_variance_ = 0.0;  // of the observation (variance + heading_sigma^2)
  float inv_sigma_along_ = 1.0f, inv_sigma_lateral_ = 1.0f, cos_tolerance_ = 0.0f;
  std::vector<Candidate> candidates_;
  std::vector<PoolCandidate> pool_;
  std::vector<int32_t> cell_head_;
  std::vector<char> used_expected_;
  std::vector<char> used_observed_;

  bool lost_ = false;
  uint64_t lost_resets_ = 0;
  int low_likelihood_steps_ = 0;
  double last_log_likelihood_ = 0.0;
};

}  // namespace pomdp_topo
