// The map builder's parameters (MapBuilder, and the loop check it runs: LoopHypotheses); every one in
// config/pomdp_topo.yaml with its unit and default.
#pragma once

#include "laser_features/building_rules.h"

namespace pomdp_topo {

struct MapBuilderParams {
  bool mapping = true;                 // -, false: localization only, the map is never changed
  laser_features::BuildingRules rules;  // side openings up to door_max_width are doors, wider ones
                                        // junctions (config/building.yaml)
  double min_node_separation = 0.8;    // m, a side opening this close to the last node joins that node
  double node_radius = 1.0;            // m, a turn this close to a node happens at that node
  double corner_min_confidence = 0.5;  // -, corners passed on a new stretch become landmarks above this
  double landmark_add_confidence = 0.7;  // -, an unknown corner passed on a known edge is added above this
  double p_lmap_min = 0.2;             // -, landmarks whose p_lmap falls below this are deleted ...
  int p_lmap_min_observations = 4;     // -, ... once observed (or missed) this many times
  double match_distance = 0.75;        // m, a passed landmark matches an expected one this close along the edge
  double fingerprint_radius = 4.0;     // m, tracked features this close to a new node make its fingerprint
  double fingerprint_tolerance = 0.3;  // rad, fingerprint entries this close in bearing match
  double leave_graph_distance = 1.0;   // m, travel past a node with no edge in that heading before a new stretch starts
  double loop_gate_base = 2.0;         // m, a loop candidate lies within base + per_m x distance ...
  double loop_gate_per_m = 0.05;       // m/m, ... travelled since the last localization on the known graph
  double loop_fingerprint_min = 0.3;   // -, fingerprint similarity a loop candidate needs, [0, 1]
  double loop_new_place_prior = 0.1;   // -, prior of "a new look-alike place" against a candidate at its expected spot
  double loop_new_landmark_probability = 0.3;  // -, likelihood of a landmark on an unexplored stretch
  double loop_false_landmark_probability = 0.05;  // -, likelihood of a landmark the old place does not explain
  double loop_decision_log_odds = 3.0; // -, a hypothesis wins when ahead by this (log odds, about 20:1)
  double loop_verify_distance = 6.0;   // m, past this the better hypothesis wins
  double position_gate = 4.0;          // m, states farther than this from the dead-reckoned position ...
  double position_gate_per_m = 0.01;   // m/m, ... plus this per metre travelled since the map and the dead
                                       // reckoning last agreed (a confident belief within position_gate of
                                       // it; a relocation after a jump) get no belief: a look-alike hallway
                                       // 15 m away is no candidate; nodes zipped after a loop closure lie
                                       // within position_gate; 0 = off
  double update_position_tolerance = 2.5;  // m, while the position gate is on, an opening passed on the
                                       // known map is added to it (to the belief's node, or as a door node
                                       // on its edge) only if its dead-reckoned position lies this close to
                                       // where the belief puts it, and a node the belief would leave the
                                       // known graph from is merged into a node of its type this close
                                       // that has the way on (twinWithWay); a belief beyond the known map
                                       // is kept, and a stretch started, only on its node's way out
                                       // (alongWayOut, departure); 0 = none of these
  bool heading_gate = true;            // -, while the heading is trusted (setHeadingTrusted), states whose
                                       // heading bin is not the front end's get no belief
  bool start_node_closed = false;      // -, the start node has no way but its edges and recorded openings (the
                                       // exploration records an open way behind the robot): a belief leaving it
                                       // elsewhere is wrong, as past a hallway end; false when nobody records them
};

}  // namespace pomdp_topo
