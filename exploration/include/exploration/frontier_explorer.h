// The frontier-exploration baseline the topological explorer is compared against: greedy frontier
// exploration on an occupancy grid (Yamauchi 1997, "A frontier-based approach for autonomous
// exploration"; the frontier cost of explore_lite, Hörner 2016), with a grid planner
// (exploration/grid_planner.h).
//
// FrontierExplorer: frontier cells are Free cells with an Unknown 4-neighbour inside the grid (a
// fixed grid's border is no frontier: nothing can be learnt beyond it) that touches no Occupied
// cell (an Unknown cell next to an obstacle is the unseen side of that obstacle: a wall's cells
// between two returns, the cell row the returns of a wall lying on a cell boundary round into;
// without this rule every wall face flickers into frontiers); 8-connected clusters of at least
// min_frontier_size are frontiers. One Dijkstra from the robot gives the path length to every
// cell; a frontier's goal is the reachable cell nearest its centroid among the cells near the
// frontier; the cost is  potential_scale * path length - gain_scale * size  (m, m), the cheapest
// frontier not blacklisted is the next goal, and none left means exploration is complete.
//
// ROS-free: Eigen, laser_features' geometry and the standard library only.
#pragma once

#include "exploration/grid_planner.h"
#include "exploration/occupancy_grid.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace exploration {

// ---------------------------------------------------------------------------------------------
// Frontiers

struct FrontierParams {
  double min_frontier_size = 0.5;   // m, clusters smaller than this (cells * resolution) are ignored
  double potential_scale = 3.0;     // 1/m, cost per metre of path to the frontier (explore_lite's
                                    // launch files: 3.0)
  double gain_scale = 1.0;          // 1/m, cost per metre of frontier (explore_lite's: 1.0)
  double goal_search_radius = 1.0;  // m, the goal is taken among the cells this close to the frontier
                                    // (8-connected steps through Free cells)
};

/// A frontier: a cluster of frontier cells.
struct Frontier {
  std::vector<CellIndex> cells;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  // m, mean of the cells' centres
  double size = 0.0;                                   // m, cells * resolution (as explore_lite)
  Eigen::Vector2d goal = Eigen::Vector2d::Zero();      // m, goal cell's centre (when reachable)
  double path_length = std::numeric_limits<double>::infinity();  // m, from the robot to the goal
  double cost = std::numeric_limits<double>::infinity();
  bool reachable = false;
  bool blacklisted = false;
};

/// The frontiers of `grid` with at least `min_size` (m), unsorted, without goals.
std::vector<Frontier> findFrontiers(const OccupancyGrid& grid, double min_size);

enum class ExplorerStatus {
  Goal,      // nextGoal() returned a goal
  Complete,  // no reachable frontier remains (blacklisted ones count as gone)
  Invalid,   // the robot position is non-finite or outside the map
};

const char* toString(ExplorerStatus status);

class FrontierExplorer {
 public:
  /// Throws std::invalid_argument when validate() refuses `params` or GridPlanner refuses
  /// `planner_params`.
  explicit FrontierExplorer(const FrontierParams& params = FrontierParams(),
                            const PlannerParams& planner_params = PlannerParams());
  static bool validate(const FrontierParams& params, std::string* error = nullptr);
  const FrontierParams& params() const { return params_; }

  /// The goal (map frame, m) of the cheapest reachable frontier not blacklisted, seen from the
  /// robot at `robot_xy`; none when exploration is complete or the input is invalid (status()).
  std::optional<Eigen::Vector2d> nextGoal(const OccupancyGrid& grid, const Eigen::Vector2d& robot_xy);
  ExplorerStatus status() const { return status_; }

  /// The frontiers of the last nextGoal(), cheapest first (unreachable and blacklisted last).
  const std::vector<Frontier>& frontiers() const { return frontiers_; }
  /// The path from the robot to the last goal (empty without one).
  const Path& goalPath() const { return path_; }

  /// Frontiers whose centroid or goal lies within `radius` (m) of `point` are skipped from now on
  /// (e.g. a goal not reached within a timeout: the caller's decision). Non-finite input ignored.
  void blacklist(const Eigen::Vector2d& point, double radius);
  void clearBlacklist() { blacklist_.clear(); }
  std::size_t blacklistSize() const { return blacklist_.size(); }

  /// The planner on the snapshot of the last nextGoal()'s grid (more plans on the same map).
  GridPlanner& planner() { return planner_; }
  const GridPlanner& planner() const { return planner_; }

 private:
  struct Disc {
    Eigen::Vector2d center;
    double radius;
  };
  bool isBlacklisted(const Eigen::Vector2d& p) const;
  void chooseGoal(const OccupancyGrid& grid, Frontier* f);

  FrontierParams params_;
  GridPlanner planner_;
  std::vector<Disc> blacklist_;
  std::vector<Frontier> frontiers_;
  Path path_;
  ExplorerStatus status_ = ExplorerStatus::Complete;
  std::vector<std::uint32_t> stamp_;  // per cell: the last goal search that visited it
  std::uint32_t stamp_counter_ = 0;
  std::vector<std::pair<int, int>> queue_;  // goal search scratch: cell index, steps
};

}  // namespace exploration
