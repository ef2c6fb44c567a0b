#include "exploration/room_explorer.h"

#include "core_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace exploration {

using laser_features::Pose2D;

namespace {

using core::fail;
using core::finite;

bool finiteAtLeast(double v, double lo) { return std::isfinite(v) && v >= lo; }

const RoomExplorerParams& checked(const RoomExplorerParams& params) {
  std::string why;
  if (!RoomExplorer::validate(params, &why)) throw std::invalid_argument("RoomExplorer: " + why);
  return params;
}

// How far around the exit point pathToExit() looks for a traversable cell when the point itself is
// not (a narrow door near a corner puts it in the inflation of a wall).
constexpr double kExitSearchRadius = 0.5;  // m

}  // namespace

const char* toString(RoomStatus status) {
  switch (status) {
    case RoomStatus::Entering: return "Entering";
    case RoomStatus::Exploring: return "Exploring";
    case RoomStatus::Done: return "Done";
    case RoomStatus::Invalid: return "Invalid";
  }
  return "?";
}

bool RoomExplorer::validate(const RoomExplorerParams& p, std::string* error) {
  std::string why;
  if (!OccupancyGrid::validate(p.grid, &why)) {
    if (error) *error = "grid: " + why;
    return false;
  }
  if (!FrontierExplorer::validate(p.frontier, &why)) {
    if (error) *error = "frontier: " + why;
    return false;
  }
  if (!GridPlanner::validate(p.planner, &why)) {
    if (error) *error = "planner: " + why;
    return false;
  }
  if (!finiteAtLeast(p.max_extent, 0.0) || !(p.max_extent > 0.0)) return fail(error, "max_extent must be > 0");
  const double side = 2.0 * p.max_extent / p.grid.resolution + 2.0;  // cells, with the rounding at the edges
  if (!(side * side <= static_cast<double>(p.grid.max_cells)))
    return fail(error, "the room grid (2 max_extent / resolution)^2 exceeds grid.max_cells");
  if (!std::isfinite(p.entry_depth) || !(p.entry_depth > p.planner.robot_radius))
    return fail(error, "entry_depth must exceed planner.robot_radius (the body is inside when the door closes)");
  if (!finiteAtLeast(p.entry_goal_extra, 0.0)) return fail(error, "entry_goal_extra must be >= 0");
  if (!std::isfinite(p.exit_depth) || !(p.exit_depth > 0.0)) return fail(error, "exit_depth must be > 0");
  if (!(p.entry_depth + p.entry_goal_extra < p.max_extent) || !(p.exit_depth < p.max_extent))
    return fail(error, "the entering goal and the exit point must lie within max_extent");
  if (!finiteAtLeast(p.door_wall_extension, 0.0)) return fail(error, "door_wall_extension must be >= 0");
  if (!finiteAtLeast(p.opening_merge_distance, 0.0)) return fail(error, "opening_merge_distance must be >= 0");
  if (!std::isfinite(p.goal_reach_tolerance) || !(p.goal_reach_tolerance > 0.0))
    return fail(error, "goal_reach_tolerance must be > 0");
  if (!std::isfinite(p.max_goal_time) || !(p.max_goal_time > 0.0)) return fail(error, "max_goal_time must be > 0");
  if (!finiteAtLeast(p.blacklist_radius, 0.0)) return fail(error, "blacklist_radius must be >= 0");
  if (p.max_goals < 1) return fail(error, "max_goals must be >= 1");
  return true;
}

RoomExplorer::RoomExplorer(const RoomExplorerParams& params)
    : params_(checked(params)),
      grid_(params_.grid),
      explorer_(params_.frontier, params_.planner),
      optimistic_planner_([&] {
        PlannerParams p = params_.planner;
        p.allow_unknown = true;
        return p;
      }()) {}

