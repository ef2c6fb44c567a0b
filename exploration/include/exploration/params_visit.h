// Every tunable parameter of the exploration node with its name in config/exploration.yaml, in one
// list: the node reads them with it, the tests check the YAML's defaults against the code's with it.
#pragma once

#include "exploration/coordinator_params.h"
#include "exploration/motion_controller.h"
#include "laser_features/robot_footprint.h"

namespace exploration {

struct ExplorationParams {
  CoordinatorParams coordinator;
  MotionParams motion;
};

/// The motion controller's parameters under "motion/" (shared by exploration_node and the
/// frontier baseline, so both drive the same robot the same way).
template <typename Visitor>
void visitMotionParams(MotionParams* m, Visitor&& visit) {
  visit("motion/max_linear", &m->max_linear);
  visit("motion/max_angular", &m->max_angular);
  visit("motion/max_linear_accel", &m->max_linear_accel);
  visit("motion/max_angular_accel", &m->max_angular_accel);
  visit("motion/goal_tolerance", &m->goal_tolerance);
  visit("motion/heading_tolerance", &m->heading_tolerance);
  visit("motion/lookahead", &m->lookahead);
  visit("motion/slow_down_distance", &m->slow_down_distance);
  visit("motion/min_linear", &m->min_linear);
  visit("motion/heading_gain", &m->heading_gain);
  visit("motion/turn_in_place_angle", &m->turn_in_place_angle);
  visit("motion/reverse_distance", &m->reverse_distance);
  visit("motion/candidate_headings", &m->candidate_headings);
  visit("motion/scan_timeout", &m->scan_timeout);
  visit("motion/stuck_time", &m->stuck_time);
  visit("motion/progress_distance", &m->progress_distance);
  visit("motion/progress_angle", &m->progress_angle);
}

template <typename Visitor>
void visitParams(ExplorationParams* p, Visitor&& visit) {
  CoordinatorParams& c = p->coordinator;
  visit("lookahead", &c.follow.lookahead);
  visit("end_distance", &c.follow.end_distance);
  visit("door_min_confidence", &c.doors.min_confidence);
  visit("door_wall_tolerance", &c.doors.wall_tolerance);
  visit("door_wall_memory", &c.doors.wall_memory);
  visit("door_same_distance", &c.doors.same_distance);
  visit("settle_time", &c.settle_time);
  visit("branch_record_distance", &c.branch_record_distance);
  visit("u_turn_cost", &c.route.u_turn_cost);
  visit("max_route_attempts", &c.route.max_route_attempts);
  visit("goal_pass_distance", &c.route.goal_pass_distance);
  visit("jump_tolerance", &c.route.jump_tolerance);
  visit("jump_hold_distance", &c.route.jump_hold_distance);
  visit("goal_refresh_distance", &c.follow.goal_refresh_distance);
  visit("follow_stall_time", &c.follow.stall_time);
  visit("max_time", &c.max_time);
  visit("explore", &c.explore);
  MissionParams& m = c.mission;
  visit("mission/relocation_timeout", &m.relocation_timeout);
  visit("mission/max_relocation_failures", &m.max_relocation_failures);
  visit("mission/time_limit", &m.time_limit);
  visit("mission/stall_time", &m.stall_time);
  visit("mission/goal_tolerance", &m.goal_tolerance);
  visit("mission/heading_tolerance", &m.heading_tolerance);
  visit("mission/refine_attempts", &m.refine_attempts);
  visit("mission/accept_distance", &m.accept_distance);
  visit("mission/accept_angle", &m.accept_angle);
  HallwayViewParams& h = c.hallway;
  visit("hallway/ahead_sector", &h.ahead_sector);
  visit("hallway/side_open_distance", &h.side_open_distance);
  visit("hallway/wall_parallel_tolerance", &h.wall_parallel_tolerance);
  visit("hallway/wall_min_length", &h.wall_min_length);
  visit("hallway/min_wall_clearance", &h.min_wall_clearance);
  visit("hallway/wall_same_lateral", &h.wall_same_lateral);
  RoomVisitParams& v = c.room_visit;
  visit("room_visit/time_limit", &v.time_limit);
  visit("room_visit/replan_period", &v.replan_period);
  visit("room_visit/exit_time_limit", &v.exit_time_limit);
  visit("room_visit/inner_rooms", &v.inner_rooms);
  RoomExplorerParams& r = c.room;
  visit("room/max_extent", &r.max_extent);
  visit("room/entry_depth", &r.entry_depth);
  visit("room/entry_goal_extra", &r.entry_goal_extra);
  visit("room/exit_depth", &r.exit_depth);
  visit("room/door_wall_extension", &r.door_wall_extension);
  visit("room/opening_merge_distance", &r.opening_merge_distance);
  visit("room/goal_reach_tolerance", &r.goal_reach_tolerance);
  visit("room/max_goal_time", &r.max_goal_time);
  visit("room/blacklist_radius", &r.blacklist_radius);
  visit("room/max_goals", &r.max_goals);
  visit("room/resolution", &r.grid.resolution);
  visit("room/min_frontier_size", &r.frontier.min_frontier_size);
  visitMotionParams(&p->motion, visit);
}

/// The robot's footprint (config/robot.yaml) where the exploration keeps the robot clear: motion
/// control and the room's planner.
inline void applyFootprint(const laser_features::RobotFootprint& f, ExplorationParams* p) {
  p->motion.robot_radius = p->coordinator.room.planner.robot_radius = f.radius;
  p->motion.safety_margin = p->coordinator.room.planner.safety_margin = f.safety_margin;
}

}  // namespace exploration
