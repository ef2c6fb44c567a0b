// The observation model OS(o, s) of the topological POMDP (Tomatis, Nourbakhsh & Siegwart, IROS
// 2001, eq. 2): the landmarks observed around the robot are matched against the landmarks the map
// expects in a window around each state. Unmatched expected landmarks count log(1 - p_lmap), unmatched
// observed ones log(false_landmark_probability) (or the unexplored one beyond where the known map
// ends), and a match log(p_lmap * confidence) - d^2 / 2, chosen by a greedy one-to-one association;
// a heading term compares the estimated heading with the state's.
//
// build() precomputes each state's window (after GraphStates::build); logLikelihoods() then does not
// allocate in the steady state. ROS-free.
#pragma once

#include "pomdp_topo/graph_states.h"
#include "pomdp_topo/observation.h"
#include "pomdp_topo/pomdp_params.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pomdp_topo {

/// A landmark the map predicts around a state, in the state's travel frame (as ObservedLandmark).
struct ExpectedLandmark {
  LandmarkType type = LandmarkType::Corner;
  double along = 0.0;        // m, + ahead
  double lateral = 0.0;      // m, + left
  double orientation = 0.0;  // rad, relative to the state's heading
  double p_lmap = 0.5;       // probability of seeing it (clamped to [0.01, 0.99])
};

class ObservationModel {
 public:
  /// Uses the window, match, landmark-probability and heading parameters.
  explicit ObservationModel(const PomdpParams& params) : params_(params) {}

  /// The expected landmarks of every state of `graph`, and where the known map ends around each.
  void build(const GraphStates& graph);
  /// False (with the reason) for a landmark of unknown type, a non-finite number, or a negative
  /// heading variance (heading and variance are only checked when heading_valid).
  static bool check(const Observation& observation, std::string* error);
  /// log OS(o, s) with the heading term, for every state of `graph` (the one build() was given) into
  /// `out` (sized graph.size()). `observation` must pass check().
  void logLikelihoods(const GraphStates& graph, const Observation& observation, std::vector<double>* out);
  /// The same for one state from its own list of expected landmarks (logLikelihoods uses a faster
  /// per-edge path); NaN for a bad index or observation.
  double stateLogLikelihood(const GraphStates& graph, size_t index, const Observation& observation);
  /// The landmarks expected at a state (empty for a bad index).
  std::vector<ExpectedLandmark> expectedLandmarks(size_t index) const;
  /// log OS(o, s) with every landmark of the last observation false and nothing expected: the
  /// number of observed landmarks times log false_landmark_probability.
  double logAllFalse() const { return obs_log_false_; }

 private:
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

  void expectStateLandmarks(const GraphStates& graph);
  void expectEdgeLandmarks(const GraphStates& graph);
  void addEdgeLandmarks(const GraphStates& graph, int32_t dir_edge, double a0);
  void addNodeOpenings(const GraphStates& graph, int32_t node_index, double along, double heading);
  void walkForward(const GraphStates& graph, int32_t dir_edge, double a0, double heading);
  void walkBackward(const GraphStates& graph, int32_t motion_edge, double a_end, double heading);
  void prepareObservation(const Observation& observation);
  double headingTerm(double heading) const;
  double unknownCorrection(size_t state) const;
  double observationLogLikelihood(size_t state);
  void edgeLogLikelihoods(const GraphStates& graph, int32_t dir_edge, double heading_term, double* out);
  double greedyMatch(uint32_t count, const float* gains);

  PomdpParams params_;

  // Expected landmarks per state (CSR; built in expected_, then kept as arrays; corners first, then
  // openings, each by along) and their sum of log(1 - p_lmap).
  std::vector<uint32_t> expected_begin_;
  std::vector<uint32_t> expected_split_;  // first opening
  std::vector<float> expected_base_;
  size_t max_expected_ = 0;
  std::vector<Expected> expected_;
  std::vector<float> ex_along_, ex_lateral_, ex_cos_, ex_sin_, ex_gain_;
  // The same per directed edge (the fast path of logLikelihoods).
  std::vector<uint32_t> de_expected_begin_;
  std::vector<EdgeExpected> edge_expected_;
  std::vector<float> x_gain_;
  std::vector<char> de_regular_;
  size_t max_edge_members_ = 0;  // largest sum over a directed edge's cells of their expected counts
  // Per state: along distances where the known map ends ahead / behind at a node with no way on
  // (GraphStates::mapEndsBeyond; observed landmarks beyond are unexplored, not false).
  std::vector<float> unknown_ahead_, unknown_behind_;

  // Build scratch.
  std::vector<uint32_t> visited_edges_;
  std::vector<int32_t> visited_nodes_;
  float cur_unknown_ahead_ = 0.0f, cur_unknown_behind_ = 0.0f;

  // The observation being scored, and step buffers (reused).
  std::vector<Obs> obs_;
  std::vector<float> obs_along_sorted_;
  double obs_log_false_ = 0.0;  // number of observed landmarks * log false_landmark_probability
  double unknown_gain_ = 0.0;   // log unexplored_landmark_probability - log false_landmark_probability
  bool heading_valid_ = false;
  double heading_ = 0.0, heading_variance_ = 0.0;  // of the observation (variance + heading_sigma^2)
  float inv_sigma_along_ = 1.0f, inv_sigma_lateral_ = 1.0f, cos_tolerance_ = 0.0f;
  std::vector<Candidate> candidates_;
  std::vector<PoolCandidate> pool_;
  std::vector<int32_t> cell_head_;
  std::vector<char> used_expected_;
  std::vector<char> used_observed_;
};

}  // namespace pomdp_topo
