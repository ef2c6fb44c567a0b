// The METRIC mode of the exploration coordinator: the coverage of one room (Tomatis, Nourbakhsh &
// Siegwart 2001, "Simultaneous localization and map building: a global topological model with local
// metric maps"; the exploration of their section 4: the robot enters an unknown room through a
// door, explores it until its walls are mapped, then leaves it by the same door, and the room
// becomes a node of the topological map with its own small metric map).
//
// RoomExplorer keeps a log-odds occupancy grid of that ONE room (OccupancyGrid, a fixed square of
// half-size max_extent around the entry door; discarded when the next room starts), in the frame of
// the poses given to it (an odometry-like frame: the room is small and visited once, so the drift
// over one room is what the local metric maps of the paper tolerate too). Inside it, greedy
// frontier exploration (FrontierExplorer: Yamauchi 1997, explore_lite's cost) restricted to the room:
//  - Entering: until the robot is entry_depth past the door line, the goal is a fixed point on the
//    door's axis (entry_depth + entry_goal_extra into the room). No virtual wall yet: the robot
//    starts in the doorway, and a wall drawn there would enclose it.
//  - Exploring: a virtual wall (Occupied cells, 2 cells thick) closes the entry door behind the
//    robot, and every other opening reported by blockOpening() (a door to the hallway or to another
//    room): the room's exploration never leaves through them, and the frontiers seen through them
//    are unreachable. On top of that, a frontier whose centroid or goal lies behind the entry door
//    line (on the hallway side) is never chosen: the wall may leak (a door width underestimated,
//    an opening to the hallway nobody reported), and the hallway belongs to the topological level.
//    The goal is the cheapest reachable frontier's; it is kept (tracking its frontier as the map
//    grows) until reached or max_goal_time passed (then its neighbourhood is blacklisted), so the
//    robot does not dither between frontiers of similar cost. A frontier whose goal is where the
//    robot already stands (within goal_reach_tolerance) is unobservable from there (beyond the
//    laser's range, glass): blacklisted, else it would be reached over and over.
//  - Done: no reachable frontier left in the room (its walls are mapped), or max_goals goals issued
//    (a bound on the time spent in a huge room), or the robot could not enter within max_goal_time.
// pathToExit() then gives the way back to the entry door (the virtual wall stays; the caller drives
// the last metres straight out through the door).
//
// The grid's cells are cleared by the scans like any other: the virtual walls are drawn again after
// every addScan() (a scan through a door would free them).
//
// ROS-free: Eigen, laser_features' geometry and the standard library only.
#pragma once

#include "exploration/frontier_explorer.h"
#include "exploration/occupancy_grid.h"
#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace exploration {

struct RoomExplorerParams {
  OccupancyGridParams grid;             // the room's grid (resolution 0.05 m by default)
  FrontierParams frontier;              // min_frontier_size, costs, goal search
  PlannerParams planner;                // robot_radius 0.25, safety_margin 0.10 by default
  double max_extent = 12.0;             // m, the grid is the square of this half-size around the
                                        // entry door (what lies beyond is dropped)
  double entry_depth = 0.7;             // m, the robot counts as inside once this far past the door
                                        // line (must exceed robot_radius: the body is through the
                                        // door when the wall closes behind it)
  double entry_goal_extra = 0.3;        // m, the entering goal lies this much beyond entry_depth
  double exit_depth = 0.6;              // m, pathToExit() ends this far inside the entry door, on
                                        // its axis (RoomVisit turns there to face out, then passes)
  double door_wall_extension = 0.3;     // m, a virtual wall across a door extends this much beyond
                                        // each edge (into the door's jambs: the edges' error)
  double opening_merge_distance = 0.5;  // m, an opening whose centre is this close to a known one's
                                        // (or to the entry door's) is the same opening
  double goal_reach_tolerance = 0.4;    // m, a frontier goal counts as reached this close
  double max_goal_time = 40.0;          // s, a goal not reached in this time is blacklisted (and
                                        // entering that takes longer gives up: Done)
  double blacklist_radius = 0.6;        // m, around a goal given up
  int max_goals = 60;                   // -, the room is Done after this many frontier goals
};

/// The box of a room's free area along its entry door's axes.
struct RoomExtent {
  laser_features::Pose2D door;      // the entry door's centre and direction into the room
  double depth_min = 0.0, depth_max = 0.0;    // m, along the direction into the room
  double across_min = 0.0, across_max = 0.0;  // m, along the door's wall (left +)
  /// `p` (in the frame `door` is in) lies inside, `margin` (m) or more within every edge (a
  /// negative margin: up to that far outside).
  bool contains(const Eigen::Vector2d& p, double margin) const;
};

