// Every tunable parameter of FeatureExtractor with its name in config/laser_features.yaml, in one
// list: the node reads them from the parameter server with it, the tests check the YAML's defaults
// against the code's with it.
#pragma once

#include "laser_features/feature_extractor.h"

namespace laser_features {

/// Calls visit(name, pointer) for each parameter; `name` is the YAML path ("lines/range_sigma").
template <typename Visitor>
void visitParams(FeatureExtractorParams* p, Visitor&& visit) {
  visit("max_beams", &p->max_beams);
  visit("circular_tolerance_beams", &p->circular_tolerance_beams);
  visit("lines/range_sigma", &p->lines.range_sigma);
  visit("lines/range_sigma_per_meter", &p->lines.range_sigma_per_meter);
  visit("lines/bearing_sigma", &p->lines.bearing_sigma);
  visit("lines/breakpoint_lambda", &p->lines.breakpoint_lambda);
  visit("lines/breakpoint_sigma_factor", &p->lines.breakpoint_sigma_factor);
  visit("lines/split_distance", &p->lines.split_distance);
  visit("lines/merge_chi2", &p->lines.merge_chi2);
  visit("lines/trim_sigma", &p->lines.trim_sigma);
  visit("lines/max_trim_per_end", &p->lines.max_trim_per_end);
  visit("lines/merge_max_gap", &p->lines.merge_max_gap);
  visit("lines/min_points", &p->lines.min_points);
  visit("lines/min_length", &p->lines.min_length);
  visit("corners/min_angle", &p->corners.min_angle);
  visit("corners/max_end_distance", &p->corners.max_end_distance);
  visit("corners/min_line_distance", &p->corners.min_line_distance);
  visit("corners/reference_length", &p->corners.reference_length);
  visit("corners/reference_points", &p->corners.reference_points);
  visit("openings/jump_min", &p->openings.jump_min);
  visit("openings/collinear_chi2", &p->openings.collinear_chi2);
  visit("openings/collinear_angle", &p->openings.collinear_angle);
  visit("openings/collinear_distance", &p->openings.collinear_distance);
  visit("openings/line_tolerance", &p->openings.line_tolerance);
  visit("openings/min_line_distance", &p->openings.min_line_distance);
  visit("openings/max_range_fraction", &p->openings.max_range_fraction);
  visit("openings/hallway_parallel_angle", &p->openings.hallway_parallel_angle);
  visit("openings/hallway_step_max_offset", &p->openings.hallway_step_max_offset);
  visit("openings/duplicate_distance", &p->openings.duplicate_distance);
  visit("place/horizon", &p->place.horizon);
  visit("place/width_softness", &p->place.width_softness);
  visit("place/min_elongation", &p->place.min_elongation);
  visit("place/full_elongation", &p->place.full_elongation);
  visit("place/max_vertices", &p->place.max_vertices);
  visit("place/wall_parallel_angle", &p->place.wall_parallel_angle);
  visit("place/min_wall_length", &p->place.min_wall_length);
  visit("odometry_consistency/max_range", &p->odometry_consistency.max_range);
  visit("odometry_consistency/tolerance", &p->odometry_consistency.tolerance);
  visit("odometry_consistency/tolerance_per_m", &p->odometry_consistency.tolerance_per_m);
  visit("odometry_consistency/max_gap", &p->odometry_consistency.max_gap);
  visit("odometry_consistency/min_points", &p->odometry_consistency.min_points);
  visit("odometry_consistency/good_enough", &p->odometry_consistency.good_enough);
  visit("odometry_consistency/search_xy", &p->odometry_consistency.search_xy);
  visit("odometry_consistency/search_xy_per_m", &p->odometry_consistency.search_xy_per_m);
  visit("odometry_consistency/search_theta", &p->odometry_consistency.search_theta);
  visit("odometry_consistency/search_theta_per_rad", &p->odometry_consistency.search_theta_per_rad);
  visit("odometry_consistency/recheck_below", &p->odometry_consistency.recheck_below);
}

}  // namespace laser_features