bool RoomExplorer::start(const Pose2D& door, double door_width) {
  // Whatever happens, the previous room is gone.
  status_ = RoomStatus::Invalid;
  entered_ = false;
  openings_.clear();
  opening_in_wall_.clear();
  furniture_gaps_.clear();
  explorer_.clearBlacklist();
  goal_.reset();
  goal_path_ = Path();
  goals_issued_ = 0;
  entering_clock_ = false;
  grid_ = OccupancyGrid(params_.grid);
  if (!std::isfinite(door.x) || !std::isfinite(door.y) || !std::isfinite(door.theta) ||
      !std::isfinite(door_width) || !(door_width > 0.0) || !(std::abs(door.x) < 1e7) || !(std::abs(door.y) < 1e7))
    return false;
  door_xy_ = door.translation();
  door_dir_ = laser_features::unitVector(door.theta);
  door_width_ = door_width;
  const double e = params_.max_extent;
  try {
    grid_ = OccupancyGrid(params_.grid, GridBounds{door.x - e, door.y - e, door.x + e, door.y + e});
  } catch (const std::invalid_argument&) {  // a door too far from the origin for the cell indices
    grid_ = OccupancyGrid(params_.grid);
    return false;
  }
  status_ = RoomStatus::Entering;
  return true;
}

bool RoomExplorer::addScan(const Pose2D& sensor, const std::vector<float>& ranges, double angle_min,
                           double angle_increment, std::string* error) {
  if (status_ == RoomStatus::Invalid) return fail(error, "no room started");
  if (!grid_.insertScan(sensor, ranges, angle_min, angle_increment, error)) return false;
  drawVirtualWalls();
  return true;
}

bool RoomExplorer::blockOpening(const Eigen::Vector2d& left, const Eigen::Vector2d& right, bool in_wall) {
  if (status_ == RoomStatus::Invalid || !finite(left) || !finite(right) || !((right - left).norm() > 1e-6))
    return false;
  const Eigen::Vector2d centre = 0.5 * (left + right);
  const double merge = params_.opening_merge_distance;
  if ((centre - door_xy_).norm() < merge) return false;  // the entry door: its wall waits for the robot
  for (std::size_t i = 0; i < openings_.size(); ++i) {
    if ((centre - 0.5 * (openings_[i].first + openings_[i].second)).norm() >= merge) continue;
    if (in_wall) opening_in_wall_[i] = true;
    return false;
  }
  openings_.emplace_back(left, right);
  opening_in_wall_.push_back(in_wall);
  drawWall(left, right);
  return true;
}

std::size_t RoomExplorer::openFurnitureGaps() {
  const std::size_t before = furniture_gaps_.size();
  std::size_t kept = 0;
  for (std::size_t i = 0; i < openings_.size(); ++i) {
    if (!opening_in_wall_[i]) {
      // Free, as the scans saw the gap before its wall was drawn (a leg at its end is seen again by
      // the next scans; the controller keeps its distance from what the laser sees).
      drawWall(openings_[i].first, openings_[i].second, CellState::Free);
      furniture_gaps_.push_back(openings_[i]);
      continue;
    }
    openings_[kept] = openings_[i];
    opening_in_wall_[kept++] = true;
  }
  openings_.resize(kept);
  opening_in_wall_.resize(kept);
  drawVirtualWalls();
  return furniture_gaps_.size() - before;
}

void RoomExplorer::closeFurnitureGaps() {
  for (const auto& [a, b] : furniture_gaps_) {
    openings_.emplace_back(a, b);
    opening_in_wall_.push_back(false);
  }
  furniture_gaps_.clear();
  drawVirtualWalls();
}

Eigen::Vector2d RoomExplorer::exitPoint() const { return door_xy_ + params_.exit_depth * door_dir_; }

