#include "exploration/waypoint_follower.h"

#include <utility>

namespace exploration {

void WaypointFollower::set(std::vector<Eigen::Vector2d> waypoints) {
  waypoints_ = std::move(waypoints);
  index_ = 0;
}

void WaypointFollower::advance(const Eigen::Vector2d& robot, const GridPlanner& planner) {
  while (index_ < waypoints_.size()) {
    const double distance = (waypoints_[index_] - robot).norm();
    if (distance >= kPassRadius) return;
    const bool last = index_ + 1 == waypoints_.size();
    if (!(distance < kOnWaypoint || last || planner.clearLine(robot, waypoints_[index_ + 1]))) return;
    ++index_;
  }
}

bool WaypointFollower::restClear(const Eigen::Vector2d& robot, const GridPlanner& planner) const {
  if (done()) return true;
  if (!planner.clearLine(robot, waypoints_[index_])) return false;
  for (std::size_t i = index_; i + 1 < waypoints_.size(); ++i)
    if (!planner.clearLine(waypoints_[i], waypoints_[i + 1])) return false;
  return true;
}

}  // namespace exploration
