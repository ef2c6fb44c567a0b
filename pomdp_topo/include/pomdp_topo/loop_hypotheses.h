// Loop closing by tracking belief peaks (Tapus & Siegwart): a door or junction node just created
// may be an old node of the map come to again. The old nodes it may be are the candidates, each
// scored (log likelihood) with the landmarks and turns passed from the node on against the
// expected path beyond the old node, and one hypothesis "a new place" scored the same scans as
// unexplored ground; MapBuilder's LoopCheck mode runs this until one dominates, then merges the
// nodes or keeps the new stretch.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "laser_features/building_axes.h"
#include "pomdp_topo/front_end.h"
#include "pomdp_topo/map_builder_params.h"
#include "pomdp_topo/observation.h"
#include "pomdp_topo/topological_map.h"

#include <cstdint>
#include <string>
#include <vector>

namespace pomdp_topo {

/// Fingerprint similarity in [0, 1]: twice the entries matched (same kind, bearing within
/// `tolerance` rad, each used once) over the entries of both; 1 for two empty ones.
double fingerprintSimilarity(const Fingerprint& a, const Fingerprint& b, double tolerance);

class LoopHypotheses {
 public:
  /// The check of node `new_node`, come to from `previous_node` along `arrival_heading` (rad) and
  /// going on along bin `go_bin` (straight past a door, the branch turned to at a junction). The
  /// candidates are the old nodes of its type within `gate` m of it (position prior: a Gaussian of
  /// sigma gate / 2) off the straight stretch just built (coming back to a place takes a turn), with
  /// every opening of the new node (as an opening or an edge), a fingerprint alike (unless come to
  /// from another way) and a way on along `go_bin` to verify against. `travel0`: FrontEnd::travel()
  /// at the new node. False, and no check, when there is no candidate.
  bool begin(const TopologicalMap& map, const MapBuilderParams& params, const laser_features::HeadingBins& bins,
             uint32_t new_node, uint32_t previous_node, double arrival_heading, int go_bin, double gate,
             double travel0);
  /// One scan of the check (`travel`: FrontEnd::travel() after it): the landmarks passed along the
  /// way verified and its turns scored for every hypothesis; the landmarks expected more than
  /// match_distance + `pass_lag` (OpeningTracks: how far behind the robot a landmark is passed)
  /// behind the robot and not seen count as missed. True when the scan has a turn.
  bool observe(const TopologicalMap& map, const MapBuilderParams& params, const laser_features::HeadingBins& bins,
               double pass_lag, const std::vector<PassedLandmark>& passed, const std::vector<Action>& actions,
               double travel);
  /// The log odds of the best old-place hypothesis against the new place.
  double logOdds() const;
  /// The best candidate's evidence so far, for the log ("3 landmarks matched, 1 expected missed, ...").
  std::string evidence() const;
  /// The old nodes the new one may be (map order).
  std::vector<uint32_t> candidates() const;
  /// The best candidate's node (the first of the best: candidates in map order). begin() was true.
  uint32_t bestNode() const;
  /// The robot travelled `metres` with the map paused (a room visit): not the check's way.
  void skipTravel(double metres) { travel0_ += metres; }
  void clear() { candidates_.clear(); }

  uint32_t newNode() const { return new_node_; }
  /// The heading bin the hypotheses are verified along (the robot's way on).
  int bin() const { return bin_; }
  /// FrontEnd::travel() at the new node.
  double travel0() const { return travel0_; }

 private:
  struct Candidate {
    uint32_t node = 0;
    double score = 0.0;  // log likelihood so far, with the position prior
    std::vector<EdgeLandmark> expected;  // along the path beyond the node, distance from it
    std::vector<bool> used;
    double path_end = 0.0;               // m, where the known path beyond the node ends
    double prior = 0.0;                  // the position prior's part of score (log)
    int matched = 0, unexpected = 0, missed = 0, turns_possible = 0, turns_impossible = 0;  // the evidence, for the log
  };
  /// The candidate for old node `m` (its expected path along `go`), with `prior` its log prior.
  Candidate candidate(const TopologicalMap& map, const MapBuilderParams& params, uint32_t m, double go,
                      double prior) const;
  void scorePassed(const MapBuilderParams& params, const std::vector<PassedLandmark>& passed);
  bool scoreTurns(const TopologicalMap& map, const MapBuilderParams& params, const laser_features::HeadingBins& bins,
                  const std::vector<Action>& actions, double u);
  void scoreMissed(const MapBuilderParams& params, double pass_lag, double u);

  uint32_t new_node_ = 0;
  int bin_ = 0;
  double travel0_ = 0.0;
  double new_score_ = 0.0;  // the new place's log likelihood
  std::vector<Candidate> candidates_;
};

}  // namespace pomdp_topo
