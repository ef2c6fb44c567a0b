// The frontier baseline's goal keeping, after explore_lite (Hörner 2016): one frontier goal held
// until it is reached or given up, following its frontier as the grid grows, and blacklisted in the
// FrontierExplorer when the robot cannot get there (the motion controller stopped, or no progress
// within a timeout: explore_lite's progress_timeout, where progress is a new shortest planned path).
// frontier_baseline_node plans with it once per replan_period.
//
// ROS-free.
#pragma once

#include "exploration/frontier_explorer.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <vector>

namespace exploration {

struct FrontierGoalParams {
  double reach_tolerance = 0.4;   // m, the goal counts as reached this close (goal_reach_tolerance)
  double timeout = 30.0;          // s, no progress for this long: given up (goal_timeout)
  double blacklist_radius = 0.5;  // m, around a goal given up
  double track_radius = 1.0;      // m, the held goal follows the frontier whose goal or centroid lies
                                  // this close (max(frontier/goal_search_radius, reach_tolerance))
};

class FrontierGoal {
 public:
  /// How the held goal ended in review().
  enum class End { Held, Reached, Stopped, NoProgress };

  explicit FrontierGoal(const FrontierGoalParams& params = FrontierGoalParams()) : params_(params) {}

  /// The held goal ends when reached (`reached`: the controller arrived; or the robot within
  /// reach_tolerance), or is given up and blacklisted in `explorer` when the motion controller
  /// `stopped` (blocked or bumped) or without progress for `timeout` by `now_ns` (ns of sim time:
  /// integer, so that "more than timeout" does not depend on rounding). No goal is held after an end.
  End review(const Eigen::Vector2d& robot, bool reached, bool stopped, int64_t now_ns, FrontierExplorer* explorer);
  /// After explorer->nextGoal(): the held goal follows its frontier (dropped when that is gone, seen
  /// on the way); with no goal held, the cheapest usable frontier becomes the goal. A frontier whose
  /// goal is where the robot stands is unobservable from there (beyond range, glass): blacklisted,
  /// its centroid appended to `unobservable`, else it would be "reached" forever. True when a goal
  /// is held, `*is_new` when it was taken now; false: no usable frontier left.
  bool choose(const Eigen::Vector2d& robot, int64_t now_ns, FrontierExplorer* explorer, bool* is_new,
              std::vector<Eigen::Vector2d>* unobservable);
  /// The planned path to the goal is `path_length` m long: progress when shorter by a grid `cell`
  /// than any since the goal was taken, or when the goal moved away with its frontier.
  void progress(double path_length, double cell, int64_t now_ns);

  const std::optional<Eigen::Vector2d>& goal() const { return goal_; }
  void drop() { goal_.reset(); }

 private:
  std::optional<Eigen::Vector2d> track(const FrontierExplorer& explorer) const;
  std::optional<Eigen::Vector2d> cheapest(const Eigen::Vector2d& robot, FrontierExplorer* explorer,
                                          std::vector<Eigen::Vector2d>* unobservable) const;

  FrontierGoalParams params_;
  std::optional<Eigen::Vector2d> goal_;  // map frame
  Eigen::Vector2d anchor_ = Eigen::Vector2d::Zero();  // where the goal was at the last progress
  double best_length_ = 0.0;   // m, shortest path to the goal since then
  int64_t progress_ns_ = 0;    // ns, sim time of the last progress
};

}  // namespace exploration