enum class RoomStatus {
  Entering,   // the robot is not yet entry_depth past the entry door line
  Exploring,  // frontier goals inside the room
  Done,       // nothing left to explore (or max_goals reached, or the room could not be entered)
  Invalid,    // not started, or start() refused its door
};

const char* toString(RoomStatus status);

class RoomExplorer {
 public:
  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit RoomExplorer(const RoomExplorerParams& params = RoomExplorerParams());
  static bool validate(const RoomExplorerParams& params, std::string* error = nullptr);
  const RoomExplorerParams& params() const { return params_; }

  /// Starts a new room (forgets the previous one): the entry door's centre and the direction INTO the
  /// room (x, y, theta, in the pose frame), and its width (m). Status Entering; false (status
  /// Invalid) for a non-finite door or a width <= 0.
  bool start(const laser_features::Pose2D& door, double door_width);

  /// Inserts one scan: the sensor's pose in the frame, the ranges (REP 117: +inf is no return, NaN
  /// and values <= the grid's min_range are skipped), the bearing of beam 0 and the increment (rad).
  /// The virtual walls are drawn again afterwards. False (nothing written) before start(), for a
  /// non-finite pose or angle; `error` says why.
  bool addScan(const laser_features::Pose2D& sensor, const std::vector<float>& ranges, double angle_min,
               double angle_increment, std::string* error = nullptr);

  /// Blocks another opening seen from inside the room (a door to the hallway or to another room) by
  /// a virtual wall between its edge points (pose frame), so the room's exploration never leaves
  /// through it. Remembered in openings() unless it is the entry door or an opening already known
  /// (centres within opening_merge_distance): then nothing is done. Returns whether it was added
  /// (false also before start() and for non-finite or coincident points).
  /// `in_wall`: this sighting shows it as a gap in a wall (laser_features' Opening::in_wall: a door,
  /// not a gap between furniture; kept closed by openFurnitureGaps()).
  bool blockOpening(const Eigen::Vector2d& left, const Eigen::Vector2d& right, bool in_wall = true);
  /// The room's coverage is over: the virtual walls of openings never seen as a gap in a wall (between
  /// table and chair legs, beside a shelf) are taken away, their cells Free (as the scans saw the
  /// gap): they cut the room's free area in pieces (a path across the room, its extent) until
  /// closeFurnitureGaps() draws them again. Returns how many were taken away.
  std::size_t openFurnitureGaps();
  void closeFurnitureGaps();

  /// The next goal (x, y, pose frame) for the robot at `robot` at time `now` (s, any monotonic
  /// clock): while Entering, the point on the door's axis entry_depth + entry_goal_extra inside
  /// (the status turns Exploring, and the entry's wall is drawn, once the robot is entry_depth in);
  /// while Exploring, the held frontier goal or a new one (see the top of the file). The held goal
  /// follows its frontier: it becomes the goal of the usable frontier whose goal or centroid lies
  /// within max(goal_search_radius, goal_reach_tolerance) of it; none such (the frontier was seen on
  /// the way) frees the robot for the next one. Each call runs the frontier search on the room's
  /// grid (O(cells)). None when Done (or Invalid), and for a non-finite input or a robot outside the
  /// grid (status unchanged).
  std::optional<Eigen::Vector2d> nextGoal(const Eigen::Vector2d& robot, double now);
  RoomStatus status() const { return status_; }
  /// Whether the robot got inside (status left Entering) since start().
  bool entered() const { return entered_; }
  /// The path (pose frame) from the robot to the goal of the last nextGoal(): the planner's while
  /// Exploring, the straight segment while Entering; empty without a goal.
  const Path& goalPath() const { return goal_path_; }

