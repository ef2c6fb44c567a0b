#include "exploration/path_driver.h"

namespace exploration {

PathDriver::PathDriver(const MotionParams& motion, const PathDriverParams& params) : params_(params), motion_(motion) {}

void PathDriver::sendGoal(const Eigen::Vector2d& target) {
  motion_.setGoal(target.x(), target.y());
  target_ = target;
}

bool PathDriver::skipReached(const Eigen::Vector2d& robot) {
  // The next waypoint when near the current (the last one is the goal: driven to exactly).
  const std::size_t first = waypoint_;
  while (waypoint_ + 1 < waypoints_.size() && (waypoints_[waypoint_] - robot).norm() <= params_.waypoint_tolerance)
    ++waypoint_;
  return waypoint_ != first;
}

void PathDriver::follow(const std::vector<Eigen::Vector2d>& path, const Eigen::Vector2d& robot) {
  if (path.empty()) return;
  waypoints_.assign(path.begin() + (path.size() > 1 ? 1 : 0), path.end());
  waypoint_ = 0;
  skipReached(robot);
  const Eigen::Vector2d& target = waypoints_[waypoint_];
  if (!motion_.hasGoal() || (target - target_).norm() > params_.goal_refresh_distance) sendGoal(target);
}

void PathDriver::stop() {
  waypoints_.clear();
  waypoint_ = 0;
  motion_.cancel();
}

void PathDriver::setScan(const std::vector<Eigen::Vector2d>& points_in_robot, double stamp) {
  motion_.setScan(points_in_robot, stamp);
}

PathDriver::Step PathDriver::update(const laser_features::Pose2D& pose, double now, double dt, bool bumper) {
  Step step;
  const Eigen::Vector2d robot = pose.translation();
  if (!waypoints_.empty()) {
    if (skipReached(robot)) sendGoal(waypoints_[waypoint_]);
    if (waypoint_ + 1 == waypoints_.size() && (waypoints_.back() - robot).norm() <= params_.goal_reach_tolerance &&
        !reached_) {
      reached_ = true;
      step.replan = true;
    }
  }
  step.command = motion_.update(pose, now, dt, bumper);
  step.status = motion_.status();
  if (step.status != last_status_) {
    last_status_ = step.status;
    if (step.status == MotionStatus::Reached && !waypoints_.empty()) {
      if (waypoint_ + 1 < waypoints_.size()) {
        sendGoal(waypoints_[++waypoint_]);
      } else {
        reached_ = true;
        step.replan = true;
      }
    } else if ((step.status == MotionStatus::Blocked || step.status == MotionStatus::Bumped) && !waypoints_.empty()) {
      stopped_ = true;
      step.replan = true;
      step.warn = true;
    } else if (step.status == MotionStatus::NoScan || step.status == MotionStatus::Invalid) {
      step.warn = true;
    }
  }
  return step;
}

void PathDriver::takeEnds(bool* reached, bool* stopped) {
  *reached = reached_;
  *stopped = stopped_;
  reached_ = stopped_ = false;
}

}  // namespace exploration
