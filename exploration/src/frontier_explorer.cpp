#include "exploration/frontier_explorer.h"

#include "core_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <queue>
#include <stdexcept>

namespace exploration {

namespace {

using core::fail;
using core::finite;

using core::kDx;
using core::kDy;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Frontiers

std::vector<Frontier> findFrontiers(const OccupancyGrid& grid, double min_size) {
  const int w = grid.width(), h = grid.height(), x0 = grid.minX(), y0 = grid.minY();
  const std::size_t n = grid.cellCount();
  std::vector<CellState> state(n);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) state[static_cast<std::size_t>(y) * w + x] = grid.cellState(x0 + x, y0 + y);

  // Open unknown: Unknown cells with no Occupied 8-neighbour. One touching an Occupied cell is the
  // unseen side of that obstacle (a wall's cells between two returns, the row the returns of a wall
  // on a cell boundary round into, conflicting evidence at a face), not space to explore.
  const auto openUnknown = [&](int x, int y) {
    if (state[static_cast<std::size_t>(y) * w + x] != CellState::Unknown) return false;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx >= 0 && ny >= 0 && nx < w && ny < h && state[static_cast<std::size_t>(ny) * w + nx] == CellState::Occupied)
        return false;
    }
    return true;
  };
  // 0: not a frontier cell, 1: a frontier cell not yet clustered, 2: clustered.
  std::vector<std::uint8_t> flag(n, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (state[i] != CellState::Free) continue;
      for (int k = 0; k < 4; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;  // the grid's border is no frontier
        if (openUnknown(nx, ny)) {
          flag[i] = 1;
          break;
        }
      }
    }
  }

  std::vector<Frontier> frontiers;
  std::vector<int> stack;
  const double res = grid.resolution();
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (flag[seed] != 1) continue;
    Frontier f;
    flag[seed] = 2;
    stack.assign(1, static_cast<int>(seed));
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      const int x = i % w, y = i / w;
      f.cells.push_back({x0 + x, y0 + y});
      sum += grid.cellCenter(x0 + x, y0 + y);
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const int ni = ny * w + nx;
        if (flag[ni] != 1) continue;
        flag[ni] = 2;
        stack.push_back(ni);
      }
    }
    f.size = static_cast<double>(f.cells.size()) * res;
    if (f.size < min_size - 1e-9) continue;
    f.centroid = sum / static_cast<double>(f.cells.size());
    frontiers.push_back(std::move(f));
  }
  return frontiers;
}

const char* toString(ExplorerStatus status) {
  switch (status) {
    case ExplorerStatus::Goal: return "Goal";
    case ExplorerStatus::Complete: return "Complete";
    case ExplorerStatus::Invalid: return "Invalid";
  }
  return "?";
}

bool FrontierExplorer::validate(const FrontierParams& p, std::string* error) {
  if (!(p.min_frontier_size >= 0.0) || !std::isfinite(p.min_frontier_size))
    return fail(error, "min_frontier_size must be >= 0");
  if (!(p.potential_scale >= 0.0) || !std::isfinite(p.potential_scale))
    return fail(error, "potential_scale must be >= 0");
  if (!(p.gain_scale >= 0.0) || !std::isfinite(p.gain_scale)) return fail(error, "gain_scale must be >= 0");
  if (!(p.goal_search_radius >= 0.0) || !std::isfinite(p.goal_search_radius))
    return fail(error, "goal_search_radius must be >= 0");
  return true;
}

FrontierExplorer::FrontierExplorer(const FrontierParams& params, const PlannerParams& planner_params)
    : params_(params), planner_(planner_params) {
  std::string why;
  if (!validate(params_, &why)) throw std::invalid_argument("FrontierExplorer: " + why);
}

void FrontierExplorer::blacklist(const Eigen::Vector2d& point, double radius) {
  if (!finite(point) || !(radius >= 0.0) || !std::isfinite(radius)) return;
  blacklist_.push_back({point, radius});
}

