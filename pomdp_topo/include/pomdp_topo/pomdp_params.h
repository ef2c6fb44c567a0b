// Parameters of the topological POMDP (Tomatis, Nourbakhsh & Siegwart, IROS 2001, section 3.3):
// its state space (GraphStates), transition (PomdpLocalizer::predict), observation model
// (ObservationModel) and belief (PomdpLocalizer). config/pomdp_topo.yaml's keys, with the code's
// defaults; PomdpLocalizer::validate() checks them.
#pragma once

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

}  // namespace pomdp_topo
