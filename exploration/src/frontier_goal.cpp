#include "exploration/frontier_goal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace exploration {

FrontierGoal::End FrontierGoal::review(const Eigen::Vector2d& robot, bool reached, bool stopped, int64_t now_ns,
                                       FrontierExplorer* explorer) {
  if (!goal_) return End::Held;
  End end = End::Held;
  if (reached || (robot - *goal_).norm() <= params_.reach_tolerance) {
    end = End::Reached;
  } else if (stopped) {
    end = End::Stopped;
  } else if (now_ns - progress_ns_ > std::llround(params_.timeout * 1e9)) {
    end = End::NoProgress;
  }
  if (end == End::Stopped || end == End::NoProgress) explorer->blacklist(*goal_, params_.blacklist_radius);
  if (end != End::Held) goal_.reset();
  return end;
}

bool FrontierGoal::choose(const Eigen::Vector2d& robot, int64_t now_ns, FrontierExplorer* explorer, bool* is_new,
                          std::vector<Eigen::Vector2d>* unobservable) {
  *is_new = false;
  if (goal_) goal_ = track(*explorer);
  if (goal_) return true;
  goal_ = cheapest(robot, explorer, unobservable);
  if (!goal_) return false;
  *is_new = true;
  anchor_ = *goal_;
  best_length_ = std::numeric_limits<double>::infinity();
  progress_ns_ = now_ns;
  return true;
}

void FrontierGoal::progress(double path_length, double cell, int64_t now_ns) {
  if (!goal_) return;
  if ((*goal_ - anchor_).norm() > params_.reach_tolerance) {  // a new target: the goal moved with its frontier
    anchor_ = *goal_;
    best_length_ = path_length;
    progress_ns_ = now_ns;
  } else if (path_length < best_length_ - cell) {
    best_length_ = path_length;
    progress_ns_ = now_ns;
  }
}

// The usable frontier whose goal or centroid lies within track_radius of the held goal, the one
// whose goal is nearest it.
std::optional<Eigen::Vector2d> FrontierGoal::track(const FrontierExplorer& explorer) const {
  double best = std::numeric_limits<double>::infinity();
  std::optional<Eigen::Vector2d> chosen;
  for (const Frontier& f : explorer.frontiers()) {  // cheapest first, unusable ones last
    if (!f.reachable || f.blacklisted) break;
    const double d = std::min((f.goal - *goal_).norm(), (f.centroid - *goal_).norm());
    if (d <= params_.track_radius && (f.goal - *goal_).norm() < best) {
      best = (f.goal - *goal_).norm();
      chosen = f.goal;
    }
  }
  return chosen;
}

std::optional<Eigen::Vector2d> FrontierGoal::cheapest(const Eigen::Vector2d& robot, FrontierExplorer* explorer,
                                                      std::vector<Eigen::Vector2d>* unobservable) const {
  for (const Frontier& f : explorer->frontiers()) {  // cheapest first, unusable ones last
    if (!f.reachable || f.blacklisted) break;
    if ((f.goal - robot).norm() <= params_.reach_tolerance) {
      explorer->blacklist(f.goal, params_.blacklist_radius);
      if (unobservable) unobservable->push_back(f.centroid);
      continue;
    }
    return f.goal;
  }
  return std::nullopt;
}

}  // namespace exploration
