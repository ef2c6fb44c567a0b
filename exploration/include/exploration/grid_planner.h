// GridPlanner, the grid path planner of the room explorer, the hallway navigator and the
// frontier-exploration baseline: A* / Dijkstra, 8-connected without corner cutting, on a snapshot
// of the grid where a cell is traversable when it is Free (or Unknown, with allow_unknown) and no
// Occupied cell's centre lies within inflationRadius() (robot_radius + safety_margin and half a
// cell's diagonal) of its centre (the robot inflated into the obstacles; by default the Unknown
// cells bordering Free ones too), nor within that of a point given by addObstacles() (the scan's
// returns).
// A start inside the inflation (the robot close to a wall, as the motion controller allows) leaves
// it through free cells within start_escape_distance (never nearer to a point of addObstacles()
// whose inflation it is in); no path ever enters the inflation after that. The escape is one
// straight leg to the first traversable cell of the path. Paths are simplified by line of sight
// (every cell a segment touches is traversable).
//
// ROS-free: Eigen and the standard library only.
#pragma once

#include "exploration/occupancy_grid.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace exploration {

struct PlannerParams {
  double robot_radius = 0.25;          // m, the robot is a circle (as in MotionParams)
  double safety_margin = 0.10;         // m, clearance on top of robot_radius (as in MotionParams)
  bool allow_unknown = false;          // -, Unknown cells are traversable (optimistic planning)
  bool inflate_unknown = true;         // -, without allow_unknown: Unknown cells next to Free ones are
                                       // inflated like obstacles (what is not seen may be a wall: a
                                       // frontier's goal keeps the robot clear of it)
  double start_escape_distance = 0.5;  // m, a start inside the inflation may cross this much of it
  double max_segment_length = 2.0;     // m, simplified waypoints at most this far apart (0: no limit;
                                       // the motion controller sees obstacles in the scan only, so
                                       // shorter legs keep it near the planned corridor)
};

/// A planned path in the map frame.
struct Path {
  std::vector<Eigen::Vector2d> waypoints;  // m: the start, the line-of-sight corners, the goal
  double length = 0.0;                     // m, along the waypoints
  std::size_t cells = 0;                   // -, cells of the grid path before simplification
};

class GridPlanner {
 public:
  static constexpr double kHalfDiagonal = 0.70710678118;  // cells: half a cell's diagonal (inflationRadius())
  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit GridPlanner(const PlannerParams& params = PlannerParams());
  static bool validate(const PlannerParams& params, std::string* error = nullptr);
  const PlannerParams& params() const { return params_; }
  /// m, what the motion controller keeps from every scan point: robot_radius + safety_margin.
  double clearance() const { return params_.robot_radius + params_.safety_margin; }
  /// m, the inflation around an Occupied cell's centre and a point of addObstacles(): clearance()
  /// and half a cell's diagonal, once a map is set. A path's line-of-sight segment passes up to
  /// half a diagonal nearer to an obstacle than the centres of the traversable cells it touches:
  /// with it, every point of a path keeps the controller's clearance. A passage planned by less
  /// (between a table's legs) leaves the controller, which needs that clearance along its heading,
  /// turning to and fro before it.
  double inflationRadius() const { return clearance() + kHalfDiagonal * resolution_; }

  /// Takes a snapshot of `grid`'s traversability (the inflation); later changes of the grid are
  /// not seen until the next call. O(cells + boundary cells * inflation disk).
  void setMap(const OccupancyGrid& grid);
  bool hasMap() const { return width_ > 0 && height_ > 0; }

  /// Blocks the snapshot's cells of `points` (grid frame, m) and stamps the inflation around them,
  /// whatever the grid says there: the latest scan's returns, which the motion controller keeps its
  /// clearance from. A log-odds grid loses thin obstacles (a chair's or a table's leg, 2-5 cm, is
  /// one cell that the beams passing beside it through that cell mark free), and a path planned
  /// between two legs that the controller will not drive between leaves the robot turning to and
  /// fro before them. A start within a point's inflation leaves it as the controller lets the robot
  /// move there: never nearer to any point it is within the inflation of (the controller's free
  /// distance is zero towards such a point, MotionController::freeDistance). Points outside the
  /// snapshot or non-finite are skipped; setMap() forgets them.
  void addObstacles(const std::vector<Eigen::Vector2d>& points);

  /// A* from `start` to `goal` (map frame, m). None when a point is non-finite or outside the
  /// map, or the goal cannot be reached (its cell not traversable, or enclosed).
  std::optional<Path> plan(const Eigen::Vector2d& start, const Eigen::Vector2d& goal);

  /// Dijkstra from `start` over the whole snapshot (one search for many goals). False when the
  /// start is non-finite or outside the map.
  bool computeDistances(const Eigen::Vector2d& start);
  /// Path length (m) from the start of the last computeDistances() to the cell's centre; +inf when
  /// unreachable, outside the map or after plan() (which reuses the buffers).
  double distance(int ix, int iy) const;
  /// The path to `goal` from the start of the last computeDistances(); none when unreachable.
  std::optional<Path> pathTo(const Eigen::Vector2d& goal) const;

  /// In the snapshot: not blocked by an obstacle, its inflation, a point of addObstacles() and its
  /// inflation, or (without allow_unknown) the unknown.
  bool traversable(int ix, int iy) const;
  /// In the snapshot: every cell the segment between the cells of a and b touches is traversable
  /// (the line of sight paths are simplified by). False outside the snapshot.
  bool clearLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;
  /// Cells settled by the last search.
  std::size_t expandedCells() const { return expanded_; }
  /// The snapshot's cell size, m, and extent (as the grid's).
  double resolution() const { return resolution_; }
  int minX() const { return min_x_; }
  int minY() const { return min_y_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  // kNearSeen: within the inflation of a point of addObstacles() (and not blocked).
  enum Pass : std::uint8_t { kBlocked = 0, kInflated = 1, kOpen = 2, kNearSeen = 3 };

  bool cellOf(const Eigen::Vector2d& p, int* index) const;  // false: outside or non-finite
  bool search(int start, int goal);                          // goal < 0: Dijkstra to all
  std::optional<Path> extract(int goal, const Eigen::Vector2d& start_point,
                              const Eigen::Vector2d& goal_point) const;
  bool lineOfSight(int a, int b) const;
  // A move from cell `from` to cell `to` gets nearer to no point of addObstacles() whose inflation
  // covers `to` (cell centres).
  bool recedes(int from, int to) const;
  Eigen::Vector2d center(int index) const;

  PlannerParams params_;
  double resolution_ = 0.0;
  int min_x_ = 0, min_y_ = 0, width_ = 0, height_ = 0;
  std::vector<std::uint8_t> pass_;
  // The points of addObstacles(), and for each cell the ones whose inflation covers it: the indices
  // seen_near_[seen_first_[i] .. seen_first_[i + 1]) (empty without points).
  std::vector<Eigen::Vector2d> seen_;
  std::vector<std::int32_t> seen_first_, seen_near_;
  std::vector<float> g_;           // m, path length from the start
  std::vector<std::int32_t> parent_;
  int start_ = -1;                 // cell of the last search's start
  Eigen::Vector2d start_point_ = Eigen::Vector2d::Zero();
  bool distances_valid_ = false;   // g_ holds a complete Dijkstra
  std::size_t expanded_ = 0;
};

}  // namespace exploration