void RoomExplorer::drawWall(const Eigen::Vector2d& a0, const Eigen::Vector2d& b0, CellState state) {
  // The segment extended by door_wall_extension beyond each edge (into the jambs: the edges come
  // from a door detector, a few centimetres off), every cell whose centre lies within one cell of it:
  // 2 to 3 cells thick, so no 8-connected step (a frontier's goal search, the planner) crosses it.
  const Eigen::Vector2d u = (b0 - a0).normalized();
  const Eigen::Vector2d a = a0 - params_.door_wall_extension * u, b = b0 + params_.door_wall_extension * u;
  const double res = grid_.resolution(), r = res * (1.0 + 1e-9);
  const CellIndex lo = grid_.worldToCell(a.cwiseMin(b).array() - r), hi = grid_.worldToCell(a.cwiseMax(b).array() + r);
  const int x0 = std::max(lo.x, grid_.minX()), y0 = std::max(lo.y, grid_.minY());
  const int x1 = std::min(hi.x, grid_.minX() + grid_.width() - 1), y1 = std::min(hi.y, grid_.minY() + grid_.height() - 1);
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  for (int iy = y0; iy <= y1; ++iy) {
    for (int ix = x0; ix <= x1; ++ix) {
      const Eigen::Vector2d c = grid_.cellCenter(ix, iy);
      const double t = len2 > 0.0 ? std::clamp((c - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      if ((a + t * ab - c).squaredNorm() <= r * r) grid_.setCell(ix, iy, state);
    }
  }
}

void RoomExplorer::drawVirtualWalls() {
  // The entry door only once the robot is inside: it starts in the doorway, and a wall there would
  // enclose it (or leave it on the hallway side).
  if (entered_) {
    const Eigen::Vector2d lateral(-door_dir_.y(), door_dir_.x());
    drawWall(door_xy_ - 0.5 * door_width_ * lateral, door_xy_ + 0.5 * door_width_ * lateral);
  }
  for (const auto& [a, b] : openings_) drawWall(a, b);
}

std::optional<Eigen::Vector2d> RoomExplorer::nextGoal(const Eigen::Vector2d& robot, double now) {
  goal_path_ = Path();
  if (status_ == RoomStatus::Invalid || status_ == RoomStatus::Done) return std::nullopt;
  if (!finite(robot) || !std::isfinite(now)) return std::nullopt;

  if (status_ == RoomStatus::Entering) {
    if (!entering_clock_) {
      entering_since_ = now;
      entering_clock_ = true;
    }
    if (depth(robot) >= params_.entry_depth) {
      // Inside: close the door behind the robot (Tomatis et al.: the room is explored on its own,
      // the way out is the door it came in by).
      status_ = RoomStatus::Exploring;
      entered_ = true;
      drawVirtualWalls();
    } else if (now - entering_since_ > params_.max_goal_time) {
      status_ = RoomStatus::Done;  // the door cannot be passed: nothing to explore here
      return std::nullopt;
    } else {
      const Eigen::Vector2d goal = door_xy_ + (params_.entry_depth + params_.entry_goal_extra) * door_dir_;
      goal_path_.waypoints = {robot, goal};
      goal_path_.length = (goal - robot).norm();
      return goal;
    }
  }

  // Exploring. The held goal ends when reached or timed out (then its neighbourhood is given up).
  if (goal_) {
    if ((robot - *goal_).norm() <= params_.goal_reach_tolerance) {
      goal_.reset();
    } else if (now - goal_since_ > params_.max_goal_time) {
      explorer_.blacklist(*goal_, params_.blacklist_radius);
      goal_.reset();
    }
  }
  if (!goal_ && goals_issued_ >= params_.max_goals) {
    status_ = RoomStatus::Done;
    return std::nullopt;
  }

  explorer_.nextGoal(grid_, robot);  // all frontiers, costed; the choice is ours (inside the room)
  if (explorer_.status() == ExplorerStatus::Invalid) return std::nullopt;  // the robot is off the grid

  // The held goal follows its frontier (whose goal cell moves as the map grows); a frontier gone
  // (seen on the way) frees the robot for the next one.
  if (goal_ && !select(robot, true)) goal_.reset();
  if (!goal_) {
    if (goals_issued_ >= params_.max_goals || !select(robot, false)) {
      // No reachable frontier left inside the room: its walls are mapped (or the bound is hit).
      status_ = RoomStatus::Done;
      return std::nullopt;
    }
    goal_since_ = now;
    ++goals_issued_;
  }
  if (auto path = explorer_.planner().pathTo(*goal_)) goal_path_ = std::move(*path);
  return goal_;
}

bool RoomExplorer::select(const Eigen::Vector2d& robot, bool track) {
  const double track_radius = std::max(params_.frontier.goal_search_radius, params_.goal_reach_tolerance);
  double best = std::numeric_limits<double>::infinity();
  std::optional<Eigen::Vector2d> chosen;
  for (const Frontier& f : explorer_.frontiers()) {  // cheapest first, unusable ones last
    if (!f.reachable || f.blacklisted) break;
    // Never behind the entry door line (the hallway side), whatever the virtual wall does: it may
    // leak (a door narrower than reported, an opening nobody blocked), and the hallway is the
    // topological level's business, not this room's.
    if (!inRoom(f.centroid) || !inRoom(f.goal)) continue;
    if (track) {
      const double d = std::min((f.goal - *goal_).norm(), (f.centroid - *goal_).norm());
      if (d <= track_radius && (f.goal - *goal_).norm() < best) {
        best = (f.goal - *goal_).norm();
        chosen = f.goal;
      }
      continue;
    }
    // A goal where the robot already stands while its frontier is still there is unobservable from
    // there (beyond the laser's range, behind glass): given up, else it would be "reached" forever.
    if ((f.goal - robot).norm() <= params_.goal_reach_tolerance) {
      explorer_.blacklist(f.goal, params_.blacklist_radius);
      continue;
    }
    chosen = f.goal;
    break;
  }
  if (!chosen) return false;
  goal_ = *chosen;
  return true;
}

std::optional<Path> RoomExplorer::pathToExit(const Eigen::Vector2d& robot, const std::vector<Eigen::Vector2d>& seen) {
  if (status_ == RoomStatus::Invalid || !finite(robot)) return std::nullopt;
  GridPlanner& planner = explorer_.planner();
  planner.setMap(grid_);
  if (!seen.empty()) {
    planner.addObstacles(seen);
    if (std::optional<Path> path = exitPathOn(&planner, robot)) return path;
    // No way out keeps clear of what the scan sees (the robot among legs it drove in between,
    // under a table, which the controller lets it leave as it came; or the way blocked by what the
    // scan sees): the grid alone then.
    planner.setMap(grid_);
  }
  return exitPathOn(&planner, robot);
}

std::optional<Path> RoomExplorer::exitPathOn(GridPlanner* planner, const Eigen::Vector2d& robot) const {
  Eigen::Vector2d target = exitPoint();
  const CellIndex ec = grid_.worldToCell(target);
  if (!planner->traversable(ec.x, ec.y)) {
    const int reach = static_cast<int>(std::ceil(kExitSearchRadius / grid_.resolution()));
    double best = std::numeric_limits<double>::infinity();
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        if (!planner->traversable(ec.x + dx, ec.y + dy)) continue;
        const Eigen::Vector2d c = grid_.cellCenter(ec.x + dx, ec.y + dy);
        const double d = (c - exitPoint()).norm();
        if (d <= kExitSearchRadius && d < best && inRoom(c)) {
          best = d;
          target = c;
        }
      }
    }
    if (!std::isfinite(best)) return std::nullopt;
  }
  return planner->plan(robot, target);
}

