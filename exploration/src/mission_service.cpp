#include "mission_service.h"

namespace exploration {

using laser_features::Pose2D;

MissionService::MissionService(ros::NodeHandle& nh, Coordinator* coordinator, lockstep::Participant* lockstep,
                               bool count_goals, bool freeze_map, Hooks hooks)
    : nh_(nh), coordinator_(coordinator), lockstep_(lockstep), freeze_map_(freeze_map), hooks_(std::move(hooks)) {
  server_ = std::make_unique<Server>(nh_, "go_to_place", false);
  server_->registerGoalCallback([this] { onGoal(); });
  server_->registerPreemptCallback([this] { onPreempt(); });
  server_->start();
  // In lockstep a goal counts as the step's input from the mission client (the node's upstream):
  // the step waits for it. Subscribed after the server, so on the one callback queue the server
  // takes the goal before this count lets the step run.
  if (lockstep_->enabled() && count_goals)
    goal_count_sub_ = lockstep_->subscribe<hybrid_slam_msgs::GoToPlaceActionGoal>(
        nh_, "go_to_place/goal", 10, [](const hybrid_slam_msgs::GoToPlaceActionGoal::ConstPtr&) {});
}

void MissionService::onGoal() {
  const auto goal = server_->acceptNewGoal();
  const Pose2D g{goal->goal.x, goal->goal.y, goal->goal.theta};
  std::string why;
  if (!coordinator_->startMission(goal->place_id, g, &why)) {
    ROS_WARN("exploration: mission to place %d refused: %s", goal->place_id, why.c_str());
    hybrid_slam_msgs::GoToPlaceResult r;
    r.success = false;
    r.message = "refused: " + why;
    server_->setAborted(r, r.message);
    resultSet();
    return;
  }
  ROS_INFO("exploration: mission to (%.2f, %.2f, %.2f) in place %d", g.x, g.y, g.theta, goal->place_id);
  // Missions run on the finished map: nodes made of a look-alike stretch of hallway (while the
  // belief is briefly wrong) would only add states to confuse the belief with.
  if (freeze_map_ && !map_frozen_) {
    std::string message;
    map_frozen_ = hooks_.freeze_map(&message);
    if (map_frozen_) ROS_INFO("exploration: topological map frozen for missions (%s)", message.c_str());
  }
}

void MissionService::onPreempt() {
  coordinator_->cancelMission("cancelled by the client");
  hooks_.stop_motion();
  hybrid_slam_msgs::GoToPlaceResult r;
  result(&r);
  server_->setPreempted(r, r.message);
  resultSet();
}

void MissionService::result(hybrid_slam_msgs::GoToPlaceResult* r) const {
  const MissionOutcome& o = coordinator_->missionOutcome();
  r->success = o.success;
  r->message = o.message;
  r->path_length = o.path_length;
  hooks_.final_pose(r);
}

void MissionService::resultSet() {
  lockstep_->published(nh_, "go_to_place/result");  // the mission client sees it at the next step
}

void MissionService::afterStep(int current_node, double entropy) {
  if (!server_->isActive()) return;
  if (coordinator_->missionActive()) {
    hybrid_slam_msgs::GoToPlaceFeedback f;
    f.mode = static_cast<uint8_t>(coordinator_->mode());
    f.current_node = current_node;
    f.current_place = coordinator_->mode() == CoordinatorMode::Metric ? coordinator_->placeOfRobot() : -1;
    f.entropy = entropy;
    f.distance_left = coordinator_->missionDistanceLeft();
    server_->publishFeedback(f);
    return;
  }
  hybrid_slam_msgs::GoToPlaceResult r;
  result(&r);
  ROS_INFO("exploration: mission %s: %s (%.1f m)", r.success ? "succeeded" : "failed", r.message.c_str(), r.path_length);
  if (r.success) server_->setSucceeded(r, r.message);
  else server_->setAborted(r, r.message);
  resultSet();
}

}  // namespace exploration
