// Topological map building and loop closing (Tomatis et al. 2001, section 3.3; Tapus & Siegwart
// for loop closing by tracking two belief peaks).
//
// Three modes:
//  - Frontier: the robot follows a hallway stretch no edge covers yet. Side openings it passes
//    become nodes (doors, or junctions when wider than door_max_width), turns away from a node
//    become junction nodes, a U-turn a hallway end; corners passed become the stretch's landmarks.
//  - Localized: the robot is on the known graph; the POMDP localizes it; while the belief is
//    confident, passed landmarks update p_lmap (eqs. 4-5), confident unknown corners are added,
//    landmarks that fall below p_lmap_min are deleted, and an unknown door splits its edge. Never
//    while unconfident. Travel past a node where no edge continues starts a new Frontier.
//  - LoopCheck: a node just created looks like an old one (type, openings, fingerprint, display
//    position): map building stops, the two hypotheses "new place" and "old place" are tracked with
//    the landmarks and turns that follow until one dominates; the nodes are then merged (loop
//    closed) or the new stretch is kept.
#pragma once

#include "laser_features/building_rules.h"
#include "pomdp_topo/dead_reckoning_gate.h"
#include "pomdp_topo/front_end.h"
#include "pomdp_topo/loop_hypotheses.h"
#include "pomdp_topo/map_builder_params.h"
#include "pomdp_topo/map_updater.h"
#include "pomdp_topo/pomdp_localizer.h"
#include "pomdp_topo/topo_event.h"
#include "pomdp_topo/topological_map.h"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pomdp_topo {

class MapBuilder {
 public:
  enum class Mode { Frontier, Localized, LoopCheck };

  MapBuilder(TopologicalMap* map, PomdpLocalizer* localizer, const MapBuilderParams& params = MapBuilderParams());
  const MapBuilderParams& params() const { return params_; }
  /// Mapping on or off while running (missions on a finished map: localization only). Off takes
  /// effect at the next frontier: the robot off the graph relocalizes instead of mapping on.
  void setMapping(bool on) { params_.mapping = on; }
  /// The building's axis (rad, map frame), once it is known: the bins of every heading mapped from
  /// then on. The per-state bins kept for the heading gate are computed again.
  void setAxis(double axis_angle) {
    fe_params_.axis_angle = axis_angle;
    gate_.invalidate();
  }

  /// Starts: an empty map gets a Start node at the robot and a Frontier along its heading; a
  /// loaded map starts Localized with a uniform belief (global localization).
  void start(const FrontEnd& front_end);

  /// One scan's actions, observation and passed landmarks (from FrontEnd).
  void process(const std::vector<Action>& actions, const Observation& observation,
               const std::vector<PassedLandmark>& passed, const FrontEnd& front_end);

  /// The robot was moved without the odometry knowing (laser_features' odometry consistency fell):
  /// whatever the builder was doing, the robot's place is now unknown. A frontier being followed is
  /// left as an unexplored opening of the node it started from (the exploration comes back to it);
  /// a loop check keeps the new place; the belief becomes uniform over the known graph (Localized,
  /// unconfident: no map change until it is confident again).
  void odometryJump(const FrontEnd& fe);
  /// The front end refused a scan's odometry (a jump past max_odometry_step, a reset of the
  /// odometry): its position is no longer the map's, and the position gate is off from now on.
  void positionLost() {
    gate_.lose();
  }
  /// The front end's heading is the map's (a map built in this run, no jump since, or agreed with
  /// since: pomdp_topo_node's HeadingRealigner): the heading gate is on (heading_gate).
  void setHeadingTrusted(bool trusted) { gate_.setHeadingTrusted(trusted); }
  /// After an odometry jump, once the belief is confident again: where the map puts the robot (m,
  /// map frame), once; the caller moves the FrontEnd there (FrontEnd::setPosition). False otherwise.
  bool takeRelocatedPosition(Eigen::Vector2d* position);

  /// The robot travelled `metres` (FrontEnd::travel()) while the topological map was paused (in a
  /// room, METRIC mode) and came back where it left the hallway: that travel is not the hallway's.
  void skipTravel(double metres);

  Mode mode() const { return mode_; }
  static const char* toString(Mode mode);
  /// The node the robot is at or came from (Frontier), or the most likely state's node; -1 if none.
  int currentNode() const;
  /// The node of a door into a room beside the robot where it stopped (one the exploration enters,
  /// or a room's other door), recorded before the front end passes it: on a new stretch, a node
  /// made where the robot stands, as passing the door would make it (joined to the node the stretch
  /// left when within that node's reach); otherwise `currentNode()`.
  int nodeBesideRobot(const NodeOpening& door, const FrontEnd& fe);
  /// Distance travelled on the current frontier beyond `currentNode()`, m.
  double frontierDistance() const { return s_; }
  int frontierHeadingBin() const { return frontier_bin_; }
  /// Whether the robot's place is known: always in Frontier mode, the belief's flag otherwise.
  bool confident() const;
  /// What happened since the last call (a node made, a loop closed, ...), in order.
  std::vector<TopoEvent> takeEvents();
  /// Loop closures done so far (pairs kept, dropped).
  const std::vector<std::pair<uint32_t, uint32_t>>& loopsClosed() const { return loops_; }
  size_t loopsRejected() const { return loops_rejected_; }
  /// LoopCheck: the log odds of the best old-place hypothesis against the new place.
  double loopLogOdds() const;
  /// The best candidate's evidence so far, for the log ("3 landmarks matched, 1 expected missed, ...").
  std::string loopEvidence() const;