bool FrontierExplorer::isBlacklisted(const Eigen::Vector2d& p) const {
  for (const Disc& d : blacklist_)
    if ((p - d.center).squaredNorm() <= d.radius * d.radius) return true;
  return false;
}

void FrontierExplorer::chooseGoal(const OccupancyGrid& grid, Frontier* f) {
  // A breadth-first search from the frontier's cells through Free cells (the goal stays on the
  // frontier's side of walls, even unseen ones), up to goal_search_radius: among the reachable
  // traversable cells met, the one nearest the centroid (ties: the shorter path).
  const int w = grid.width(), h = grid.height(), x0 = grid.minX(), y0 = grid.minY();
  if (stamp_.size() != grid.cellCount()) {
    stamp_.assign(grid.cellCount(), 0);
    stamp_counter_ = 0;
  }
  if (++stamp_counter_ == 0) {  // wrapped: start over
    std::fill(stamp_.begin(), stamp_.end(), 0);
    stamp_counter_ = 1;
  }
  const int max_steps = static_cast<int>(std::ceil(params_.goal_search_radius / grid.resolution()));
  queue_.clear();
  for (const CellIndex& c : f->cells) {
    const int i = (c.y - y0) * w + (c.x - x0);
    stamp_[i] = stamp_counter_;
    queue_.emplace_back(i, 0);
  }
  double best_d2 = std::numeric_limits<double>::infinity(), best_path = best_d2;
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const auto [i, steps] = queue_[head];
    const int x = i % w, y = i / w;
    const double path = planner_.distance(x0 + x, y0 + y);
    // Reachable and traversable (not a cell of the start's escape from the inflation).
    if (path < std::numeric_limits<double>::infinity() && planner_.traversable(x0 + x, y0 + y)) {
      const double d2 = (grid.cellCenter(x0 + x, y0 + y) - f->centroid).squaredNorm();
      if (d2 < best_d2 - 1e-12 || (d2 <= best_d2 + 1e-12 && path < best_path)) {
        best_d2 = d2;
        best_path = path;
        f->goal = grid.cellCenter(x0 + x, y0 + y);
        f->path_length = path;
        f->reachable = true;
      }
    }
    if (steps >= max_steps) continue;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const int ni = ny * w + nx;
      if (stamp_[ni] == stamp_counter_ || grid.cellState(x0 + nx, y0 + ny) != CellState::Free) continue;
      stamp_[ni] = stamp_counter_;
      queue_.emplace_back(ni, steps + 1);
    }
  }
}

std::optional<Eigen::Vector2d> FrontierExplorer::nextGoal(const OccupancyGrid& grid, const Eigen::Vector2d& robot_xy) {
  frontiers_.clear();
  path_ = Path();
  status_ = ExplorerStatus::Invalid;
  if (!finite(robot_xy)) return std::nullopt;
  planner_.setMap(grid);
  if (!planner_.computeDistances(robot_xy)) return std::nullopt;

  frontiers_ = findFrontiers(grid, params_.min_frontier_size);
  for (Frontier& f : frontiers_) {
    chooseGoal(grid, &f);
    f.blacklisted = isBlacklisted(f.centroid) || (f.reachable && isBlacklisted(f.goal));
    if (f.reachable) f.cost = params_.potential_scale * f.path_length - params_.gain_scale * f.size;
  }
  const auto usable = [](const Frontier& f) { return f.reachable && !f.blacklisted; };
  std::stable_sort(frontiers_.begin(), frontiers_.end(), [&](const Frontier& a, const Frontier& b) {
    if (usable(a) != usable(b)) return usable(a);
    return a.cost < b.cost;
  });
  if (frontiers_.empty() || !usable(frontiers_.front())) {
    status_ = ExplorerStatus::Complete;
    return std::nullopt;
  }
  const Eigen::Vector2d goal = frontiers_.front().goal;
  if (auto path = planner_.pathTo(goal)) path_ = std::move(*path);
  status_ = ExplorerStatus::Goal;
  return goal;
}

}  // namespace exploration
