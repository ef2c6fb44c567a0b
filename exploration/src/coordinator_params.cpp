#include "exploration/coordinator_params.h"

namespace exploration {

bool CoordinatorParams::valid(std::string* error) const {
  auto fail = [&](const char* why) {
    if (error) *error = why;
    return false;
  };
  if (!(follow.lookahead > 0.3)) return fail("lookahead must be > 0.3 m");
  if (!(follow.end_distance > 0.5)) return fail("end_distance must be > 0.5 m");
  if (!rules.valid(error)) return false;
  if (!(doors.min_confidence >= 0.0 && doors.min_confidence <= 1.0)) return fail("door_min_confidence must be in [0, 1]");
  if (!doors.tracks.valid(error)) return false;
  if (!(doors.same_distance > 0.0 && doors.wall_tolerance > 0.0 && doors.wall_memory >= 0.0))
    return fail("door_same_distance and door_wall_tolerance must be > 0, door_wall_memory >= 0");
  if (!RoomVisit::validate(room_visit, error)) return false;
  if (!(settle_time >= 0.0 && max_time >= 0.0)) return fail("settle_time and max_time must be >= 0");
  if (route.max_route_attempts < 1) return fail("max_route_attempts must be >= 1");
  if (!(route.goal_pass_distance > 0.0)) return fail("goal_pass_distance must be > 0");
  if (!(route.jump_tolerance >= 0.0 && route.jump_hold_distance >= 0.0))
    return fail("jump_tolerance and jump_hold_distance must be >= 0");
  if (!(branch_record_distance >= 0.0 && route.u_turn_cost >= 0.0 && follow.goal_refresh_distance > 0.0))
    return fail("branch_record_distance and u_turn_cost must be >= 0, goal_refresh_distance > 0");
  if (!MissionRunner::validate(mission, error)) return false;
  if (!(follow.stall_time > 0.0)) return fail("follow_stall_time must be > 0");
  return RoomExplorer::validate(room, error);
}

}  // namespace exploration
