// Every tunable parameter of pomdp_topo's core with its name in config/pomdp_topo.yaml, in one list:
// the node reads them with it, the tests check the YAML's defaults against the code's with it.
// Parameters several pieces share (resolution, heading bins, building axis, node radius, the line
// quality the heading estimator and the axis estimator use) have one key; sync() copies them into
// every piece.
#pragma once

#include <string>

#include "pomdp_topo/front_end.h"
#include "pomdp_topo/heading_estimator.h"
#include "pomdp_topo/map_builder.h"
#include "pomdp_topo/pomdp_localizer.h"

namespace pomdp_topo {

struct TopoParams {
  PomdpParams pomdp;
  FrontEndParams front_end;
  HeadingEstimatorParams heading;
  MapBuilderParams builder;
  laser_features::BuildingAxisParams axis;  // the building's axis from the first scans' walls
  bool axis_from_walls = true;              // false: axis_angle as given
  int axis_max_scans = 50;                  // scans without agreed walls before axis_angle is used

  /// Copies the shared values (held in `pomdp`) into the other pieces.
  void sync() {
    front_end.resolution = pomdp.resolution;
    front_end.heading_bins = pomdp.heading_bins;
    front_end.axis_angle = pomdp.axis_angle;
    front_end.rules = builder.rules;
    heading.axis_angle = pomdp.axis_angle;
    builder.node_radius = pomdp.node_radius;
    axis.min_line_length = heading.min_line_length;
    axis.max_alpha_sigma = heading.max_alpha_sigma;
  }
};

/// Range checks of every parameter (the POMDP's by PomdpLocalizer::validate). False with the first
/// offending parameter's name and range in `error`.
bool validateParams(const TopoParams& params, std::string* error = nullptr);

template <typename Visitor>
void visitParams(TopoParams* p, Visitor&& visit) {
  // Shared.
  visit("resolution", &p->pomdp.resolution);
  visit("heading_bins", &p->pomdp.heading_bins);
  visit("axis_angle", &p->pomdp.axis_angle);
  visit("node_radius", &p->pomdp.node_radius);
  // POMDP (transition, observation, belief).
  visit("travel_spread", &p->pomdp.travel_spread);
  visit("turn_mid_edge_probability", &p->pomdp.turn_mid_edge_probability);
  visit("turn_lost_mass", &p->pomdp.turn_lost_mass);
  visit("blocked_travel_probability", &p->pomdp.blocked_travel_probability);
  visit("window_ahead", &p->pomdp.window_ahead);
  visit("window_behind", &p->pomdp.window_behind);
  visit("window_lateral", &p->pomdp.window_lateral);
  visit("match_sigma_along", &p->pomdp.match_sigma_along);
  visit("match_sigma_lateral", &p->pomdp.match_sigma_lateral);
  visit("match_orientation_tolerance", &p->pomdp.match_orientation_tolerance);
  visit("false_landmark_probability", &p->pomdp.false_landmark_probability);
  visit("unexplored_landmark_probability", &p->pomdp.unexplored_landmark_probability);
  visit("opening_p_lmap", &p->pomdp.opening_p_lmap);
  visit("observation_weight", &p->pomdp.observation_weight);
  visit("heading_sigma", &p->pomdp.heading_sigma);
  visit("heading_floor", &p->pomdp.heading_floor);
  visit("uniform_mixing", &p->pomdp.uniform_mixing);
  visit("entropy_max", &p->pomdp.entropy_max);
  visit("lost_likelihood", &p->pomdp.lost_likelihood);
  visit("lost_steps", &p->pomdp.lost_steps);
  visit("max_cells_per_edge", &p->pomdp.max_cells_per_edge);
  // Heading estimator.
  visit("heading_gate_probability", &p->heading.gate_probability);
  visit("heading_odometry_variance_per_rad", &p->heading.odometry_variance_per_rad);
  visit("heading_odometry_variance_per_m", &p->heading.odometry_variance_per_m);
  visit("heading_min_line_length", &p->heading.min_line_length);
  visit("heading_initial_variance", &p->heading.initial_variance);
  visit("heading_max_alpha_sigma", &p->heading.max_alpha_sigma);
  // The building's axis.
  visit("axis_from_walls", &p->axis_from_walls);
  visit("axis_min_wall_length", &p->axis.min_wall_length);
  visit("axis_min_agreement", &p->axis.min_agreement);
  visit("axis_cluster_width", &p->axis.cluster_width);
  visit("axis_max_scans", &p->axis_max_scans);
  // Front end (tracking, actions).
  visit("turn_hysteresis", &p->front_end.turn_hysteresis);
  visit("turn_settle_angle", &p->front_end.turn_settle_angle);
  visit("max_feature_range", &p->front_end.max_feature_range);
  visit("track_gate", &p->front_end.track_gate);
  visit("min_confidence", &p->front_end.min_confidence);
  visit("observation_range", &p->front_end.observation_range);
  visit("track_max_rotation", &p->front_end.track_max_rotation);
  visit("max_odometry_step", &p->front_end.max_odometry_step);
  // Map building and loop closing.
  visit("mapping", &p->builder.mapping);
  visit("min_node_separation", &p->builder.min_node_separation);
  visit("corner_min_confidence", &p->builder.corner_min_confidence);
  visit("landmark_add_confidence", &p->builder.landmark_add_confidence);
  visit("p_lmap_min", &p->builder.p_lmap_min);
  visit("p_lmap_min_observations", &p->builder.p_lmap_min_observations);
  visit("match_distance", &p->builder.match_distance);
  visit("fingerprint_radius", &p->builder.fingerprint_radius);
  visit("fingerprint_tolerance", &p->builder.fingerprint_tolerance);
  visit("leave_graph_distance", &p->builder.leave_graph_distance);
  visit("loop_gate_base", &p->builder.loop_gate_base);
  visit("loop_gate_per_m", &p->builder.loop_gate_per_m);
  visit("loop_fingerprint_min", &p->builder.loop_fingerprint_min);
  visit("loop_new_place_prior", &p->builder.loop_new_place_prior);
  visit("loop_new_landmark_probability", &p->builder.loop_new_landmark_probability);
  visit("loop_false_landmark_probability", &p->builder.loop_false_landmark_probability);
  visit("loop_decision_log_odds", &p->builder.loop_decision_log_odds);
  visit("loop_verify_distance", &p->builder.loop_verify_distance);
  visit("position_gate", &p->builder.position_gate);
  visit("position_gate_per_m", &p->builder.position_gate_per_m);
  visit("update_position_tolerance", &p->builder.update_position_tolerance);
  visit("heading_gate", &p->builder.heading_gate);
  visit("start_node_closed", &p->builder.start_node_closed);
}

}  // namespace pomdp_topo