  /// Where the dead-reckoned position `robot` (the front end's, in the map's frame) lies against
  /// a new stretch `*s` m out of node `n` along `heading` (DeadReckoningGate::departure).
  using Departure = DeadReckoningGate::Departure;
  Departure departure(const TopoNode& n, double heading, const Pose2D& robot, double* s) const;

 private:
  using Scan = ScanRecord;

  void dispatch(const Scan& scan, const FrontEnd& fe);
  void processFrontier(const Scan& scan, const FrontEnd& fe);
  void processLocalized(const Scan& scan);
  /// What one action of processLocalized does where the belief stands at a node heading where no
  /// edge leads: nothing special (OnGraph), the observation not used (an unexplored way, or the
  /// belief reset), used with the travel beyond still counted (a hallway's end), or a new stretch
  /// started (LeftGraph: the rest of the scan is the frontier's).
  enum class BeyondStep { OnGraph, SkipObservation, ObserveAtEnd, LeftGraph };
  BeyondStep stepBeyondGraph(const Action& a, const Scan& scan);
  /// The belief beyond the graph at `node` is wrong (`where` it would put the robot): an event,
  /// the belief uniform, the travel beyond forgotten.
  BeyondStep resetBeyondGraph(const std::string& where, uint32_t node);
  /// The node `st` is at, recorded twice: merged into its twin, the belief on along the twin's way.
  bool mergeTwin(const PomdpLocalizer::State& st);
  void processLoopCheck(const Scan& scan, const FrontEnd& fe);
  void frontierTurn(int k, const Scan& scan, const FrontEnd& fe);
  /// Creates a node `pos` metres along the frontier (or adds the openings to the node it started
  /// from when that is closer than min_node_separation); returns the node's id.
  uint32_t createNode(NodeType type, double pos, const Scan& scan, const FrontEnd& fe,
                      const std::vector<NodeOpening>& openings);
  void startFrontier(uint32_t node, int bin, double s, double travel);
  /// m, where the front end tracks `door` along the frontier from the robot (0 if it tracks none).
  double trackedAlong(const NodeOpening& door, const FrontEnd& fe) const;
  void becomeLocalizedAt(uint32_t node, int bin);
  bool startLoopCheck(uint32_t new_node, uint32_t previous_node, const Scan& scan);
  void decideLoop(bool old_wins, const FrontEnd& fe);
  Fingerprint fingerprintAt(const Eigen::Vector2d& position, const FrontEnd& fe) const;
  laser_features::HeadingBins headingBins() const { return {fe_params_.axis_angle, fe_params_.heading_bins}; }
  double binHeading(int bin) const;
  int binOf(double heading) const;
  void refreshLocalizer();
  void event(TopoEvent::Kind kind, std::string text, int node = -1, int other_node = -1) {
    events_.push_back(TopoEvent{kind, node, other_node, -1, std::move(text)});
  }

  TopologicalMap* map_;
  PomdpLocalizer* localizer_;
  MapBuilderParams params_;
  FrontEndParams fe_params_;
  Mode mode_ = Mode::Frontier;

  // Frontier.
  uint32_t from_node_ = 0;
  int frontier_bin_ = 0;
  double s_ = 0.0;        // m, travel along the frontier beyond from_node_
  double s_base_ = 0.0;   // s_ = s_base_ + FrontEnd::travel() - travel_base_
  double travel_base_ = 0.0;
  laser_features::Pose2D frontier_pose_;  // FrontEnd::pose() at the last frontier scan (where s_ was)
  double frontier_travel_ = 0.0;          // FrontEnd::travel() then
  std::vector<EdgeLandmark> pending_;  // corners on the frontier, distance from from_node_
  double travel_since_localized_ = 0.0;
  DeadReckoningGate gate_;  // the belief and the map checked against the dead reckoning
  MapUpdater updater_;      // the known map updated while the belief is confident on it
  bool relocation_pending_ = false;     // an odometry jump happened; not yet confident again
  bool relocated_ = false;              // confident again: the position is to be taken
  Eigen::Vector2d relocated_position_ = Eigen::Vector2d::Zero();

  // Localized.
  double beyond_ = 0.0;     // travel while the most likely state is a node with no exit that way
  int beyond_state_ = -1;   // the localizer state beyond_ counts for
  // A hallway that ended (U-turn) less than node_radius past a node made no node of its own: how
  // far past that node (node, heading bin) the robot went before turning. Travel that far beyond
  // it is no new stretch. In memory only (a U-turn made after a restart records it again).
  std::map<std::pair<uint32_t, int>, double> end_beyond_;

  // LoopCheck.
  int departure_bin_ = -1;    // frontierTurn: the bin the robot leaves the junction it creates along
  LoopHypotheses loop_;
  std::vector<Scan> buffer_;  // the scans since the new node: replayed as a new stretch if it is one

  std::vector<TopoEvent> events_;
  std::vector<std::pair<uint32_t, uint32_t>> loops_;
  size_t loops_rejected_ = 0;
};

}  // namespace pomdp_topo
