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
#include "pomdp_topo/front_end.h"
#include "pomdp_topo/loop_hypotheses.h"
#include "pomdp_topo/map_builder_params.h"
#include "pomdp_topo/pomdp_localizer.h"
#include "pomdp_topo/topological_map.h"

#include <map>
#include <string>
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
    state_bins_.clear();
    state_positions_.clear();
    state_beyond_map_.clear();
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
    position_trusted_ = false;
    heading_trusted_ = false;
  }
  /// The front end's heading is the map's (a map built in this run, no jump since, or agreed with
  /// since: pomdp_topo_node's HeadingRealigner): the heading gate is on (heading_gate).
  void setHeadingTrusted(bool trusted) { heading_trusted_ = trusted; }
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
  /// Distance travelled on the current frontier beyond `currentNode()`, m.
  double frontierDistance() const { return s_; }
  int frontierHeadingBin() const { return frontier_bin_; }
  /// Whether the robot's place is known: always in Frontier mode, the belief's flag otherwise.
  bool confident() const;
  /// Log of what happened ("node 4 (door) created", "loop closed: node 9 merged into node 2", ...).
  std::vector<std::string> takeEvents();
  /// Loop closures done so far (pairs kept, dropped).
  const std::vector<std::pair<uint32_t, uint32_t>>& loopsClosed() const { return loops_; }
  size_t loopsRejected() const { return loops_rejected_; }
  /// LoopCheck: the log odds of the best old-place hypothesis against the new place.
  double loopLogOdds() const;
  /// The best candidate's evidence so far, for the log ("3 landmarks matched, 1 expected missed, ...").
  std::string loopEvidence() const;

  /// Where the dead-reckoned position `robot` (the front end's, in the map's frame) lies against
  /// a new stretch `*s` m out of node `n` along `heading`, within update_position_tolerance: there
  /// (Here; `*s` becomes the dead reckoning's distance along the way where that is farther by more
  /// than the tolerance: the belief reached the node late), on the way out but short of that
  /// (NotYet; `*s` becomes its distance past the node, at least 0: the belief leads the robot out),
  /// or off the way out (Elsewhere: the belief is wrong). Here when the map is not checked against
  /// the dead reckoning (deadReckoningChecks).
  enum class Departure { Here, NotYet, Elsewhere };
  Departure departure(const TopoNode& n, double heading, const Pose2D& robot, double* s) const;

 private:
  /// What the builder needs of one scan (kept to replay the scans of a rejected loop hypothesis).
  struct Scan {
    std::vector<Action> actions;
    Observation observation;
    std::vector<PassedLandmark> passed;
    double travel = 0.0;  // FrontEnd::travel() after the scan
    Pose2D pose;          // FrontEnd::pose() after the scan
    int heading_bin = 0;  // FrontEnd::headingBin() after the scan
  };

  void dispatch(const Scan& scan, const FrontEnd& fe);
  void processFrontier(const Scan& scan, const FrontEnd& fe);
  void processLocalized(const Scan& scan);
  void processLoopCheck(const Scan& scan, const FrontEnd& fe);
  void frontierTurn(int k, const Scan& scan, const FrontEnd& fe);
  /// Creates a node `pos` metres along the frontier (or adds the openings to the node it started
  /// from when that is closer than min_node_separation); returns the node's id.
  uint32_t createNode(NodeType type, double pos, const Scan& scan, const FrontEnd& fe,
                      const std::vector<NodeOpening>& openings);
  void startFrontier(uint32_t node, int bin, double s, double travel);
  void becomeLocalizedAt(uint32_t node, int bin);
  bool startLoopCheck(uint32_t new_node, uint32_t previous_node, const Scan& scan);
  /// The map position of a belief state (a node, or along an edge between its nodes' poses).
  bool statePosition(const PomdpLocalizer::State& st, Eigen::Vector2d* p) const;
  /// The point `d` metres along edge `e` from its source (clamped to the edge), map frame; false for
  /// an edge whose nodes are unknown.
  bool pointOnEdge(const TopoEdge& e, double d, Eigen::Vector2d* p) const;
  /// The position and heading gates (position_gate, heading_gate): the belief restricted to states
  /// near the dead-reckoned position and with the dead-reckoned heading.
  void gateByDeadReckoning(const Scan& scan);
  /// A node of the same type as `id` within update_position_tolerance of it (position gate on) with
  /// an edge along `heading`, which `id` lacks: one place recorded twice. -1 if none.
  int twinWithWay(uint32_t id, double heading) const;
  /// Whether `robot` lies on the way out of a node at `node` along `heading`: within
  /// update_position_tolerance of that ray, not farther behind the node; `*along` is its distance
  /// along the way.
  bool alongWayOut(const Eigen::Vector2d& node, double heading, const Eigen::Vector2d& robot, double* along) const;
  /// update_position_tolerance: the dead-reckoned position of a passed landmark is farther than the
  /// tolerance from `believed` (where the belief puts it, map frame), while the position gate is on.
  bool farFromDeadReckoning(const Eigen::Vector2d& believed, const PassedLandmark& p, const Scan& scan) const;
  /// Where the dead reckoning puts a passed landmark (map frame); false while the position gate is
  /// off or the dead reckoning is not trusted (as farFromDeadReckoning).
  bool deadReckonedPosition(const PassedLandmark& p, const Scan& scan, Eigen::Vector2d* at) const;
  /// The map is checked against the dead reckoning (update_position_tolerance): the position gate
  /// is on, the tolerance set and the front end's position trusted.
  bool deadReckoningChecks() const {
    return position_trusted_ && params_.position_gate > 0.0 && params_.update_position_tolerance > 0.0;
  }
  void decideLoop(bool old_wins, const FrontEnd& fe);
  void updateKnownEdge(const Scan& scan);
  /// A node within min_node_separation + match_distance of `d` along edge `e` (either way, through
  /// short edges), or of where the dead reckoning puts the passed opening `p`, has an opening at
  /// `bearing` (map frame) of a compatible `width`.
  bool knownOpeningNear(const TopoEdge& e, double d, const PassedLandmark& p, const Scan& scan, double bearing,
                        double width) const;
  /// The same from a list of (node, reach left in m).
  bool knownOpeningNear(std::vector<std::pair<uint32_t, double>> todo, const PassedLandmark& p, const Scan& scan,
                        double bearing, double width) const;
  /// The dead reckoning puts the passed opening `p` farther than min_node_separation +
  /// match_distance from node `n`: it is not an opening `n` lacks. False without dead reckoning.
  bool farFromNode(const TopoNode& n, const PassedLandmark& p, const Scan& scan) const;
  /// Doors passed while the belief is at node `st` that no node within reach has: added to it.
  void addOpeningsAtNode(const PomdpLocalizer::State& st, const Scan& scan);
  void splitEdgeWithDoor(uint32_t edge, double distance, const NodeOpening& opening, bool is_door);
  Fingerprint fingerprintAt(const Eigen::Vector2d& position, const FrontEnd& fe) const;
  laser_features::HeadingBins headingBins() const { return {fe_params_.axis_angle, fe_params_.heading_bins}; }
  double binHeading(int bin) const;
  int binOf(double heading) const;
  void refreshLocalizer();
  void event(const std::string& text) { events_.push_back(text); }

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
  std::vector<EdgeLandmark> pending_;  // corners on the frontier, distance from from_node_
  double travel_since_localized_ = 0.0;
  bool position_trusted_ = false;   // the front end's position is in the map's frame (see position_gate)
  bool heading_trusted_ = false;    // the front end's heading is in the map's frame (see heading_gate)
  double trusted_travel_ = 0.0;     // FrontEnd::travel() when it last became so
  // The gates' per-state positions (NaN: none) and heading bins, kept until the map or the localizer's
  // states change, and its mask: nothing allocated or looked up per scan.
  std::vector<Eigen::Vector2d> state_positions_;
  std::vector<int> state_bins_;  // the heading gate's per-state heading bins, kept with the positions
  std::vector<bool> state_beyond_map_;  // per state: at a node, heading where no edge leads (wayOn)
  uint64_t state_positions_revision_ = ~0ull, state_positions_states_revision_ = ~0ull;
  std::vector<bool> gate_allowed_;
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
  int last_edge_ = -1;      // most likely edge and offset at the previous step (eq. 5 misses)
  bool last_forward_ = true;
  double last_offset_ = 0.0;
  std::vector<uint32_t> matched_recently_;  // indices of landmarks of last_edge_ matched lately

  // LoopCheck.
  int departure_bin_ = -1;    // frontierTurn: the bin the robot leaves the junction it creates along
  LoopHypotheses loop_;
  std::vector<Scan> buffer_;  // the scans since the new node: replayed as a new stretch if it is one

  std::vector<std::string> events_;
  std::vector<std::pair<uint32_t, uint32_t>> loops_;
  size_t loops_rejected_ = 0;
};

}  // namespace pomdp_topo
