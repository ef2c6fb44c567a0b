// Range checks of every pomdp_topo parameter (TopoParams): a wrong value in the YAML ends the node
// with the parameter's name instead of a map built with it.
#include <cmath>
#include <string>

#include "pomdp_topo/params_visit.h"

namespace pomdp_topo {

bool validateParams(const TopoParams& p, std::string* error) {
  std::string why;
  if (!PomdpLocalizer::validate(p.pomdp, &why)) {
    if (error) *error = why;
    return false;
  }
  bool ok = true;
  auto need = [&](bool condition, const char* text) {
    if (ok && !condition) {
      ok = false;
      if (error) *error = text;
    }
  };
  auto finite = [](double v) { return std::isfinite(v); };
  auto positive = [&](double v) { return finite(v) && v > 0.0; };
  auto nonneg = [&](double v) { return finite(v) && v >= 0.0; };
  auto unit = [&](double v) { return finite(v) && v >= 0.0 && v <= 1.0; };
  const HeadingEstimatorParams& h = p.heading;
  need(finite(h.gate_probability) && h.gate_probability > 0.0 && h.gate_probability < 1.0,
       "heading_gate_probability must be in (0, 1)");
  need(nonneg(h.odometry_variance_per_rad), "heading_odometry_variance_per_rad must be >= 0");
  need(nonneg(h.odometry_variance_per_m), "heading_odometry_variance_per_m must be >= 0");
  need(nonneg(h.min_line_length), "heading_min_line_length must be >= 0");
  need(positive(h.initial_variance), "heading_initial_variance must be > 0");
  need(positive(h.max_alpha_sigma), "heading_max_alpha_sigma must be > 0");
  need(positive(p.axis.min_wall_length), "axis_min_wall_length must be > 0");
  need(unit(p.axis.min_agreement), "axis_min_agreement must be in [0, 1]");
  need(positive(p.axis.cluster_width) && p.axis.cluster_width < 0.39, "axis_cluster_width must be in (0, 0.39) rad");
  need(p.axis_max_scans >= 1, "axis_max_scans must be >= 1");
  const FrontEndParams& f = p.front_end;
  need(nonneg(f.turn_hysteresis), "turn_hysteresis must be >= 0");
  need(positive(f.turn_settle_angle), "turn_settle_angle must be > 0");
  need(positive(f.max_feature_range), "max_feature_range must be > 0");
  need(positive(f.track_gate), "track_gate must be > 0");
  need(unit(f.min_confidence), "min_confidence must be in [0, 1]");
  need(positive(f.observation_range), "observation_range must be > 0");
  need(positive(f.track_max_rotation), "track_max_rotation must be > 0");
  need(positive(f.max_odometry_step), "max_odometry_step must be > 0");
  const MapBuilderParams& b = p.builder;
  std::string rules_error;
  const bool rules_valid = b.rules.valid(&rules_error);
  need(rules_valid, rules_error.c_str());
  std::string tracks_error;
  const bool tracks_valid = f.tracks.valid(&tracks_error);
  need(tracks_valid, tracks_error.c_str());
  need(nonneg(b.min_node_separation), "min_node_separation must be >= 0");
  need(unit(b.corner_min_confidence), "corner_min_confidence must be in [0, 1]");
  need(unit(b.landmark_add_confidence), "landmark_add_confidence must be in [0, 1]");
  need(unit(b.p_lmap_min), "p_lmap_min must be in [0, 1]");
  need(b.p_lmap_min_observations >= 1, "p_lmap_min_observations must be >= 1");
  need(positive(b.match_distance), "match_distance must be > 0");
  need(positive(b.fingerprint_radius), "fingerprint_radius must be > 0");
  need(positive(b.fingerprint_tolerance), "fingerprint_tolerance must be > 0");
  need(nonneg(b.leave_graph_distance), "leave_graph_distance must be >= 0");
  need(nonneg(b.loop_gate_base), "loop_gate_base must be >= 0");
  need(nonneg(b.loop_gate_per_m), "loop_gate_per_m must be >= 0");
  need(unit(b.loop_fingerprint_min), "loop_fingerprint_min must be in [0, 1]");
  // Probabilities inside the loop test's log odds: 0 or 1 would give infinities.
  need(finite(b.loop_new_place_prior) && b.loop_new_place_prior > 0.0 && b.loop_new_place_prior < 1.0,
       "loop_new_place_prior must be in (0, 1)");
  need(finite(b.loop_new_landmark_probability) && b.loop_new_landmark_probability > 0.0 &&
           b.loop_new_landmark_probability < 1.0,
       "loop_new_landmark_probability must be in (0, 1)");
  need(finite(b.loop_false_landmark_probability) && b.loop_false_landmark_probability > 0.0 &&
           b.loop_false_landmark_probability < 1.0,
       "loop_false_landmark_probability must be in (0, 1)");
  need(positive(b.loop_decision_log_odds), "loop_decision_log_odds must be > 0");
  need(positive(b.loop_verify_distance), "loop_verify_distance must be > 0");
  need(nonneg(b.position_gate), "position_gate must be >= 0");
  need(nonneg(b.position_gate_per_m), "position_gate_per_m must be >= 0");
  need(nonneg(b.update_position_tolerance), "update_position_tolerance must be >= 0");
  return ok;
}

}  // namespace pomdp_topo
