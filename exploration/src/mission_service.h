// The exploration node's GoToPlace action server (`go_to_place`): a goal goes to the coordinator as
// a mission, feedback follows each coordinator step, the result is set once the mission ended. In
// lockstep, with a mission client named (~mission_client), goals and results are counted, so a
// goal is taken at the step it was sent and its result seen by the client at the next. Node-side (ROS).
#pragma once

#include <actionlib/server/simple_action_server.h>
#include <hybrid_slam_msgs/GoToPlaceAction.h>
#include <ros/ros.h>

#include <functional>
#include <memory>
#include <string>

#include "exploration/coordinator.h"
#include "lockstep/participant.h"

namespace exploration {

class MissionService {
 public:
  struct Hooks {
    std::function<void()> stop_motion;                                 // a preempted mission's motion cancelled
    std::function<bool(std::string*)> freeze_map;                      // pomdp_topo's mapping off (set_mapping false)
    std::function<void(hybrid_slam_msgs::GoToPlaceResult*)> final_pose;  // the EKF's last pose in the place, if any
  };

  /// `count_goals`: lockstep with a mission client (the node's upstream); `freeze_map`: the first
  /// mission turns pomdp_topo's mapping off.
  MissionService(ros::NodeHandle& nh, Coordinator* coordinator, lockstep::Participant* lockstep, bool count_goals,
                 bool freeze_map, Hooks hooks);

  /// After each coordinator step: the mission's feedback (`current_node`, -1 if the belief is not
  /// confident; the belief's `entropy`), or its result once it ended.
  void afterStep(int current_node, double entropy);

 private:
  using Server = actionlib::SimpleActionServer<hybrid_slam_msgs::GoToPlaceAction>;
  void onGoal();
  void onPreempt();
  void result(hybrid_slam_msgs::GoToPlaceResult* r) const;
  void resultSet();

  ros::NodeHandle nh_;
  Coordinator* coordinator_;
  lockstep::Participant* lockstep_;
  bool freeze_map_ = true;
  bool map_frozen_ = false;
  Hooks hooks_;
  std::unique_ptr<Server> server_;
  ros::Subscriber goal_count_sub_;
};

}  // namespace exploration