  /// The way out: a grid path from `robot` to the point exit_depth inside the entry door on its axis
  /// (or, when that point is not traversable, the traversable cell nearest to it within 0.5 m on the
  /// room's side). The entry's virtual wall stays: the caller drives straight out from there. None
  /// when unreachable, before start() or for a non-finite position. `seen`: the latest scan's
  /// returns (pose frame), obstacles whatever the grid says (GridPlanner::addObstacles), unless no
  /// path leaves them (the robot among table legs it drove in between): then the grid's path.
  std::optional<Path> pathToExit(const Eigen::Vector2d& robot, const std::vector<Eigen::Vector2d>& seen = {});
  /// A grid path from `robot` to `goal` in the room as seen so far (a mission's goal), through its
  /// unseen part too (optimistic: the caller plans again as the room is seen; a goal behind
  /// furniture not yet seen round is otherwise unreachable). None when unreachable on the grid,
  /// before start() or for non-finite points. `seen`: the latest scan's returns (pose frame), kept
  /// clear of as in pathToExit(), unless no path leaves them: then the grid's path.
  std::optional<Path> pathTo(const Eigen::Vector2d& robot, const Eigen::Vector2d& goal,
                             const std::vector<Eigen::Vector2d>& seen = {});
  /// The planners whose snapshots made the last pathToExit() and pathTo() paths.
  const GridPlanner& exitPlanner() const { return explorer_.planner(); }
  const GridPlanner& pathPlanner() const { return optimistic_planner_; }
  /// Where pathToExit() heads for (pose frame).
  Eigen::Vector2d exitPoint() const;

  const OccupancyGrid& grid() const { return grid_; }
  /// The blocked openings other than the entry door (edge points, pose frame), in order of report.
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& openings() const { return openings_; }
  /// m^2 of the room's Free cells: those on the room's side of the entry door line connected to the
  /// entry (through Free cells, 4-connected) - neither the hallway seen through the door nor what is
  /// seen through a blocked opening counts. O(cells).
  double freeArea() const;
  /// An opening of the room (its centre, `into` the room, rad) leads out of it: the point `distance`
  /// (m) behind it lies beyond the room's extent (the box of freeArea()'s cells along the entry door's
  /// axes, by a robot radius: a pocket between furniture and a wall lies within it), the space there
  /// was seen Free (through the opening), and none of it within a robot radius is the room's free
  /// area (the virtual walls close the openings, so a room behind a door is reached only through it,
  /// while the space behind a gap between furniture and a wall is the room's own). O(cells).
  bool leadsOutOfRoom(const Eigen::Vector2d& centre, double into, double distance) const;
  /// The box of freeArea()'s cells along the entry door's axes (pose frame); none without a room.
  std::optional<RoomExtent> extent() const;
  /// Frontier goals issued since start() (the entering goal is not one).
  int goalsIssued() const { return goals_issued_; }
  /// Memory of the room's grid: one byte per cell.
  std::size_t bytes() const { return grid_.bytes(); }

  /// Signed distance (m) of `p` past the entry door line, positive inside the room.
  double depth(const Eigen::Vector2d& p) const { return (p - door_xy_).dot(door_dir_); }

 private:
  void drawVirtualWalls();
  /// freeArea()'s cells, one flag per grid cell (empty when there is no room or no seed).
  std::vector<std::uint8_t> roomCells() const;
  std::optional<RoomExtent> extent(const std::vector<std::uint8_t>& cells) const;
  /// The cells of a virtual wall across a-b set to `state` (Occupied: drawn; Free: taken away).
  void drawWall(const Eigen::Vector2d& a, const Eigen::Vector2d& b, CellState state = CellState::Occupied);
  bool inRoom(const Eigen::Vector2d& p) const { return depth(p) > 0.0; }
  /// The path from `robot` to the exit point (or the traversable cell nearest to it within
  /// kExitSearchRadius in the room) on `planner`'s snapshot.
  std::optional<Path> exitPathOn(GridPlanner* planner, const Eigen::Vector2d& robot) const;
  /// Chooses the goal among the explorer's frontiers (after its nextGoal()): when `track`, the one
  /// the held goal belongs to, else the cheapest usable one inside the room. False when none.
  bool select(const Eigen::Vector2d& robot, bool track);

  RoomExplorerParams params_;
  OccupancyGrid grid_;
  FrontierExplorer explorer_;
  GridPlanner optimistic_planner_;  // pathTo(): Unknown cells traversable
  RoomStatus status_ = RoomStatus::Invalid;
  bool entered_ = false;

  Eigen::Vector2d door_xy_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d door_dir_ = Eigen::Vector2d::UnitX();  // unit, into the room
  double door_width_ = 0.0;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> openings_;
  std::vector<bool> opening_in_wall_;  // per openings_: seen as a gap in a wall
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> furniture_gaps_;  // opened (openFurnitureGaps)

  double entering_since_ = 0.0;   // s, the first nextGoal() after start()
  bool entering_clock_ = false;   // entering_since_ is set
  std::optional<Eigen::Vector2d> goal_;  // the held frontier goal
  double goal_since_ = 0.0;       // s, when it was issued
  int goals_issued_ = 0;
  Path goal_path_;
};

}  // namespace exploration
