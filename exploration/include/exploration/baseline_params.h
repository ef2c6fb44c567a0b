// Every tunable parameter of frontier_baseline_node (the frontier-exploration baseline of the
// comparison in issue 6) with its name in config/frontier_baseline.yaml: the node reads them with
// it, a test checks the YAML's defaults against the code's with it.
#pragma once

#include "exploration/frontier_explorer.h"
#include "exploration/occupancy_grid.h"
#include "exploration/params_visit.h"

#include <string>

namespace exploration {

/// Every tunable parameter of the node (config/frontier_baseline.yaml documents each with its unit
/// and the same default).
struct BaselineParams {
  // Node
  std::string map_frame = "map";         // the grid's frame (ground truth through fake_localization)
  std::string odom_frame = "odom";       // for the odometric travel only
  std::string base_frame = "base_link";  // robot frame
  double control_rate = 20.0;            // Hz (sim time), motion control cycles (cmd_vel)
  double replan_period = 1.0;            // s (sim time), frontiers and the goal's path are recomputed
                                         // this often (and at once when a goal ends)
  double goal_timeout = 30.0;            // s (sim time), no progress towards the goal for this long:
                                         // blacklisted (explore_lite's progress_timeout)
  double goal_reach_tolerance = 0.4;     // m, the goal counts as reached this close
  double blacklist_radius = 0.5;         // m, around a goal given up
  double waypoint_tolerance = 0.3;       // m, the next waypoint of the path is taken this close
  double goal_refresh_distance = 0.25;   // m, a replanned waypoint replaces the controller's goal when
                                         // it moved this much
  double map_publish_period = 5.0;       // s (sim time), baseline_map is published this often
  double progress_period = 30.0;         // s (sim time), a progress line is printed this often
  double max_time = 0.0;                 // s (sim time), the exploration gives up after this; 0: none
  bool shutdown_when_done = true;        // the node ends when the exploration ends
  std::string summary_file;              // JSON summary written at the end; "": none
  OccupancyGridParams grid;
  FrontierParams frontier;
  PlannerParams planner;
  MotionParams motion;
};

template <typename Visitor>
void visitBaselineParams(BaselineParams* p, Visitor&& visit) {
  visit("map_frame", &p->map_frame);
  visit("odom_frame", &p->odom_frame);
  visit("base_frame", &p->base_frame);
  visit("control_rate", &p->control_rate);
  visit("replan_period", &p->replan_period);
  visit("goal_timeout", &p->goal_timeout);
  visit("goal_reach_tolerance", &p->goal_reach_tolerance);
  visit("blacklist_radius", &p->blacklist_radius);
  visit("waypoint_tolerance", &p->waypoint_tolerance);
  visit("goal_refresh_distance", &p->goal_refresh_distance);
  visit("map_publish_period", &p->map_publish_period);
  visit("progress_period", &p->progress_period);
  visit("max_time", &p->max_time);
  visit("shutdown_when_done", &p->shutdown_when_done);
  visit("summary_file", &p->summary_file);
  OccupancyGridParams& g = p->grid;
  visit("grid/resolution", &g.resolution);
  visit("grid/max_range", &g.max_range);
  visit("grid/no_return_free_range", &g.no_return_free_range);
  visit("grid/fill_gaps", &g.fill_gaps);
  FrontierParams& f = p->frontier;
  visit("frontier/min_frontier_size", &f.min_frontier_size);
  visit("frontier/potential_scale", &f.potential_scale);
  visit("frontier/gain_scale", &f.gain_scale);
  visit("frontier/goal_search_radius", &f.goal_search_radius);
  PlannerParams& pl = p->planner;
  visit("planner/allow_unknown", &pl.allow_unknown);
  visit("planner/max_segment_length", &pl.max_segment_length);
  visitMotionParams(&p->motion, visit);
}

/// The robot's footprint (config/robot.yaml): the baseline's planner and motion control.
inline void applyFootprint(const laser_features::RobotFootprint& f, BaselineParams* p) {
  p->motion.robot_radius = p->planner.robot_radius = f.radius;
  p->motion.safety_margin = p->planner.safety_margin = f.safety_margin;
}

}  // namespace exploration