std::optional<Path> RoomExplorer::pathTo(const Eigen::Vector2d& robot, const Eigen::Vector2d& goal,
                                         const std::vector<Eigen::Vector2d>& seen) {
  if (status_ == RoomStatus::Invalid || !finite(robot) || !finite(goal)) return std::nullopt;
  optimistic_planner_.setMap(grid_);
  if (!seen.empty()) {
    optimistic_planner_.addObstacles(seen);
    if (std::optional<Path> path = optimistic_planner_.plan(robot, goal)) return path;
    optimistic_planner_.setMap(grid_);  // as pathToExit: the grid alone where the scan leaves no way
  }
  return optimistic_planner_.plan(robot, goal);
}

std::vector<std::uint8_t> RoomExplorer::roomCells() const {
  std::vector<std::uint8_t> seen;
  if (status_ == RoomStatus::Invalid || grid_.cellCount() == 0) return seen;
  // The seed: the exit point's cell, or the Free cell nearest to it within 1 m inside the room.
  const double res = grid_.resolution();
  const CellIndex ec = grid_.worldToCell(exitPoint());
  const int reach = static_cast<int>(std::ceil(1.0 / res));
  std::optional<CellIndex> seed;
  double best = std::numeric_limits<double>::infinity();
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const CellIndex c{ec.x + dx, ec.y + dy};
      if (grid_.cellState(c) != CellState::Free || !inRoom(grid_.cellCenter(c))) continue;
      const double d = std::hypot(dx, dy);
      if (d < best) {
        best = d;
        seed = c;
      }
    }
  }
  if (!seed) return seen;
  // 4-connected flood fill through the Free cells on the room's side of the entry line.
  seen.assign(grid_.cellCount(), 0);
  std::vector<CellIndex> stack{*seed};
  seen[grid_.index(seed->x, seed->y)] = 1;
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  while (!stack.empty()) {
    const CellIndex c = stack.back();
    stack.pop_back();
    for (int k = 0; k < 4; ++k) {
      const int x = c.x + dx[k], y = c.y + dy[k];
      if (!grid_.contains(x, y)) continue;
      std::uint8_t& s = seen[grid_.index(x, y)];
      if (s || grid_.cellState(x, y) != CellState::Free || !inRoom(grid_.cellCenter(x, y))) continue;
      s = 1;
      stack.push_back({x, y});
    }
  }
  return seen;
}

