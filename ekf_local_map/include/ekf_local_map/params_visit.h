// Every tunable parameter of StochasticMap with its name in config/ekf_local_map.yaml, in one list:
// the node reads them with it, the tests check the YAML's defaults against the code's with it.
#pragma once

#include "ekf_local_map/stochastic_map.h"

namespace ekf_local_map {

template <typename Visitor>
void visitParams(StochasticMapParams* p, Visitor&& visit) {
  visit("gate_probability", &p->gate_probability);
  visit("new_line_exclusion_nis", &p->new_line_exclusion_nis);
  visit("extent_margin", &p->extent_margin);
  visit("new_line_min_points", &p->new_line_min_points);
  visit("new_line_min_length", &p->new_line_min_length);
  visit("observation_cov_inflation", &p->observation_cov_inflation);
  visit("observation_alpha_sigma_floor", &p->observation_alpha_sigma_floor);
  visit("observation_r_sigma_floor", &p->observation_r_sigma_floor);
  visit("expected_line_range", &p->expected_line_range);
  visit("occlusion_margin", &p->occlusion_margin);
  visit("gating_failure_min_expected", &p->gating_failure_min_expected);
  visit("gating_failure_min_observations", &p->gating_failure_min_observations);
  visit("relocation_min_matches", &p->relocation_min_matches);
  visit("relocation_joint_probability", &p->relocation_joint_probability);
  visit("relocation_min_angle", &p->relocation_min_angle);
  visit("initial_line_capacity", &p->initial_line_capacity);
}

}  // namespace ekf_local_map
