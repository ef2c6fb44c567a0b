// The exploration coordinator's parameters (config/exploration.yaml; params_visit.h names each
// one's key), gathered from the classes it delegates to, and their check.
//
// ROS-free: Eigen, laser_features and the standard library only.
#pragma once

#include "exploration/hallway_doors.h"
#include "exploration/hallway_follower.h"
#include "exploration/hallway_view.h"
#include "exploration/mission_runner.h"
#include "exploration/room_explorer.h"
#include "exploration/room_visit.h"
#include "exploration/route_policy.h"
#include "laser_features/building_rules.h"

#include <string>

namespace exploration {

struct CoordinatorParams {
  HallwayViewParams hallway;
  HallwayFollowerParams follow;      // following a hallway (lookahead, end_distance, goal_refresh_distance,
                                     // follow_stall_time in config/exploration.yaml)
  RoomExplorerParams room;
  laser_features::BuildingRules rules;  // door widths (config/building.yaml): openings outside them are no doors
  HallwayDoorParams doors;           // the hallway's doors (door_* in config/exploration.yaml)
  double settle_time = 0.5;          // s, standing still before a switch (the nodes see the robot stopped)
  RoomVisitParams room_visit;        // a room's visit (room_visit/* in config/exploration.yaml)
  double branch_record_distance = 1.0;  // m travelled after a turn before the ways not taken are recorded
  RoutePolicyParams route;           // the route's rules (u_turn_cost, max_route_attempts, jump_tolerance,
                                     // jump_hold_distance, goal_pass_distance in config/exploration.yaml)
  double max_time = 0.0;             // s, the exploration gives up after this (sim time); 0: no limit
  bool explore = true;               // -, explore from the start; false: wait for missions (a loaded map)
  MissionParams mission;             // missions (mission/* in config/exploration.yaml)

  /// True when every value is in its range; else false, and the first one out of it (named by its
  /// key) in `error`.
  bool valid(std::string* error = nullptr) const;
};

}  // namespace exploration