double RoomExplorer::freeArea() const {
  const std::vector<std::uint8_t> cells = roomCells();
  const double res = grid_.resolution();
  return static_cast<double>(std::count(cells.begin(), cells.end(), std::uint8_t(1))) * res * res;
}

bool RoomExtent::contains(const Eigen::Vector2d& p, double margin) const {
  const Eigen::Vector2d dir = laser_features::unitVector(door.theta), across(-dir.y(), dir.x());
  const Eigen::Vector2d r = p - Eigen::Vector2d(door.x, door.y);
  const double a = r.dot(dir), b = r.dot(across);
  return a > depth_min + margin && a < depth_max - margin && b > across_min + margin && b < across_max - margin;
}

std::optional<RoomExtent> RoomExplorer::extent(const std::vector<std::uint8_t>& cells) const {
  if (cells.empty()) return std::nullopt;
  const Eigen::Vector2d across(-door_dir_.y(), door_dir_.x());
  RoomExtent e;
  e.door = laser_features::Pose2D{door_xy_.x(), door_xy_.y(), std::atan2(door_dir_.y(), door_dir_.x())};
  e.depth_min = e.across_min = std::numeric_limits<double>::infinity();
  e.depth_max = e.across_max = -e.depth_min;
  for (int y = grid_.minY(); y < grid_.minY() + grid_.height(); ++y) {
    for (int x = grid_.minX(); x < grid_.minX() + grid_.width(); ++x) {
      if (!cells[grid_.index(x, y)]) continue;
      const Eigen::Vector2d p = grid_.cellCenter(x, y) - door_xy_;
      e.depth_min = std::min(e.depth_min, p.dot(door_dir_));
      e.depth_max = std::max(e.depth_max, p.dot(door_dir_));
      e.across_min = std::min(e.across_min, p.dot(across));
      e.across_max = std::max(e.across_max, p.dot(across));
    }
  }
  return e;
}

std::optional<RoomExtent> RoomExplorer::extent() const { return extent(roomCells()); }

bool RoomExplorer::leadsOutOfRoom(const Eigen::Vector2d& centre, double into, double distance) const {
  const std::vector<std::uint8_t> cells = roomCells();
  const std::optional<RoomExtent> room = extent(cells);
  if (!room) return false;
  const Eigen::Vector2d behind = centre - distance * Eigen::Vector2d(std::cos(into), std::sin(into));
  const double r = params_.planner.robot_radius;
  // Beyond the room's extent by a robot radius (a pocket between furniture and a wall, closed by
  // virtual walls of its own, lies within it).
  if (room->contains(behind, -r)) return false;
  // The cells within a robot radius of it: some seen Free (through the opening), none of the room's
  // area (reached around furniture, the gap is no door).
  const CellIndex c0 = grid_.worldToCell(behind);
  const int reach = static_cast<int>(std::ceil(r / grid_.resolution()));
  bool free_seen = false;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const int x = c0.x + dx, y = c0.y + dy;
      if (!grid_.contains(x, y) || (grid_.cellCenter(x, y) - behind).norm() > r) continue;
      if (grid_.cellState(x, y) != CellState::Free) continue;
      free_seen = true;
    }
  }
  return free_seen;
}

}  // namespace exploration
